/* The counted cost and the screen-space stages (docs/metrics.md,
 * docs/techniques.md), where each is exact or measurable:
 *   - fetch counts equal hand counts: on parallel_planes every pixel is
 *     covered and inside the map, so hard is 1 fetch a pixel, pcf its
 *     sample count (with hardware_2x2 too: one comparison a tap), savsm
 *     16 (a box from 16 SAT values); pcss is its search taps everywhere
 *     plus its filter taps where it ran the filter, so its count lies
 *     below the count without early-outs (B + F) by exactly the skipped
 *     filter taps, F (1 - expensive_fraction); and a preparing product
 *     counts its texels (prep_texels), the depth map alone none;
 *   - the penumbra mask is conservative on the closed form: it skips no
 *     pixel pcss runs its full filter on (expensive_fraction unchanged,
 *     the picture unchanged) while saving fetches; without its dilation
 *     it skips more; its distance-dependent dilation (mask_dilate_world)
 *     is one block where the world radius is below a block, the most
 *     blocks where it is far above, and between them in between;
 *   - early bail saves fetches and costs accuracy, reported
 *     (misclassified_fraction);
 *   - the bilateral denoiser keeps a depth step sharp where a plain blur
 *     of the same radius (a world sigma far beyond the scene) does not: on
 *     overlapping_occluders the plain blur lights the true umbra next to
 *     a lit surface nearer the camera (leak_fraction), the bilateral one
 *     lights none; its normal weight changes nothing on flat receivers
 *     and blurs less across the bunny's folds (fewer pixels too dark). */
#include "check.h"
#include "run_cmd.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

static const char *sb;
static char dir[] = "/tmp/sb_test_stages_XXXXXX";

/* Runs `args` into <dir>/<name>; returns its matrix.json (or NULL). */
static cJSON *run_cells(const char *name, const char *args)
{
    char *out = util_printf("%s/%s", dir, name);
    char *cmd = util_printf("%s run %s --settings default --frames 1 --warmup 0 --no-cache -q --width 128 "
                            "--height 128 --gt-samples 256 --out %s", sb, args, out);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0, "%s: exit %d: %s", name, status, err.data ? err.data : "");
    char *path = util_printf("%s/matrix.json", out), *text = NULL;
    size_t size;
    cJSON *m = util_read_file(path, &text, &size) == 0 ? cJSON_Parse(text) : NULL;
    CHECK(m, "%s: %s cannot be read", name, path);
    free(text), free(path), free(cmd), free(out);
    strbuf_free(&err);
    return m;
}

/* Metric `key` of the cell named `cell` (as run names it), or NAN. */
static double metric(const cJSON *m, const char *cell, const char *key)
{
    const cJSON *c;
    cJSON_ArrayForEach(c, cJSON_GetObjectItem(m, "cells")) {
        const char *name = cJSON_GetStringValue(cJSON_GetObjectItem(c, "cell"));
        if (name && strcmp(name, cell) == 0) {
            const cJSON *v = cJSON_GetObjectItem(c, key);
            return cJSON_IsNumber(v) ? v->valuedouble : NAN;
        }
    }
    CHECK(false, "no cell %s", cell);
    return NAN;
}

static void fetch_counts(void)
{
    cJSON *m = run_cells("counts", "--scene parallel_planes --technique hard,pcf,savsm,pcss "
                                   "--sweep pcf.samples=16,64 --sweep pcf.hardware_2x2=false,true");
    /* sums of small integers in float: exact */
    CHECK(metric(m, "hard", "fetches_per_pixel") == 1.0, "hard: %g fetches a pixel, not 1",
          metric(m, "hard", "fetches_per_pixel"));
    const char *pcf[] = {"pcf@samples=16,hardware_2x2=false", "pcf@samples=64,hardware_2x2=false",
                         "pcf@samples=16,hardware_2x2=true", "pcf@samples=64,hardware_2x2=true"};
    const double taps[] = {16, 64, 16, 64};
    for (int i = 0; i < 4; i++) {
        CHECK(metric(m, pcf[i], "fetches_per_pixel") == taps[i], "%s: %g fetches a pixel, not %g", pcf[i],
              metric(m, pcf[i], "fetches_per_pixel"), taps[i]);
        CHECK(metric(m, pcf[i], "expensive_fraction") == 1.0, "%s has no early-out", pcf[i]);
        CHECK(isnan(metric(m, pcf[i], "misclassified_fraction")), "%s decides no pixel early", pcf[i]);
    }
    CHECK(metric(m, "savsm", "fetches_per_pixel") == 16.0, "savsm: %g fetches a pixel, not 16",
          metric(m, "savsm", "fetches_per_pixel"));
    CHECK(metric(m, "savsm", "prep_texels") > 0 && metric(m, "hard", "prep_texels") == 0,
          "prep_texels: savsm's table counts (%g), the depth map alone does not (%g)",
          metric(m, "savsm", "prep_texels"), metric(m, "hard", "prep_texels"));
    /* pcss 32 + 32: the search everywhere, the filter where it ran */
    const double f = metric(m, "pcss", "fetches_per_pixel"), x = metric(m, "pcss", "expensive_fraction");
    CHECK(x > 0.2 && x < 0.9, "pcss: the closed form has lit, umbra and penumbra (expensive_fraction %g)", x);
    CHECK(fabs(f - (32 + 32 * x)) < 1e-9 * f, "pcss: %.9g fetches a pixel, hand count 32 + 32 x %.9g = %.9g", f, x,
          32 + 32 * x);
    CHECK(fabs((64 - f) - 32 * (1 - x)) < 1e-9 * f, "pcss: below 64 by the skipped filter taps");
    cJSON_Delete(m);
}

static void penumbra_mask(void)
{
    cJSON *m = run_cells("mask", "--scene parallel_planes --technique pcss,hard --sweep pcss.penumbra_mask=false,true "
                                 "--sweep pcss.mask_dilate_blocks=0,1");
    const char *off = "pcss@penumbra_mask=false,mask_dilate_blocks=1", *on = "pcss@penumbra_mask=true,mask_dilate_blocks=1",
               *bare = "pcss@penumbra_mask=true,mask_dilate_blocks=0";
    CHECK(metric(m, on, "expensive_fraction") == metric(m, off, "expensive_fraction"),
          "the mask must skip no pixel pcss filters: expensive_fraction %.6f with it, %.6f without",
          metric(m, on, "expensive_fraction"), metric(m, off, "expensive_fraction"));
    CHECK(metric(m, on, "rmse") == metric(m, off, "rmse") &&
              metric(m, on, "misclassified_fraction") == metric(m, off, "misclassified_fraction"),
          "a conservative mask decides only what pcss decides alike: rmse %.6f against %.6f", metric(m, on, "rmse"),
          metric(m, off, "rmse"));
    CHECK(metric(m, on, "fetches_per_pixel") < 0.9 * metric(m, off, "fetches_per_pixel"),
          "the mask must save fetches: %.2f against %.2f", metric(m, on, "fetches_per_pixel"),
          metric(m, off, "fetches_per_pixel"));
    CHECK(metric(m, on, "ms_mask") > 0 && metric(m, off, "ms_mask") == 0, "the mask's pass is timed as ms_mask");
    CHECK(metric(m, bare, "fetches_per_pixel") < metric(m, on, "fetches_per_pixel"),
          "without the dilation the mask skips more (%.2f fetches against %.2f)", metric(m, bare, "fetches_per_pixel"),
          metric(m, on, "fetches_per_pixel"));
    CHECK(metric(m, "hard", "fetches_per_pixel") == 1.0, "a cell after a masked one counts no mask fetches: hard %g",
          metric(m, "hard", "fetches_per_pixel"));
    cJSON_Delete(m);
}

/* mask_dilate_world on contact_hardening, whose surfaces lie 4 to 8.8 m
 * from the camera in view depth: a block (4 pixels at 128 x 128) is 0.105
 * to 0.233 m wide there */
static void mask_world_radius(void)
{
    cJSON *m = run_cells("mask_world", "--scene contact_hardening --technique pcss --set pcss.penumbra_mask=true "
                                       "--sweep pcss.mask_dilate_blocks=0,1 "
                                       "--sweep pcss.mask_dilate_world=0,0.09,0.2,2,50");
    const char *one = "pcss@mask_dilate_blocks=1,mask_dilate_world=0.0",
               *under = "pcss@mask_dilate_blocks=0,mask_dilate_world=0.09",
               *some = "pcss@mask_dilate_blocks=0,mask_dilate_world=0.2",
               *capped = "pcss@mask_dilate_blocks=0,mask_dilate_world=2.0",
               *wide = "pcss@mask_dilate_blocks=0,mask_dilate_world=50.0";
    const double f_one = metric(m, one, "fetches_per_pixel"), f_under = metric(m, under, "fetches_per_pixel"),
                 f_some = metric(m, some, "fetches_per_pixel"), f_capped = metric(m, capped, "fetches_per_pixel"),
                 f_wide = metric(m, wide, "fetches_per_pixel");
    /* 0.09 m is under every block's width: ceil makes it one block (a block
     * angle half the true one would make most blocks two) */
    CHECK(f_under == f_one && metric(m, under, "rmse") == metric(m, one, "rmse"),
          "a world radius under a block dilates by one block: %.4f fetches against %.4f", f_under, f_one);
    /* 0.2 m is two blocks where they are under 0.2 m wide, one beyond (a
     * block angle twice the true one would make every block one) */
    CHECK(f_one < f_some && f_some < f_capped, "0.2 m lies between one block and the cap: %.4f < %.4f < %.4f", f_one,
          f_some, f_capped);
    /* 2 m is 9 to 19 blocks, 50 m the whole mask: both the cap of 8 */
    CHECK(f_capped == f_wide, "past the cap the radius is the cap: %.4f against %.4f fetches", f_capped, f_wide);
    /* a wider dilation only sends more pixels to pcss: never fewer decided right */
    CHECK(metric(m, wide, "misclassified_fraction") <= metric(m, one, "misclassified_fraction"),
          "a wider dilation must not misclassify more: %.6f against %.6f", metric(m, wide, "misclassified_fraction"),
          metric(m, one, "misclassified_fraction"));
    cJSON_Delete(m);
}

static void early_bail(void)
{
    cJSON *m = run_cells("bail", "--scene parallel_planes --technique pcss --sweep pcss.early_bail=false,true");
    const char *off = "pcss@early_bail=false", *on = "pcss@early_bail=true";
    CHECK(metric(m, on, "fetches_per_pixel") < metric(m, off, "fetches_per_pixel"), "early bail must save fetches");
    CHECK(metric(m, on, "misclassified_fraction") > metric(m, off, "misclassified_fraction"),
          "8 probes in a penumbra that 32 taps resolve: early bail decides more of it wrongly (%.4f against %.4f)",
          metric(m, on, "misclassified_fraction"), metric(m, off, "misclassified_fraction"));
    cJSON_Delete(m);
}

static void bilateral(void)
{
    /* pcf at radius 1: nearly hard edges, and depth steps where the
     * occluders stand over the floor and over each other */
    cJSON *m = run_cells("denoise", "--scene overlapping_occluders --technique pcf --set pcf.radius_texels=1 "
                                    "--sweep pcf.denoise_radius_px=0,4 --sweep pcf.denoise_sigma_world=0.05,100");
    const char *none = "pcf@denoise_radius_px=0,denoise_sigma_world=0.05",
               *bilateral = "pcf@denoise_radius_px=4,denoise_sigma_world=0.05",
               *plain = "pcf@denoise_radius_px=4,denoise_sigma_world=100.0";
    CHECK(metric(m, none, "leak_fraction") == 0, "pcf at radius 1 leaks no light (%.5f)",
          metric(m, none, "leak_fraction"));
    CHECK(metric(m, bilateral, "leak_fraction") == 0, "the bilateral blur lights no umbra across a depth step (%.5f)",
          metric(m, bilateral, "leak_fraction"));
    CHECK(metric(m, plain, "leak_fraction") > 0.001, "a plain blur of the same radius does (%.5f)",
          metric(m, plain, "leak_fraction"));
    CHECK(metric(m, bilateral, "ms_denoise") > 0 && metric(m, none, "ms_denoise") == 0,
          "the denoiser is timed as ms_denoise");
    cJSON_Delete(m);

    /* The normal weight: on parallel_planes every normal is the same (dot
     * products 1 within float rounding: measured, the same rmse); on
     * stanford_bunny it keeps the blur off faces turned away, which a
     * 4-pixel blur otherwise darkens (measured at 128²: dark_fraction 0.0153
     * without, 0.0092 at power 64; rmse 0.0940 and 0.0859) */
    const char *scenes[2] = {"parallel_planes", "stanford_bunny"};
    for (int k = 0; k < 2; k++) {
        char *name = util_printf("normals_%s", scenes[k]);
        char *args = util_printf("--scene %s --technique pcf --set pcf.radius_texels=1 --set pcf.denoise_radius_px=4 "
                                 "--set pcf.denoise_sigma_world=0.05 --sweep pcf.denoise_normal_power=0,64", scenes[k]);
        m = run_cells(name, args);
        const char *off = "pcf@denoise_normal_power=0.0", *on = "pcf@denoise_normal_power=64.0";
        if (k == 0)
            CHECK_NEAR(metric(m, on, "rmse"), metric(m, off, "rmse"), 1e-6,
                       "the normal weight must leave a flat receiver's blur alone");
        else
            CHECK(metric(m, on, "dark_fraction") < 0.8 * metric(m, off, "dark_fraction") &&
                      metric(m, on, "rmse") < metric(m, off, "rmse"),
                  "the normal weight must blur less across folds: dark_fraction %.4f against %.4f, rmse %.4f "
                  "against %.4f", metric(m, on, "dark_fraction"), metric(m, off, "dark_fraction"),
                  metric(m, on, "rmse"), metric(m, off, "rmse"));
        cJSON_Delete(m);
        free(name), free(args);
    }
}

TEST_MAIN(dir, fetch_counts, penumbra_mask, mask_world_radius, early_bail, bilateral)
