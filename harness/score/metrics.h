/* Error metrics of docs/design.md §7 (contract), over the scored mask, with
 * e = V_tech - V_gt. A metric with nothing to score (no scored pixel, an
 * empty penumbra band) is NAN, written as null: unscored is not perfect. */
#ifndef SB_METRICS_H
#define SB_METRICS_H

#include "base/util.h"
#include "truth/groundtruth.h"

#include <stdbool.h>
#include <stddef.h>

/* Relative disagreement between the GL camera distance and the ray-traced
 * hit distance above which a pixel is a silhouette mismatch. Both sample the
 * same pixel centre on the same triangles, so on a shared surface they agree
 * to float rounding (~1e-6); across a silhouette they differ by far more.
 * A technique whose renderer measurably cannot meet it states its own
 * (technique.h's depth_tolerance), which applies off the truth's silhouettes
 * only. */
#define METRICS_DEPTH_TOLERANCE 1e-3f

/* The scored mask's depth tolerance of a technique whose own is own (0:
 * it has none): its own, or the harness's. */
static inline float metrics_depth_tolerance(float own)
{
    return own > 0 ? own : METRICS_DEPTH_TOLERANCE;
}

/* Penumbra band: V_gt strictly inside (lo, hi), dilated by this many pixels. */
#define METRICS_PENUMBRA_LO 0.02
#define METRICS_PENUMBRA_HI 0.98
#define METRICS_PENUMBRA_DILATE 2

/* leak_fraction's and dark_fraction's thresholds (docs/design.md §7): light
 * leaking is V_tech above LEAK_TECH where V_gt is below LEAK_GT (the true
 * umbra); over-darkening (acne) is V_tech below DARK_TECH where V_gt is
 * above DARK_GT. Plain literals: the help text spells them (UTIL_STR). */
#define METRICS_LEAK_GT 0.05
#define METRICS_LEAK_TECH 0.25
#define METRICS_DARK_GT 0.95
#define METRICS_DARK_TECH 0.75

/* Every metric of a cell, once (STYLE.md item 6a): X(key, C type, printf
 * format for the report, shown in the report's matrix table, help). struct
 * metrics, metrics.json, matrix.csv/json and the report's columns come from
 * this list, in this order; test_metrics checks docs/metrics.md's metric table
 * against it. */
#define METRICS(X)                                                                              \
    X(rmse, double, "%.4f", true, "root-mean-square error")                                     \
    X(mae, double, "%.4f", true, "mean absolute error")                                          \
    X(bias, double, "%+.4f", true, "mean signed error (> 0: too bright)")                        \
    X(max_abs, double, "%.4f", false, "largest absolute error")                                  \
    X(p99_abs, double, "%.4f", true, "99th-percentile absolute error (nearest rank)")             \
    X(penumbra_rmse, double, "%.4f", true, "rmse over the penumbra band")                        \
    X(leak_fraction, double, "%.4f", true, "share of scored pixels with V_gt < " UTIL_STR(METRICS_LEAK_GT)         \
      ", V_tech > " UTIL_STR(METRICS_LEAK_TECH))                                                                \
    X(dark_fraction, double, "%.4f", true, "share of scored pixels with V_gt > " UTIL_STR(METRICS_DARK_GT)         \
      ", V_tech < " UTIL_STR(METRICS_DARK_TECH))                                                                \
    X(shaded_rmse, double, "%.4f", true, "rms of (V_tech - V_gt_weighted) E / mean E: the error seen in the shaded image") \
    X(nonfinite, long, "%.0f", true, "NaN/Inf values of V_tech where GL drew geometry")          \
    X(scored_pixels, long, "%.0f", false, "pixels scored")                                       \
    X(mismatch_pixels, long, "%.0f", false, "pixels where GL and the ray tracer see different surfaces") \
    X(terminator_pixels, long, "%.0f", false, "scored pixels that see part of the light below their horizon (H < 1)") \
    X(penumbra_pixels, long, "%.0f", false, "pixels in the penumbra band")                       \
    X(ms_shadowmap, double, "%.2f", true, "median ms per frame: the depth pass")                 \
    X(ms_filter_prep, double, "%.2f", true, "median ms per frame: the products filtered from it") \
    X(ms_mask, double, "%.2f", false, "median ms per frame: the penumbra mask's pre-pass (0: none)") \
    X(ms_receiver, double, "%.2f", true, "median ms per frame: the receiver pass")                \
    X(ms_denoise, double, "%.2f", false, "median ms per frame: the denoiser (0: none)")          \
    X(ms_total, double, "%.2f", true, "median ms of a whole frame (all its stages)")             \
    X(ms_total_q1, double, "%.2f", false, "first quartile of the frames' ms_total")              \
    X(ms_total_q3, double, "%.2f", false, "third quartile of the frames' ms_total")               \
    X(fetches_per_pixel, double, "%.1f", true, "shadow-map fetches per covered pixel (receiver pass and mask), " \
      "counted on the device")                                                                   \
    X(prep_texels, double, "%.0f", false, "texels read and written per frame by the passes that build the products") \
    X(expensive_fraction, double, "%.3f", false, "share of covered pixels that ran the full filter")  \
    X(misclassified_fraction, double, "%.4f", false, "of the pixels an early-out or the mask decided, the share " \
      "in the true penumbra")                                                                    \
    X(gt_noise_rmse, double, "%.4f", false, "the ground truth's own rms error over the scored pixels") \
    X(gt_noise_penumbra_rmse, double, "%.4f", true, "the ground truth's own rms error over the band")

struct metrics {
#define X(key, type, format, in_report, help) type key;
    METRICS(X)
#undef X
};

/* The list as data, for the writers that iterate over it. */
struct metric_info {
    const char *key, *format, *help;
    bool in_report;  /* a column of the report's matrix table */
};
enum {
#define X(key, type, format, in_report, help) METRIC_##key,
    METRICS(X)
#undef X
    METRIC_COUNT
};
extern const struct metric_info metric_info[METRIC_COUNT];

/* The value of metric k (METRIC_*) of m. */
double metrics_value(const struct metrics *m, int k);

/* Every metric of m from object j, as the files write them (a number,
 * null where nothing was measured; a count a whole number, never null).
 * Returns 0, or -1 when j holds anything else (another process's file is
 * read with it). */
struct cJSON;
int metrics_read_json(const struct cJSON *j, struct metrics *m);

/* scored[i] = 1 where gt_mask is set and GL saw the same surface (camera
 * distances agree within depth_tolerance, relative: METRICS_DEPTH_TOLERANCE
 * or the technique's own, metrics_depth_tolerance; a wider one applies
 * only off the truth's silhouettes, metrics_truth_silhouette, where
 * METRICS_DEPTH_TOLERANCE stays); returns the number of mismatch pixels:
 * where exactly one of GL and the ray tracer hit geometry, or both did at
 * different distances. gl_distance and gt_distance are width x height, -1
 * where nothing was hit. */
long metrics_score_mask(const float *gt_mask, const float *gt_distance, const float *gl_distance, int width,
                        int height, float depth_tolerance, float *scored);

/* Whether the truth's pixel (x, y) lies on a silhouette: a neighbour's
 * camera ray hits nothing where this one hits (or the other way round),
 * or its distances break there, across x or y: a jump, not a slope (the
 * second difference of 1 / distance over the pixel and its two neighbours
 * more than METRICS_SILHOUETTE_JUMP; at the image's edge, a jump of that
 * much, relative, to the one neighbour). A plane seen at a grazing angle,
 * whose distance grows by far more than that from pixel to pixel, does not
 * break. */
#define METRICS_SILHOUETTE_JUMP 0.02f
bool metrics_truth_silhouette(const float *gt_distance, int width, int height, int x, int y);

/* Fills every error metric of V_tech against gt over scored (not the
 * timings, not mismatch_pixels). Pixels whose V_tech is not finite are
 * counted in nonfinite and left out of the error sums. */
void metrics_compute(const float *v_tech, const struct gt_image *gt, const float *scored,
                     const float *gl_distance, struct metrics *m);

/* band[i] = 1 where pixel i is scored and in the penumbra band: V_gt in
 * (METRICS_PENUMBRA_LO, METRICS_PENUMBRA_HI), dilated by
 * METRICS_PENUMBRA_DILATE pixels; else 0. */
void metrics_penumbra_band(const float *v_gt, const float *scored, int width, int height, float *band);

/* The counted costs of docs/metrics.md from a counting frame
 * (render/receiver.h's receiver_cost): fetches over the covered pixels (fetches_per_pixel), the share of them that ran
 * the full filter (expensive_fraction), and of the scored pixels a
 * shortcut decided (shortcut[i] != 0), the share whose V_gt lies in
 * (METRICS_PENUMBRA_LO, METRICS_PENUMBRA_HI) (misclassified_fraction; NAN
 * when none was decided so). */
void metrics_cost(double fetches, long covered, long expensive, const float *shortcut, const struct gt_image *gt,
                  const float *scored, int count, struct metrics *m);

/* Whether the cell had anything to score (its error metrics are numbers). */
bool metrics_scored(const struct metrics *m);

/* No measurement at all (a cell that failed): every real-valued metric
 * NaN (null in its files), every count 0. */
void metrics_none(struct metrics *m);

#endif
