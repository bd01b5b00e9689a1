/* Protects the metric definitions of DESIGN.md §7 with synthetic images whose
 * answers are known by hand. Tolerances are float rounding (1e-6): every
 * expected value below is exact arithmetic on a few pixels. */
#include "check.h"
#include "base/util.h"
#include "score/metrics.h"

#include <stdlib.h>
#include <string.h>

#define W 10
#define H 10
#define N (W * H)

static float v_gt[N], v_tech[N], scored[N], dist[N];

static void reset(float gt, float tech)
{
    for (int i = 0; i < N; i++) {
        v_gt[i] = gt, v_tech[i] = tech, scored[i] = 1.0f, dist[i] = 1.0f;
    }
}

static void test_basic_errors(void)
{
    /* Half the pixels +0.1, half -0.1: rmse = mae = max = 0.1, bias = 0. */
    reset(0.5f, 0.5f);
    for (int i = 0; i < N; i++)
        v_tech[i] = i % 2 ? 0.6f : 0.4f;
    struct metrics m = {0};
    metrics_compute(v_tech, v_gt, NULL, scored, dist, W, H, &m);
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
    metrics_compute(v_tech, v_gt, NULL, scored, dist, W, H, &m);
    CHECK(m.rmse == 0.0 && m.max_abs == 0.0, "unscored pixels must not count: rmse %g", m.rmse);
    CHECK(m.scored_pixels == 50, "scored %ld", m.scored_pixels);
}

static void test_noise_floor(void)
{
    /* A second-seed ground truth differing by +-0.1 everywhere: the two
     * estimates' difference has rms 0.1, so one image's own error is 0.1/sqrt 2. */
    reset(0.5f, 0.5f);
    float alt[N];
    for (int i = 0; i < N; i++)
        alt[i] = i % 2 ? 0.6f : 0.4f;
    struct metrics m = {0};
    metrics_compute(v_tech, v_gt, alt, scored, dist, W, H, &m);
    CHECK_NEAR(m.gt_noise_rmse, 0.1 / sqrt(2.0), 1e-6, "noise floor from two seeds");
    /* V_gt = 0.5 everywhere: every pixel is in the penumbra band. */
    CHECK_NEAR(m.gt_noise_penumbra_rmse, 0.1 / sqrt(2.0), 1e-6, "noise floor over the band");
}

static void test_p99_and_bias(void)
{
    /* 100 errors 0.00, 0.01, ..., 0.99 (too bright): nearest-rank p99 is the
     * 99th smallest, 0.98; bias = mean = 0.495. */
    reset(0.0f, 0.0f);
    for (int i = 0; i < N; i++)
        v_tech[i] = (float)i / 100.0f;
    struct metrics m = {0};
    metrics_compute(v_tech, v_gt, NULL, scored, dist, W, H, &m);
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
    metrics_compute(v_tech, v_gt, NULL, scored, dist, W, H, &m);
    CHECK(m.penumbra_pixels == 50, "band of column 5 dilated by 2: %ld pixels", m.penumbra_pixels);
    CHECK_NEAR(m.penumbra_rmse, 0.0, 1e-9, "error outside the band");
    for (int y = 0; y < H; y++)
        v_tech[y * W + 8] = 1.0f, v_tech[y * W + 3] = 0.2f;
    metrics_compute(v_tech, v_gt, NULL, scored, dist, W, H, &m);
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
    metrics_compute(v_tech, v_gt, NULL, scored, dist, W, H, &m);
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
    long mismatch = metrics_score_mask(gt_mask, gt_dist, gl_dist, N, out);
    CHECK(mismatch == 2, "mismatch pixels %ld (expected the silhouette and the GL miss)", mismatch);
    CHECK(out[0] == 0 && out[1] == 0 && out[2] == 0 && out[3] == 0 && out[4] == 1 && out[5] == 1,
          "scored mask %g %g %g %g %g %g", out[0], out[1], out[2], out[3], out[4], out[5]);
}

/* The README's metric table ("### Metrics", first column, `key`s) names
 * exactly the metrics of METRICS(), the list every output is written from:
 * a metric added to one and not the other fails here. */
static void test_readme_table(void)
{
    char *path = util_printf("%s/README.md", SB_SOURCE_DIR), *text = NULL;
    size_t size;
    CHECK(util_read_file(path, &text, &size) == 0, "cannot read %s", path);
    char *section = text ? strstr(text, "\n### Metrics") : NULL;
    CHECK(section != NULL, "README.md has no '### Metrics' section");
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
            CHECK(found >= 0, "README lists `%.*s`, which is not a metric", (int)(close - k - 1), k + 1);
            if (found >= 0)
                listed[found] = true;
            k = close;
        }
    }
    CHECK(rows > 0, "README's metric table has no rows");
    for (int m = 0; m < METRIC_COUNT; m++)
        CHECK(listed[m], "README's metric table lacks `%s`", metric_info[m].key);
    free(text);
    free(path);
}

int main(void)
{
    test_basic_errors();
    test_noise_floor();
    test_p99_and_bias();
    test_penumbra_band();
    test_leak_dark_nonfinite();
    test_score_mask();
    test_readme_table();
    return check_finish();
}
