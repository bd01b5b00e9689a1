/* Protects the ground truth (DESIGN.md §6) against closed forms.
 *
 * Parallel planes: a light of width w at height H faces down onto a receiver
 * at y = 0; an occluder half-plane (x < 0) at y = h_b has its straight edge
 * along z, parallel to the receiver. With d_b = H - h_b (light to blocker) and
 * d_r = H (light to receiver), a receiver point at x = s sees the part of the
 * light with x_l >= c, c = -s * d_b / (d_r - d_b). So
 *   rect:  V(s) = clamp(0.5 + s / W, 0, 1),  W = w (d_r - d_b) / d_b
 *   disk:  V(s) = fraction of the disk beyond the chord at c (circular segment).
 * Also: same seed -> same image; the error falls from N to 4N; the two-seed
 * noise-floor estimate matches the true error. */
#include "check.h"
#include "parallel_planes.h"
#include "base/util.h"
#include "cli/catalog.h"
#include "scene/light_frustum.h"
#include "truth/groundtruth.h"

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define H_LIGHT PP_H_LIGHT
#define H_BLOCK PP_H_BLOCK
#define LIGHT_W 1.0f  /* the shipped parallel_planes scenes' */
#define IMG 128

static char tmpdir[] = "/tmp/sb_test_gt_XXXXXX";

static double expected_v(double s, bool disk)
{
    const double d_b = H_LIGHT - H_BLOCK, d_r = H_LIGHT;
    if (!disk) {
        double W = LIGHT_W * (d_r - d_b) / d_b, v = 0.5 + s / W;
        return v < 0 ? 0 : v > 1 ? 1 : v;
    }
    double R = 0.5 * LIGHT_W, c = -s * d_b / (d_r - d_b);
    if (c >= R)
        return 0;
    if (c <= -R)
        return 1;
    double a = fabs(c), seg = R * R * acos(a / R) - a * sqrt(R * R - a * a);
    double f = seg / (M_PI * R * R);  /* part beyond |c| */
    return c >= 0 ? f : 1 - f;
}

struct profile_error { double rms, max; long pixels; };

/* Error of V_gt against the closed form over receiver pixels (y ~ 0, within
 * |z| < 1 where the occluder is effectively infinite). */
static struct profile_error profile_error(const struct scene *s, const struct gt_image *g, bool disk,
                                          float *in_profile)
{
    const struct scene_camera *c = &s->camera;
    struct profile_error e = {0};
    double sum = 0;
    for (int y = 0; y < g->height; y++)
        for (int x = 0; x < g->width; x++) {
            int i = y * g->width + x;
            in_profile[i] = 0.0f;
            if (g->mask[i] < 0.5f)
                continue;
            float t = tanf(0.5f * c->yfov_rad);
            float sx = (2.0f * ((float)x + 0.5f) / (float)g->width - 1.0f) * t;
            float sy = (1.0f - 2.0f * ((float)y + 0.5f) / (float)g->height) * t;
            struct vec3 d = v3_normalize(v3_add(v3_add(v3_scale(c->x, sx), v3_scale(c->y, sy)),
                                                v3_scale(c->z, -1.0f)));
            struct vec3 p = v3_add(c->pos, v3_scale(d, g->distance[i]));
            if (fabsf(p.y) > 1e-3f || fabsf(p.z) > 1.0f)
                continue;
            in_profile[i] = 1.0f;
            double err = g->v[i] - expected_v(p.x, disk);
            sum += err * err;
            e.max = fmax(e.max, fabs(err));
            e.pixels++;
        }
    e.rms = e.pixels ? sqrt(sum / (double)e.pixels) : INFINITY;
    return e;
}

static void check_closed_form(bool disk)
{
    /* The shipped scenes themselves (light width LIGHT_W). */
    const char *shape = disk ? "disk" : "rect";
    char *path = catalog_resolve(disk ? "parallel_planes_disk" : "parallel_planes");
    struct scene s;
    struct light_frustum f;
    CHECK(scene_load(path, &s) == 0 && light_frustum_fit(&s, &f) == 0, "loading %s", path);

    struct gt_image lo, hi, lo2;
    gt_render(&s, &f, &(struct gt_desc){IMG, IMG, 256, 1}, &lo);
    gt_render(&s, &f, &(struct gt_desc){IMG, IMG, 1024, 1}, &hi);
    gt_render(&s, &f, &(struct gt_desc){IMG, IMG, 256, 2}, &lo2);
    static float in_profile[IMG * IMG];
    struct profile_error e_hi = profile_error(&s, &hi, disk, in_profile);
    struct profile_error e_lo = profile_error(&s, &lo, disk, in_profile);
    printf("%s light: %ld penumbra-profile pixels; rms error %.5f (max %.4f) at N=256, %.5f (max "
           "%.4f) at N=1024\n", shape, e_hi.pixels, e_lo.rms, e_lo.max, e_hi.rms, e_hi.max);
    CHECK(e_hi.pixels > 2000, "%s: too few receiver pixels in view (%ld)", shape, e_hi.pixels);
    /* Stratified n x n sampling of a light cut by one straight edge: only the
     * ~n strata the edge crosses are uncertain, each a Bernoulli of variance
     * <= 1/4, so sigma(V) <= sqrt(n / 4) / N = 0.0028 at N = 1024 (n = 32).
     * rms must stay within 1.5 sigma (bias would show as more), the max over
     * ~10^4 pixels within 8 sigma. */
    CHECK(e_hi.rms <= 0.0042, "%s: rms %.5f against the closed form", shape, e_hi.rms);
    CHECK(e_hi.max <= 0.0225, "%s: max %.4f against the closed form", shape, e_hi.max);
    /* N -> 4N: sigma ~ N^(-3/4) for an edge, a factor 2.8; demand at least 1.7. */
    CHECK(e_hi.rms < e_lo.rms / 1.7, "%s: error did not fall from N=256 (%.5f) to 1024 (%.5f)",
          shape, e_lo.rms, e_hi.rms);
    /* The noise floor from two seeds (rms difference / sqrt 2) must estimate
     * the true error of one image over the same pixels: within a factor 1.25
     * (the estimator is unbiased; ~8000 pixels make its spread a few %). */
    double floor = gt_noise_floor(lo.v, lo2.v, in_profile, IMG * IMG);
    printf("%s light: noise floor estimate at N=256 %.5f (true error %.5f)\n", shape, floor, e_lo.rms);
    CHECK(floor > e_lo.rms / 1.25 && floor < e_lo.rms * 1.25,
          "%s: noise floor %.5f does not estimate the true error %.5f", shape, floor, e_lo.rms);

    gt_image_free(&lo), gt_image_free(&hi), gt_image_free(&lo2);
    scene_free(&s);
    free(path);
}

static void check_determinism(void)
{
    char *path = util_printf("%s/det.gltf", tmpdir);
    write_parallel_planes(path, LIGHT_W, false);
    struct scene s;
    struct light_frustum f;
    CHECK(scene_load(path, &s) == 0 && light_frustum_fit(&s, &f) == 0, "loading %s", path);
    struct gt_image a, b, c;
    gt_render(&s, &f, &(struct gt_desc){64, 48, 64, 7}, &a);
    gt_render(&s, &f, &(struct gt_desc){64, 48, 64, 7}, &b);
    gt_render(&s, &f, &(struct gt_desc){64, 48, 64, 8}, &c);
    size_t bytes = sizeof(float) * 64 * 48;
    CHECK(memcmp(a.v, b.v, bytes) == 0 && memcmp(a.v_weighted, b.v_weighted, bytes) == 0 &&
              memcmp(a.mask, b.mask, bytes) == 0,
          "same seed must give the same image, whatever the thread schedule");
    CHECK(memcmp(a.v, c.v, bytes) != 0, "another seed must give another sample pattern");
    gt_image_free(&a), gt_image_free(&b), gt_image_free(&c);
    scene_free(&s);
    unlink(path);
    free(path);
}

int main(void)
{
    if (!mkdtemp(tmpdir))
        return 1;
    check_closed_form(false);
    check_closed_form(true);
    check_determinism();
    gt_shutdown();
    rmdir(tmpdir);
    return check_finish();
}
