/* Protects the metric definitions of docs/design.md §7 with synthetic images whose
 * answers are known by hand. Tolerances are float rounding (1e-6): every
 * expected value below is exact arithmetic on a few pixels. */
#include "check.h"
#include "base/util.h"
#include "score/metrics.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 10
#define H 10
#define N (W * H)

static float v_gt[N], v_weighted[N], h[N], e[N], noise[N], v_tech[N], scored[N], dist[N];
static const struct gt_image gt = {.width = W, .height = H, .v = v_gt, .v_weighted = v_weighted,
                                   .h = h, .e = e, .noise = noise, .distance = dist, .mask = scored};

/* V_gt = V_gt_weighted = gt, V_tech = tech; every pixel scored, fully
 * above the horizon (H = 1), unit irradiance, no ground-truth noise. */
static void reset(float gt_value, float tech)
{
    for (int i = 0; i < N; i++) {
        v_gt[i] = v_weighted[i] = gt_value, v_tech[i] = tech, scored[i] = 1.0f, dist[i] = 1.0f;
        h[i] = 1.0f, e[i] = 1.0f, noise[i] = 0.0f;
    }
}

static void test_basic_errors(void)
{
    /* Half the pixels +0.1, half -0.1: rmse = mae = max = 0.1, bias = 0. */
    reset(0.5f, 0.5f);
    for (int i = 0; i < N; i++)
        v_tech[i] = i % 2 ? 0.6f : 0.4f;
    struct metrics m = {0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.rmse, 0.1, 1e-6, "rmse of +-0.1");
    CHECK_NEAR(m.mae, 0.1, 1e-6, "mae of +-0.1");
    CHECK_NEAR(m.bias, 0.0, 1e-6, "bias of symmetric errors");
    CHECK_NEAR(m.max_abs, 0.1, 1e-6, "max_abs");
    CHECK(m.scored_pixels == N, "scored %ld", m.scored_pixels);
    CHECK(m.nonfinite == 0, "nonfinite %ld", m.nonfinite);

    /* Only unscored pixels are wrong: every error metric is zero. */
    reset(0.5f, 0.5f);
    for (int i = 0; i < 50; i++)
        v_tech[i] = 1.0f, scored[i] = 0.0f;
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK(m.rmse == 0.0 && m.max_abs == 0.0, "unscored pixels must not count: rmse %g", m.rmse);
    CHECK(m.scored_pixels == 50, "scored %ld", m.scored_pixels);
    CHECK(metrics_scored(&m), "a cell with scored pixels is scored");
}

static void test_unscored(void)
{
    /* Nothing scored: every error metric is null (NAN), never a perfect 0;
     * the counts stay numbers. */
    reset(0.5f, 0.5f);
    for (int i = 0; i < N; i++)
        scored[i] = 0.0f;
    struct metrics m = {.ms_total = 3.0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK(!metrics_scored(&m), "no scored pixel: unscored");
    for (int k = 0; k < METRIC_COUNT; k++) {
        double v = metrics_value(&m, k);
        bool count = strstr(metric_info[k].key, "pixels") || strcmp(metric_info[k].key, "nonfinite") == 0;
        bool timing = strncmp(metric_info[k].key, "ms_", 3) == 0;
        bool cost = strcmp(metric_info[k].key, "fetches_per_pixel") == 0 || strcmp(metric_info[k].key, "prep_texels") == 0 ||
                    strcmp(metric_info[k].key, "expensive_fraction") == 0 ||
                    strcmp(metric_info[k].key, "misclassified_fraction") == 0;
        if (cost)  /* metrics_cost's, from a counting frame: left as they were */
            CHECK(v == 0, "%s is a counted cost, not metrics_compute's", metric_info[k].key);
        else if (count || timing)
            CHECK(!isnan(v), "%s is a count or a time, defined without scored pixels", metric_info[k].key);
        else
            CHECK(isnan(v), "%s = %g with no scored pixel; expected null", metric_info[k].key, v);
    }
    CHECK(m.scored_pixels == 0 && m.ms_total == 3.0, "counts 0, timings kept");
    /* Scored pixels but an empty penumbra band (V_gt = 1 everywhere): the
     * band's metrics are null, the others numbers. */
    reset(1.0f, 1.0f);
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK(metrics_scored(&m) && m.rmse == 0.0, "lit and right: scored, rmse 0");
    CHECK(isnan(m.penumbra_rmse) && isnan(m.gt_noise_penumbra_rmse) && m.penumbra_pixels == 0,
          "empty band: penumbra_rmse %g, expected null", m.penumbra_rmse);
}

static void test_shaded_and_terminator(void)
{
    /* shaded_rmse = rms((V_tech - V_gt_weighted) E) / mean E over scored
     * pixels. Half the pixels (odd) have E = 3, half (even) E = 1: mean E 2.
     * V_tech - V_gt_weighted = 0.2 on the odd ones, -0.1 on the even ones:
     * errors 0.6 and -0.1, rms sqrt((0.36 + 0.01) / 2), over 2. V_gt itself
     * differs from V_gt_weighted, so rmse (against V_gt) is another number. */
    reset(0.5f, 0.5f);
    for (int i = 0; i < N; i++) {
        e[i] = i % 2 ? 3.0f : 1.0f;
        v_weighted[i] = 0.4f;
        v_tech[i] = i % 2 ? 0.6f : 0.3f;
        h[i] = i < 30 ? 0.5f : 1.0f;  /* 30 terminator pixels, 10 of them unscored */
    }
    for (int i = 0; i < 10; i++)
        scored[i] = 0.0f;
    /* The unscored pixels must not count: give them an absurd error. */
    for (int i = 0; i < 10; i++)
        v_tech[i] = 100.0f;
    struct metrics m = {0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.shaded_rmse, sqrt((0.36 + 0.01) / 2.0) / 2.0, 1e-6, "shaded_rmse by hand");
    CHECK_NEAR(m.rmse, sqrt((0.01 + 0.04) / 2.0), 1e-6, "rmse against V_gt, not V_gt_weighted");
    CHECK(m.terminator_pixels == 20, "terminator pixels %ld, expected the 20 scored with H < 1",
          m.terminator_pixels);
    /* Acne where N.L already darkens (small E) costs little in the shaded
     * image: the same error with E ten times smaller there counts less. */
    double before = m.shaded_rmse;
    for (int i = 0; i < N; i++)
        if (i % 2 == 0)
            e[i] = 0.1f;
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.shaded_rmse, sqrt((0.36 + 0.0001) / 2.0) / 1.55, 1e-6, "shaded_rmse, dim pixels");
    CHECK(m.shaded_rmse != before, "E weights the error");
}

static void test_noise_floor(void)
{
    /* The ground truth's noise samples +-0.1 everywhere (and 5 on unscored
     * pixels, which must not count): its noise floor is their rms, 0.1. */
    reset(0.5f, 0.5f);
    for (int i = 0; i < N; i++)
        noise[i] = i % 2 ? 0.1f : -0.1f;
    for (int i = 0; i < 4; i++)
        noise[i] = 5.0f, scored[i] = 0.0f;
    struct metrics m = {0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.gt_noise_rmse, 0.1, 1e-6, "noise floor over the scored pixels");
    /* V_gt = 0.5 everywhere: every scored pixel is in the penumbra band. */
    CHECK_NEAR(m.gt_noise_penumbra_rmse, 0.1, 1e-6, "noise floor over the band");
}

static void test_p99_and_bias(void)
{
    /* 100 errors 0.00, 0.01, ..., 0.99 (too bright): nearest-rank p99 is the
     * 99th smallest, 0.98; bias = mean = 0.495. */
    reset(0.0f, 0.0f);
    for (int i = 0; i < N; i++)
        v_tech[i] = (float)i / 100.0f;
    struct metrics m = {0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.p99_abs, 0.98, 1e-6, "nearest-rank 99th percentile");
    CHECK_NEAR(m.bias, 0.495, 1e-6, "mean signed error");
    CHECK_NEAR(m.max_abs, 0.99, 1e-6, "max");
}

static void test_penumbra_band(void)
{
    /* V_gt: 0 in columns 0-4, 0.5 in column 5, 1 in 6-9. The band is column
     * 5 dilated by 2 px: columns 3-7, 50 pixels. An error of 0.2 on column 8
     * only is outside the band: penumbra_rmse 0. Then 0.2 on column 3 (in the
     * band): penumbra_rmse = sqrt(10 * 0.04 / 50). */
    reset(0.0f, 0.0f);
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            v_gt[y * W + x] = v_tech[y * W + x] = x < 5 ? 0.0f : x == 5 ? 0.5f : 1.0f;
    for (int y = 0; y < H; y++)
        v_tech[y * W + 8] = 0.8f;
    struct metrics m = {0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK(m.penumbra_pixels == 50, "band of column 5 dilated by 2: %ld pixels", m.penumbra_pixels);
    CHECK_NEAR(m.penumbra_rmse, 0.0, 1e-9, "error outside the band");
    for (int y = 0; y < H; y++)
        v_tech[y * W + 8] = 1.0f, v_tech[y * W + 3] = 0.2f;
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.penumbra_rmse, sqrt(10 * 0.04 / 50.0), 1e-6, "error inside the band");
}

static void test_leak_dark_nonfinite(void)
{
    /* 4 umbra pixels leak (V_tech 0.3 > 0.25 where V_gt 0 < 0.05), 1 does
     * not (0.2); 3 lit pixels are over-darkened (0.7 < 0.75 where 1 > 0.95);
     * one NaN is counted and kept out of the sums. */
    reset(0.0f, 0.0f);
    for (int i = 50; i < N; i++)
        v_gt[i] = v_tech[i] = 1.0f;
    for (int i = 0; i < 4; i++)
        v_tech[i] = 0.3f;
    v_tech[4] = 0.2f;
    for (int i = 50; i < 53; i++)
        v_tech[i] = 0.7f;
    v_tech[99] = NAN;
    struct metrics m = {0};
    metrics_compute(v_tech, &gt, scored, dist, &m);
    CHECK_NEAR(m.leak_fraction, 4.0 / N, 1e-9, "leak share of scored pixels");
    CHECK_NEAR(m.dark_fraction, 3.0 / N, 1e-9, "dark share of scored pixels");
    CHECK(m.nonfinite == 1, "nonfinite %ld", m.nonfinite);
    CHECK(isfinite(m.rmse), "NaN must not reach rmse");
    double expect = sqrt((4 * 0.09 + 0.04 + 3 * 0.09) / 99.0);
    CHECK_NEAR(m.rmse, expect, 1e-6, "rmse over the 99 finite pixels");
}

static void test_score_mask(void)
{
    /* GT mask on everywhere but pixel 0; pixel 1 a silhouette (GL 1% farther
     * than the ray hit); pixel 2 GL misses; pixel 3 both miss. */
    float gt_mask[N], gt_dist[N], gl_dist[N], out[N];
    for (int i = 0; i < N; i++)
        gt_mask[i] = 1.0f, gt_dist[i] = gl_dist[i] = 10.0f;
    gt_mask[0] = 0.0f;
    gl_dist[1] = 10.1f;
    gl_dist[2] = -1.0f;
    gt_dist[3] = gl_dist[3] = -1.0f;
    gt_mask[3] = 0.0f;
    gl_dist[4] = 10.0f * (1.0f + 0.5f * METRICS_DEPTH_TOLERANCE); /* within tolerance */
    long mismatch = metrics_score_mask(gt_mask, gt_dist, gl_dist, W, H, METRICS_DEPTH_TOLERANCE, out);
    CHECK(mismatch == 2, "mismatch pixels %ld (expected the silhouette and the GL miss)", mismatch);
    CHECK(out[0] == 0 && out[1] == 0 && out[2] == 0 && out[3] == 0 && out[4] == 1 && out[5] == 1,
          "scored mask %g %g %g %g %g %g", out[0], out[1], out[2], out[3], out[4], out[5]);
    /* a technique's own tolerance is the one applied: 2 % takes pixel 1's 1 % in, 0.5 % leaves it out */
    mismatch = metrics_score_mask(gt_mask, gt_dist, gl_dist, W, H, 0.02f, out);
    CHECK(mismatch == 1 && out[1] == 1 && out[2] == 0, "at 2 %%: %ld mismatch pixels, pixel 1 scored %g", mismatch,
          out[1]);
    mismatch = metrics_score_mask(gt_mask, gt_dist, gl_dist, W, H, 0.005f, out);
    CHECK(mismatch == 2 && out[1] == 0 && out[4] == 1, "at 0.5 %%: %ld mismatch pixels, pixel 1 scored %g",
          mismatch, out[1]);
    /* but never on the truth's silhouettes: pixel (3, 2) beside a jump of the truth's distance, GL 1 % off
     * there, is a mismatch at 2 % too; the pixel of the jump itself, where GL agrees, is scored */
    gt_dist[2 * W + 2] = gl_dist[2 * W + 2] = 20.0f;
    gl_dist[2 * W + 3] = 10.1f;
    mismatch = metrics_score_mask(gt_mask, gt_dist, gl_dist, W, H, 0.02f, out);
    CHECK(mismatch == 2 && out[2 * W + 3] == 0 && out[2 * W + 2] == 1 && out[1] == 1,
          "a silhouette at 2 %%: %ld mismatch pixels, (3, 2) scored %g", mismatch, out[2 * W + 3]);
    CHECK(metrics_truth_silhouette(gt_dist, W, H, 3, 2) && !metrics_truth_silhouette(gt_dist, W, H, 6, 6),
          "the truth's silhouette: beside the jump, not far from it");
}

/* docs/metrics.md's metric table ("### Metrics", first column, `key`s) names
 * exactly the metrics of METRICS(), the list every output is written from:
 * a metric added to one and not the other fails here. */
static void test_docs_table(void)
{
    char *path = util_printf("%s/docs/metrics.md", SB_SOURCE_DIR), *text = NULL;
    size_t size;
    CHECK(util_read_file(path, &text, &size) == 0, "cannot read %s", path);
    char *section = text ? strstr(text, "\n### Metrics") : NULL;
    CHECK(section != NULL, "docs/metrics.md has no '### Metrics' section");
    bool listed[METRIC_COUNT] = {false};
    int rows = 0;
    /* Table rows until the next heading or the end of the table. */
    for (char *line = section ? strchr(section + 1, '\n') : NULL; line && line[1] != '#';
         line = strchr(line + 1, '\n')) {
        if (strncmp(line + 1, "| `", 3) != 0)
            continue;
        rows++;
        char *end = strchr(line + 2, '|');  /* the first cell */
        for (char *k = strchr(line + 1, '`'); k && k < end; k = strchr(k + 1, '`')) {
            char *close = strchr(k + 1, '`');
            if (!close || close > end)
                break;
            int found = -1;
            for (int m = 0; m < METRIC_COUNT; m++)
                if ((size_t)(close - k - 1) == strlen(metric_info[m].key) &&
                    strncmp(k + 1, metric_info[m].key, (size_t)(close - k - 1)) == 0)
                    found = m;
            CHECK(found >= 0, "docs/metrics.md lists `%.*s`, which is not a metric", (int)(close - k - 1), k + 1);
            if (found >= 0)
                listed[found] = true;
            k = close;
        }
    }
    CHECK(rows > 0, "docs/metrics.md's metric table has no rows");
    for (int m = 0; m < METRIC_COUNT; m++)
        CHECK(listed[m], "docs/metrics.md's metric table lacks `%s`", metric_info[m].key);
    free(text);
    free(path);
}

int main(void)
{
    test_basic_errors();
    test_unscored();
    test_shaded_and_terminator();
    test_noise_floor();
    test_p99_and_bias();
    test_penumbra_band();
    test_leak_dark_nonfinite();
    test_score_mask();
    test_docs_table();
    return check_finish();
}
