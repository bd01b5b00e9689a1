/* The sun's ground truth against another renderer (docs/groundtruth.md):
 * Blender's Cycles renders sun_parallel_planes' planes under its sun lamp
 * at 0.53 and 5 degrees, direct light only, on white Lambert surfaces, with
 * the plate and without it (tests/blender_sun.py); the ratio is Cycles'
 * V_gt_weighted, compared pixel by pixel with ours over the penumbra band.
 * Skipped (exit 77) where Blender is not installed: tools/setup does not
 * install it (a 300 MB package for one check); tools/blender-check records
 * what this prints into results/blender/ for the docs.
 *
 * Tolerances: Cycles' sampler (scrambled Sobol in Blender 3.4) is
 * stratified like ours, so each estimate's error over a chord is about
 * sqrt(n / 6) / N = 0.0023 for N = n x n = 1024 samples, both together
 * 0.0033: the rms difference must be within 0.006 (a sun 10 % wider in
 * Blender gives 0.023). The mean difference, the bias of one against the
 * other, within 0.001: 25 times its standard error over the ~5000 band
 * pixels (0.0033 / sqrt(5000) = 5e-5), leaving room for what the two do
 * differently and should not matter (Cycles' offset of its shadow rays,
 * its pixel filter 0.01 of a pixel wide); a wrong width, which moves the
 * band symmetrically about the edge, is the rms's to catch. Where the
 * closed form says fully lit, the two must agree within 0.005 (Cycles'
 * samples of cos theta over the disk vary by 1e-3 of it at 5 degrees). */
#include "check.h"
#include "parallel_planes.h"
#include "run_cmd.h"
#include "scene/light_frustum.h"
#include "truth/groundtruth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define IMG 96

static char dir[] = "/tmp/sb_test_blender_XXXXXX";

static void compare(double deg)
{
    char *scene_path = util_printf("%s/sun_%g.gltf", dir, deg), *ratio_path = util_printf("%s/ratio_%g.f32", dir, deg);
    write_sun_parallel_planes(scene_path, deg);
    struct scene s;
    struct light_frustum f;
    CHECK(scene_load(scene_path, &s) == 0 && light_frustum_fit(&s, 1.0f, &f) == 0, "loading %s", scene_path);
    struct gt_image g;
    CHECK(gt_render(&s, &f, &(struct gt_desc){.width = IMG, .height = IMG, .samples = 1024, .quiet = true}, &g) == 0,
          "the ground truth");

    char *cmd = util_printf("blender -b --factory-startup --python-exit-code 1 -P '%s/tests/blender_sun.py' -- '%s' %g "
                            "%d %d 1024 '%s'", SB_SOURCE_DIR, scene_path, deg, IMG, IMG, ratio_path);
    struct strbuf err = {0}, out = {0};
    const int status = run_cmd(cmd, &err, &out);
    CHECK(status == 0, "blender: exit %d: %s", status, err.data ? err.data : "");
    char *data = NULL;
    size_t size = 0;
    CHECK(status != 0 || (util_read_file(ratio_path, &data, &size) == 0 && size == sizeof(float) * IMG * IMG),
          "Blender's ratio %s: %zu bytes", ratio_path, size);
    if (data && size == sizeof(float) * IMG * IMG) {
        const float *cycles = (const float *)data;
        const double tan_a = tan(0.5 * deg * M_PI / 180);
        const struct scene_camera *c = &s.camera;
        double sum = 0, sum2 = 0, lit_worst = 0;
        long band = 0, lit = 0;
        for (int i = 0; i < IMG * IMG; i++) {
            if (g.mask[i] < 0.5f || cycles[i] < 0)
                continue;
            const struct vec3 p = pixel_hit(c, i, IMG, IMG, g.distance[i]);
            const double chord = -p.x / (PP_H_BLOCK * tan_a);
            const double e = (double)cycles[i] - (double)g.v_weighted[i];
            if (fabs(chord) < 1) {
                sum += e, sum2 += e * e, band++;
            } else if (chord <= -1) {
                lit_worst = fmax(lit_worst, fabs(e)), lit++;
            }
        }
        const double mean = band ? sum / (double)band : NAN, rms = band ? sqrt(sum2 / (double)band) : NAN;
        printf("sun %g deg, %dx%d, 1024 samples a pixel each: Cycles - shadowbench V_gt_weighted over %ld penumbra-band "
               "pixels: mean %+.4f, rms %.4f; over %ld lit pixels: largest |difference| %.4f\n", deg, IMG, IMG, band,
               mean, rms, lit, lit_worst);
        CHECK(band > 2000 && lit > 100, "sun %g deg: %ld band and %ld lit pixels compared", deg, band, lit);
        CHECK(fabs(mean) <= 0.001, "sun %g deg: Cycles and the ground truth differ by %+.4f on average", deg, mean);
        CHECK(rms <= 0.006, "sun %g deg: rms difference %.4f", deg, rms);
        CHECK(lit_worst <= 0.005, "sun %g deg: lit pixels differ by up to %.4f", deg, lit_worst);
    }
    free(data), free(cmd);
    strbuf_free(&err), strbuf_free(&out);
    gt_image_free(&g);
    scene_free(&s);
    free(scene_path), free(ratio_path);
}

int main(void)
{
    if (system("command -v blender >/dev/null 2>&1") != 0) {
        printf("skipped: Blender is not installed (apt-get install blender to compare with Cycles)\n");
        return 77;
    }
    if (!mkdtemp(dir))
        return 1;
    compare(SCENE_SUN_DEG);
    compare(5.0);
    gt_shutdown();
    char *rm = util_printf("rm -rf '%s'", dir);
    if (!check_failures && system(rm) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
    free(rm);
    return check_finish();
}
