/* Temporal stability (`shadowbench stability --motion`): how much a
 * technique's error changes from frame to frame beyond what the truth's
 * own change explains. With e_t = V_tech,t - V_gt,t at a pixel,
 * |ΔV_tech - ΔV_gt| = |e_t - e_(t-1)|: the flicker a viewer sees on that
 * pixel, which a still error (a constant offset) does not cause.
 *
 * Pixels: a pair of frames counts a pixel scored in both frames; one scored
 * in one frame only (it entered or left the mask: the camera or the frustum
 * moved) is left out and counted in mask_changes. The ground truth's own
 * frame-to-frame noise, estimated the same way from its per-pixel noise
 * samples (two halves of its light samples, groundtruth.h), is the floor:
 * a flicker at or below it is not a meaningful number. */
#ifndef SB_FLICKER_H
#define SB_FLICKER_H

#include "scene/scene.h"

#include <stdbool.h>
#include <stddef.h>

struct flicker {
    double *d;         /* |e_t - e_(t-1)| of every counted pixel of every pair */
    size_t count, capacity;
    double floor_sum;  /* sum of |noise_t - noise_(t-1)| over the same pixels */
    double band_sum, band_floor_sum;  /* the same two sums over the penumbra band's pixels */
    long band_count;
    long mask_changes; /* pixels scored in one frame of a pair only */
    double rmse_sum, rmse_max;  /* of the rmse of each frame with pixels scored */
    double rmse_last, rmse_jump;  /* the last such frame's rmse; the largest change from one to the next */
    double *frame_rmse;           /* each frame's rmse (NAN: nothing scored), frames of them */
    int frames, scored_frames;  /* frames added; of them, with pixels scored */
    float *prev_e, *prev_noise, *prev_scored, *prev_gt;  /* the last frame's */
};

/* The summary of a run of frames. */
struct flicker_result {
    double flicker;      /* mean |e_t - e_(t-1)| over the counted pixels: NAN if none */
    double flicker_p99;  /* its 99th percentile (nearest rank) */
    double floor;        /* the ground truth's: mean |noise_t - noise_(t-1)| */
    double flicker_penumbra, floor_penumbra;  /* both over the pixels where V_gt is in the penumbra band
                                                 (METRICS_PENUMBRA_LO..HI, undilated) in either frame of
                                                 the pair: where edges move. NAN if none */
    bool meaningful;     /* flicker > floor */
    double rmse_mean, rmse_max;  /* over the frames with pixels scored (each frame's rmse over them) */
    double rmse_jump;    /* the largest change of that rmse from a frame to the next: a pop (a caster
                            crossing a cascade split) stands out of a steady crawl. NAN: one frame */
    long pairs_pixels, band_pixels, mask_changes;
    int frames, scored_frames;  /* scored_frames < frames: some frame had nothing to score */
};

/* Adds frame t: V_tech, V_gt, the ground truth's noise sample and the
 * scored mask (1 = scored), count pixels each. from (flicker_reproject;
 * NULL: each pixel itself) gives the last frame's pixel that saw the same
 * point: a moving camera's pixels are compared on the surface they see, so
 * what counts is a shadow crawling over it (shimmer), not the image
 * moving. A pixel with none (-1) counts in mask_changes when scored. */
void flicker_add(struct flicker *f, const float *v_tech, const float *v_gt, const float *noise,
                 const float *scored, const int *from, size_t count);

/* Sorts f's differences (for the percentile). */
void flicker_finish(struct flicker *f, struct flicker_result *r);

void flicker_free(struct flicker *f);

/* The exponential moving average that temporal accumulation (TAA) keeps:
 * history = alpha * v + (1 - alpha) * history[from[i]], where from[i] is the
 * pixel of the last frame that pixel i saw (reprojection), or -1 (no
 * history there: history = v). */
void flicker_accumulate(float *history, const float *prev_history, const float *v, const int *from,
                        float alpha, size_t count);

/* from[i]: the pixel of the last frame (camera prev) that pixel i of this
 * frame (camera now) sees, or -1: the accumulation's reprojection, from the
 * GL camera distances of w x h images (-1 where no geometry). A pixel whose
 * point the last frame saw at another distance (it was hidden, or is new)
 * has none. */
void flicker_reproject(const struct scene_camera *now, const struct scene_camera *prev, const float *dist_now,
                       const float *dist_prev, int w, int h, int *from);

#endif
