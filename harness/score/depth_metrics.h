/* The error by view depth (docs/metrics.md, docs/cascades.md): per
 * distance bin from the camera (perspective aliasing: texels grow with
 * distance), per cascade slice, and the seam at each split, where
 * resolution or softness may jump. metrics.json's "depth" object. */
#ifndef SB_DEPTH_METRICS_H
#define SB_DEPTH_METRICS_H

#include "metrics.h"
#include "scene/light_frustum.h"

#include <cjson/cJSON.h>

#define DEPTH_BINS 8            /* distance bins, log-spaced over the scored view depths */
#define DEPTH_SEAM_WIDTH 0.1f   /* a seam's band on each side of its split: this fraction of the
                                   split's view depth (past the blend band on the near side) */

/* rms of e and of the truth's noise over a set of pixels; NAN when empty. */
struct depth_group {
    float lo, hi;                  /* view depths */
    double rmse, penumbra_rmse;    /* over the scored pixels, over those of the penumbra band */
    double gt_noise_penumbra_rmse; /* the truth's own over the band */
    long pixels, penumbra_pixels;
};

/* A split's seam: the jump of the penumbra band's rms error across it,
 * |far - near|, against the truth's own (the same jump of its noise). */
struct depth_seam {
    float at;                      /* the split's view depth */
    struct depth_group near, far;  /* the bands on either side */
    double seam, gt_seam;          /* NAN when a side has no penumbra pixel */
};

struct depth_metrics {
    int bins, slices;
    struct depth_group bin[DEPTH_BINS];
    struct depth_group slice[CASCADES_MAX];
    struct depth_seam seam[CASCADES_MAX - 1];
};

/* Fills d from V_tech, the truth and the scored mask, the pixels' view
 * depths (-1: none) and the slices z[0..slices] with each one's blend band
 * (slices 1: no seam). */
void depth_metrics_compute(const float *v_tech, const struct gt_image *gt, const float *scored,
                           const float *view_depth, const float *z, const float *band, int slices,
                           struct depth_metrics *d);

/* As metrics.json's "depth" object. */
cJSON *depth_metrics_json(const struct depth_metrics *d);

/* d from such an object (null: NaN). Returns 0, or -1 when j is not one. */
int depth_metrics_read(const cJSON *j, struct depth_metrics *d);

#endif
