/* Scenes as users' tools write them (docs/scene-format.md): shipped scenes
 * passed through glTF Transform's command line (npm @gltf-transform/cli,
 * pinned by tools/gltf-transform/package-lock.json, installed by
 * tools/setup) quantized (KHR_mesh_quantization), compressed with
 * meshoptimizer (EXT_meshopt_compression, over quantized data) and with
 * Draco (KHR_draco_mesh_compression), as .gltf and as .glb, load as the
 * originals and score like them. The scenes: three parts under an area
 * light, the sun's pole, the 70 k-triangle bunny.
 *
 * Geometry, where the decoding is checked: each encoding rounds a mesh's
 * positions to 14 bits of its own bounding box (glTF Transform's default):
 * the box's largest half-side h maps to 8191, rounded, and the 14 bits are
 * replicated into a 16-bit integer that the decoder divides by 32767, which
 * adds up to 2.3e-5 h; so a vertex moves by at most h (0.5 / 8191 +
 * 2.3e-5) (0.25 mm on sun_contact's 6-unit box). The decoded scene must
 * have the original's triangles, its bounds within that on each axis, its
 * surface area within 0.1 % (rounding moves it by
 * about a step over a mesh's size, 1e-4 here), and the camera and light
 * unchanged. A wrong normalisation or a lost node transform moves the
 * bounds by whole units; a wrong index buffer changes the area.
 *
 * Metrics (hard and pcss, 128², 256 ground-truth samples, the same seed):
 * what that rounding does to them, measured here, is at most 0.002 for the
 * means over every pixel (rmse, mae, bias, shaded_rmse) and the shares
 * (leak, dark), required within 0.003; penumbra_rmse, over the band's few
 * pixels where a sub-millimetre move flips a map texel's coverage near an
 * edge (sun_contact's penumbra is under a millimetre at the pole's foot),
 * moved by 0.0037, required within 0.006. p99_abs and max_abs, quantiles of
 * a few discrete error levels that jump when a handful of pixels cross, are
 * not compared. */
#include "check.h"
#include "run_cmd.h"
#include "scene/scene.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

static const char *sb, *cli;
static char dir[] = "/tmp/sb_test_compressed_XXXXXX";

static double surface_area(const struct scene *s)
{
    double a = 0;
    for (size_t t = 0; t < s->triangle_count; t++) {
        const float *p[3];
        for (int k = 0; k < 3; k++)
            p[k] = &s->positions[3 * s->indices[3 * t + k]];
        const struct vec3 u = v3(p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]);
        const struct vec3 w = v3(p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]);
        a += 0.5 * v3_length(v3_cross(u, w));
    }
    return a;
}

/* The most a vertex moves (above) for the scene's whole box, which holds
 * each mesh's own. */
static double rounding(const struct scene *s)
{
    const struct vec3 d = v3_sub(s->bounds_max, s->bounds_min);
    return 0.5 * fmax(d.x, fmax(d.y, d.z)) * (0.5 / 8191 + 2.3e-5);
}

static void same_geometry(const char *what, const struct scene *a, const struct scene *b)
{
    const double h = rounding(a) + 1e-6;  /* and float rounding of the node transforms */
    const float lo[3] = {a->bounds_min.x, a->bounds_min.y, a->bounds_min.z}, hi[3] = {a->bounds_max.x, a->bounds_max.y,
                                                                                      a->bounds_max.z};
    const float blo[3] = {b->bounds_min.x, b->bounds_min.y, b->bounds_min.z}, bhi[3] = {b->bounds_max.x, b->bounds_max.y,
                                                                                        b->bounds_max.z};
    double worst = 0;
    for (int k = 0; k < 3; k++)
        worst = fmax(worst, fmax(fabs(lo[k] - blo[k]), fabs(hi[k] - bhi[k])));
    const double area_a = surface_area(a), area_b = surface_area(b);
    CHECK(a->triangle_count == b->triangle_count, "%s: %zu triangles, the original %zu", what, b->triangle_count,
          a->triangle_count);
    CHECK(worst <= h, "%s: bounds moved by %g, more than the rounding allows (%g)", what, worst, h);
    CHECK(fabs(area_b / area_a - 1) < 1e-3, "%s: surface area %g, the original %g", what, area_b, area_a);
    CHECK(v3_length(v3_sub(a->camera.pos, b->camera.pos)) < 1e-5f && fabsf(a->camera.yfov_rad - b->camera.yfov_rad) < 1e-6f,
          "%s: the camera moved", what);
    CHECK(a->light.shape == b->light.shape && v3_length(v3_sub(a->light.z, b->light.z)) < 1e-5f &&
              fabsf(a->light.half_angle - b->light.half_angle) < 1e-7f && fabsf(a->light.width - b->light.width) < 1e-6f,
          "%s: the light changed", what);
}

/* The metrics of hard and pcss on scene: 2 cells x METRICS values (NAN on failure). */
#define METRIC_KEYS 8
static const char *const keys[METRIC_KEYS] = {"rmse", "mae", "bias", "shaded_rmse", "leak_fraction", "dark_fraction",
                                              "penumbra_rmse", "gt_noise_rmse"};
static const double tolerance[METRIC_KEYS] = {0.003, 0.003, 0.003, 0.003, 0.003, 0.003, 0.006, 0.003};

static void score(const char *scene, const char *out, double v[2][METRIC_KEYS])
{
    char *cmd = util_printf("%s run --scene '%s' --technique hard,pcss --settings default --width 128 --height 128 "
                            "--gt-samples 256 --frames 1 --no-cache -q --out '%s'", sb, scene, out);
    struct strbuf err = {0};
    const int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0, "%s: exit %d: %s", scene, status, err.data ? err.data : "");
    char *path = util_printf("%s/matrix.json", out), *text = NULL;
    size_t size;
    cJSON *m = status == 0 && util_read_file(path, &text, &size) == 0 ? cJSON_Parse(text) : NULL;
    for (int c = 0; c < 2; c++)
        for (int k = 0; k < METRIC_KEYS; k++)
            v[c][k] = cJSON_GetNumberValue(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(m, "cells"), c),
                                                               keys[k]));
    cJSON_Delete(m);
    free(text), free(path), free(cmd);
    strbuf_free(&err);
}

int main(int argc, char **argv)
{
    if (argc < 2 || !mkdtemp(dir))
        return 1;
    sb = argv[1];
    cli = SB_SOURCE_DIR "/tools/gltf-transform/node_modules/.bin/gltf-transform";
    CHECK(access(cli, X_OK) == 0, "%s: not installed (tools/setup runs npm ci in tools/gltf-transform)", cli);
    static const char *const scenes[] = {"floating_box_sphere", "sun_contact", "stanford_bunny"};
    static const char *const encodings[][2] = {{"quantize", "KHR_mesh_quantization"},
                                               {"meshopt", "EXT_meshopt_compression"},
                                               {"draco", "KHR_draco_mesh_compression"}};
    for (int si = 0; si < 3 && access(cli, X_OK) == 0; si++) {
        char *original = util_printf("%s/scenes/%s.gltf", SB_SOURCE_DIR, scenes[si]);
        struct scene a;
        CHECK(scene_load(original, &a) == 0, "loading %s", original);
        char *out = util_printf("%s/%s", dir, scenes[si]);
        double want[2][METRIC_KEYS];
        score(original, out, want);
        free(out);
        for (int e = 0; e < 3; e++)
            for (int glb = 0; glb < 2; glb++) {
                char *file = util_printf("%s/%s_%s.%s", dir, scenes[si], encodings[e][0], glb ? "glb" : "gltf");
                char *what = util_printf("%s as %s %s", scenes[si], encodings[e][0], glb ? "GLB" : "glTF");
                char *cmd = util_printf("'%s' %s '%s' '%s' >/dev/null 2>&1", cli, encodings[e][0], original, file);
                CHECK(system(cmd) == 0, "%s: gltf-transform failed", what);
                char *text = NULL;
                size_t size = 0;
                CHECK(util_read_file(file, &text, &size) == 0 && memmem(text, size, encodings[e][1], strlen(encodings[e][1])),
                      "%s: does not use %s", what, encodings[e][1]);
                free(text);
                struct scene b;
                if (scene_load(file, &b) == 0) {
                    same_geometry(what, &a, &b);
                    scene_free(&b);
                } else {
                    CHECK(false, "%s: does not load", what);
                }
                char *out_b = util_printf("%s/%s_%s_%d", dir, scenes[si], encodings[e][0], glb);
                double got[2][METRIC_KEYS];
                score(file, out_b, got);
                double worst = 0;
                for (int c = 0; c < 2; c++)
                    for (int k = 0; k < METRIC_KEYS; k++) {
                        const double d = fabs(got[c][k] - want[c][k]);
                        CHECK(d <= tolerance[k], "%s: %s %s moved by %.4f (%.4f -> %.4f), over %g", what,
                              c ? "pcss" : "hard", keys[k], d, want[c][k], got[c][k], tolerance[k]);
                        worst = fmax(worst, d / tolerance[k]);
                    }
                printf("%s: loads, the geometry within its rounding, metrics within %.0f %% of their tolerances\n", what,
                       100 * worst);
                free(out_b), free(cmd), free(what), free(file);
            }
        scene_free(&a);
        free(original);
    }
    char *rm = util_printf("rm -rf '%s'", dir);
    if (!check_failures && system(rm) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    free(rm);
    return check_finish();
}
