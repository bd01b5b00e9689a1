/* Error metrics of DESIGN.md §7 (contract), over the scored mask, with
 * e = V_tech - V_gt. */
#ifndef SB_METRICS_H
#define SB_METRICS_H

#include <cjson/cJSON.h>

/* Relative disagreement between the GL camera distance and the ray-traced
 * hit distance above which a pixel is a silhouette mismatch. Both sample the
 * same pixel centre on the same triangles, so on a shared surface they agree
 * to float rounding (~1e-6); across a silhouette they differ by far more. */
#define METRICS_DEPTH_TOLERANCE 1e-3f

/* Penumbra band: V_gt strictly inside (lo, hi), dilated by this many pixels. */
#define METRICS_PENUMBRA_LO 0.02
#define METRICS_PENUMBRA_HI 0.98
#define METRICS_PENUMBRA_DILATE 2

struct metrics {
    double rmse, mae, bias, max_abs, p99_abs;
    double penumbra_rmse;
    double leak_fraction;   /* of scored pixels: V_gt < 0.05 and V_tech > 0.25 */
    double dark_fraction;   /* of scored pixels: V_gt > 0.95 and V_tech < 0.75 */
    long nonfinite;         /* NaN/Inf in V_tech anywhere GL drew geometry */
    long scored_pixels, mismatch_pixels, penumbra_pixels;
    double ms_shadowmap, ms_filter_prep, ms_receiver, ms_total;
    double gt_noise_rmse;           /* the ground truth's own rms error over the mask */
    double gt_noise_penumbra_rmse;  /* ... over the penumbra band */
};

/* scored[i] = 1 where gt_mask is set and GL saw the same surface (camera
 * distances agree within METRICS_DEPTH_TOLERANCE); returns the number of
 * mismatch pixels: where exactly one of GL and the ray tracer hit geometry,
 * or both did at different distances. gl_distance and gt_distance are -1
 * where nothing was hit. */
long metrics_score_mask(const float *gt_mask, const float *gt_distance, const float *gl_distance,
                        int count, float *scored);

/* Fills every error metric (not the timings, not mismatch_pixels). Pixels
 * whose V_tech is not finite are counted in nonfinite and left out of the
 * error sums. v_gt_alt (may be NULL) is the ground truth with an independent
 * seed: rms(v_gt - v_gt_alt) / sqrt(2) is the noise floor. */
void metrics_compute(const float *v_tech, const float *v_gt, const float *v_gt_alt,
                     const float *scored, const float *gl_distance, int width, int height,
                     struct metrics *m);

cJSON *metrics_json(const struct metrics *m);

#endif
