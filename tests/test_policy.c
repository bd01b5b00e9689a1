/* Protects the policies of score/, called directly (no binary, no GL):
 *   - the break rule (score/break_rule.h): each clause at its threshold,
 *     and break points found walking away from the reference;
 *   - the Pareto front (score/frontier.h): on random sets, no point of the
 *     front is dominated and every other point is;
 *   - the baseline comparison (score/baseline.h): a metric beyond its
 *     tolerance either way, bias by its size, unscored on one side, a
 *     picture that moved with and without a metric better;
 *   - the accumulation's reprojection (flicker_reproject): a still camera
 *     maps every pixel to itself, a camera moved by whole pixels maps by
 *     them, a disagreeing distance maps to none. */
#include "check.h"
#include "base/util.h"
#include "score/baseline.h"
#include "score/break_rule.h"
#include "score/flicker.h"
#include "score/frontier.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static struct metrics scored(double rmse, double leak, double dark)
{
    return (struct metrics){.rmse = rmse, .leak_fraction = leak, .dark_fraction = dark, .scored_pixels = 100};
}

static void break_rule(void)
{
    const struct metrics ref = scored(0.02, 0.01, 0.01);
    /* rmse: at least twice as large and BREAK_RULE_RMSE_RISE (0.01) larger, both */
    struct metrics twice = scored(0.04, 0.01, 0.01), small_ref = scored(0.004, 0, 0);
    CHECK(break_rule_broken(&twice, &ref), "rmse 0.02 -> 0.04 (x2, +0.02) breaks");
    struct metrics almost = scored(0.0399, 0.01, 0.01);
    CHECK(!break_rule_broken(&almost, &ref), "rmse 0.02 -> 0.0399 (under x2) holds");
    struct metrics tiny = scored(0.012, 0, 0);
    CHECK(!break_rule_broken(&tiny, &small_ref), "rmse 0.004 -> 0.012 (x3 but +0.008) holds");
    /* leak or dark: BREAK_RULE_FRACTION_RISE (0.05) larger */
    struct metrics leak = scored(0.02, 0.0601, 0.01), dark = scored(0.02, 0.01, 0.0601),
                   dark_less = scored(0.02, 0.01, 0.0599);
    CHECK(break_rule_broken(&leak, &ref) && break_rule_broken(&dark, &ref), "leak or dark +0.0501 breaks");
    CHECK(!break_rule_broken(&dark_less, &ref), "dark +0.0499 holds");
    /* NaN/Inf always; unscored never (nothing to compare) */
    struct metrics nan_v = scored(0.02, 0.01, 0.01), unscored = {0};
    nan_v.nonfinite = 1;
    unscored.rmse = NAN;
    CHECK(break_rule_broken(&nan_v, &ref), "a NaN breaks");
    CHECK(!break_rule_broken(&unscored, &ref) && !break_rule_broken(&twice, &unscored), "unscored: no verdict");

    /* Break points: values 0..5, the reference 2; 0 and 4, 5 broken, 3 not:
     * the first broken walking down is 0 (1 holds), walking up 4. */
    const struct metrics v0 = twice, v1 = ref, v3 = almost, v4 = leak, v5 = dark;
    const struct metrics *m[6] = {&v0, &v1, &ref, &v3, &v4, &v5};
    int below, above;
    break_rule_points(m, 6, 2, &below, &above);
    CHECK(below == 0 && above == 4, "break points %d, %d: wanted 0, 4", below, above);
    m[4] = NULL;  /* not measured: skipped */
    break_rule_points(m, 6, 2, &below, &above);
    CHECK(above == 5, "an unmeasured value is skipped: %d", above);
    m[2] = NULL;
    break_rule_points(m, 6, 2, &below, &above);
    CHECK(below == -1 && above == -1, "no reference, no break points");
}

static void pareto(void)
{
    /* A tie in time keeps the lower error; the rest by the definition. */
    const double x[] = {5, 1, 9, 6, 1}, y[] = {0.5, 0.3, 0.1, 0.35, 0.4};
    int front[64];
    CHECK(frontier_pareto(x, y, 5, front) == 2 && front[0] == 1 && front[1] == 2, "the hand-made front");
    uint64_t rng = 12345;
    for (int trial = 0; trial < 200; trial++) {
        double xs[64], ys[64];
        const int n = 1 + trial % 64;
        for (int i = 0; i < n; i++) {
            rng = rng * 6364136223846793005ull + 1442695040888963407ull;
            xs[i] = (double)(rng >> 40 & 15), ys[i] = (double)(rng >> 20 & 15);  /* ties on purpose */
        }
        const int f = frontier_pareto(xs, ys, n, front);
        bool on[64] = {false};
        for (int k = 0; k < f; k++) {
            on[front[k]] = true;
            CHECK(k == 0 || (xs[front[k]] > xs[front[k - 1]] && ys[front[k]] < ys[front[k - 1]]),
                  "trial %d: the front is not in increasing time and decreasing error", trial);
        }
        for (int i = 0; i < n; i++) {
            bool dominated = false, twin = false;  /* beaten: as fast and as good, and better in one */
            for (int j = 0; j < n; j++)
                dominated |= xs[j] <= xs[i] && ys[j] <= ys[i] && (xs[j] < xs[i] || ys[j] < ys[i]);
            for (int k = 0; k < f; k++)  /* the same point as one on the front: one of them is kept */
                twin |= front[k] != i && xs[front[k]] == xs[i] && ys[front[k]] == ys[i];
            CHECK(on[i] ? !dominated : dominated || twin, "trial %d: point %d (%g, %g) is %s the front and %s",
                  trial, i, xs[i], ys[i], on[i] ? "on" : "off", dominated ? "dominated" : "not dominated");
        }
    }
}

/* A baseline of W x W pixels of V = 0.5 with rmse 0.1, bias -0.02, the
 * other guarded metrics 0, every tolerance 0.001. */
#define W 16
static struct baseline make_baseline(void)
{
    struct baseline b = {.setup = {W, W, 1, 16, 1}, .pixel_threshold = 0.002, .max_moved = 0.0015};
    b.doc = cJSON_CreateObject();
    cJSON *m = cJSON_AddObjectToObject(b.doc, "metrics"), *tol = cJSON_AddObjectToObject(b.doc, "tolerances");
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const int k = baseline_guards[g].metric;
        cJSON_AddNumberToObject(m, metric_info[k].key, k == METRIC_rmse ? 0.1 : k == METRIC_bias ? -0.02 : 0);
        cJSON_AddNumberToObject(cJSON_AddObjectToObject(tol, metric_info[k].key), "value", 0.001);
    }
    b.picture = xmalloc(sizeof *b.picture * W * W);
    float half[W * W];
    for (int i = 0; i < W * W; i++)
        half[i] = 0.5f;
    baseline_quantize(half, W * W, b.picture);
    return b;
}

static enum baseline_status compare(const struct baseline *b, const struct metrics *m, const float *v,
                                    struct baseline_comparison *c)
{
    baseline_compare(b, m, v, c);
    return c->status;
}

static void baseline_comparison(void)
{
    struct baseline b = make_baseline();
    float v[W * W];
    for (int i = 0; i < W * W; i++)
        v[i] = 0.5f;
    struct metrics m = {.rmse = 0.1, .bias = -0.02};
    struct baseline_comparison c;
    CHECK(compare(&b, &m, v, &c) == BASELINE_PASS && c.moved_fraction == 0, "the same cell passes");
    m.rmse = 0.1009;
    CHECK(compare(&b, &m, v, &c) == BASELINE_PASS, "rmse within its tolerance (0.0009 of 0.001) passes");
    m.rmse = 0.1011;
    CHECK(compare(&b, &m, v, &c) == BASELINE_REGRESSED && c.worse == 1 && c.direction[0] == 1,
          "rmse beyond its tolerance: regressed");
    m.rmse = 0.0989;
    CHECK(compare(&b, &m, v, &c) == BASELINE_IMPROVED && c.better == 1, "rmse better beyond it: improved");
    m.rmse = 0.1, m.bias = 0.0211;  /* |bias| 0.0211 > 0.02 + 0.001, though the signed value rose */
    CHECK(compare(&b, &m, v, &c) == BASELINE_REGRESSED, "bias is judged by its size");
    m.bias = 0.019;
    CHECK(compare(&b, &m, v, &c) == BASELINE_IMPROVED, "a bias of smaller size is better");
    m.bias = -0.02, m.rmse = NAN;
    CHECK(compare(&b, &m, v, &c) == BASELINE_REGRESSED, "unscored now, scored before: regressed");
    m.rmse = 0.1;
    /* The picture: one pixel in 256 (0.39 %) moved past 0.002, no metric moved: regressed. */
    v[7] = 0.51f;
    CHECK(compare(&b, &m, v, &c) == BASELINE_REGRESSED && c.picture_moved && c.worse == 0 && c.better == 0,
          "a picture that moved with no metric better regresses");
    m.rmse = 0.098;
    CHECK(compare(&b, &m, v, &c) == BASELINE_IMPROVED, "moved with a metric better: improved, not regressed");
    v[7] = 0.5015f, m.rmse = 0.1;
    CHECK(compare(&b, &m, v, &c) == BASELINE_PASS && c.moved_fraction == 0, "a move under the threshold is none");
    baseline_free(&b);
}

static void reprojection(void)
{
    enum { N = 16 };
    const struct scene_camera cam = {.pos = {0, 0, 5}, .x = {1, 0, 0}, .y = {0, 1, 0}, .z = {0, 0, 1},
                                     .yfov_rad = 0.8f, .znear = 0.1f};
    /* A plane at z = 0 seen square on: its camera distance per pixel. */
    float dist[N * N];
    const float t = tanf(0.4f);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            const float sx = (2 * (x + 0.5f) / N - 1) * t, sy = (1 - 2 * (y + 0.5f) / N) * t;
            dist[y * N + x] = 5 * sqrtf(1 + sx * sx + sy * sy);
        }
    int from[N * N];
    flicker_reproject(&cam, &cam, dist, dist, N, N, from);
    int same = 0;
    for (int i = 0; i < N * N; i++)
        same += from[i] == i;
    CHECK(same == N * N, "a still camera maps %d of %d pixels to themselves", same, N * N);
    /* The camera moved by two pixels' width at the plane, along +x: the
     * scene moved left on screen, so a point now at pixel x was at x + 2
     * last frame. */
    struct scene_camera moved = cam;
    moved.pos.x += 2 * (2 * 5 * t / N);
    float dist_moved[N * N];  /* moved parallel to the plane: the same distances */
    memcpy(dist_moved, dist, sizeof dist);
    flicker_reproject(&moved, &cam, dist_moved, dist, N, N, from);
    int shifted = 0, none = 0;
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            const int i = y * N + x;
            shifted += x + 2 < N && from[i] == i + 2;
            none += x + 2 >= N && from[i] == -1;  /* past the last frame's edge */
        }
    CHECK(shifted == (N - 2) * N && none == 2 * N, "moved two pixels: %d mapped by two, %d to none", shifted, none);
    /* What the last frame saw nearer (an occluder there then): no history. */
    dist[5 * N + 7] *= 0.5f;
    flicker_reproject(&moved, &cam, dist_moved, dist, N, N, from);
    CHECK(from[5 * N + 5] == -1, "a pixel whose point was hidden last frame maps to none: %d", from[5 * N + 5]);
}

int main(void)
{
    break_rule();
    pareto();
    baseline_comparison();
    reprojection();
    return check_finish();
}
