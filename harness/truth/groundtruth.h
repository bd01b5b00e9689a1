/* The ground truth (DESIGN.md §6, contract): the visible fraction of the
 * area light at each camera-ray hit, ray traced with Embree 3. */
#ifndef SB_GROUNDTRUTH_H
#define SB_GROUNDTRUTH_H

#include "scene/light_frustum.h"
#include "scene/scene.h"

#include <stdbool.h>
#include <stdint.h>

/* Bump whenever anything that changes the ground truth's pixels changes:
 * it is part of the cache key. */
#define GT_VERSION 1

/* Shadow-ray origins are offset along the normal by this fraction of the
 * scene's bounding-box diagonal. */
#define GT_OFFSET_SCALE 1e-4f

#define GT_DEFAULT_SAMPLES 1024
#define GT_MAX_SAMPLES 65536

/* Zero means default (samples, seed); the image size is required. */
struct gt_desc {
    int width, height;  /* pixels */
    int samples;        /* N light samples per pixel, a square n*n, default GT_DEFAULT_SAMPLES */
    uint32_t seed;      /* default 1 */
};

struct gt_image {
    int width, height;
    float *v;           /* V_gt: unweighted visible fraction of the light's area */
    float *v_weighted;  /* V_gt_weighted: cos*cos/r^2 weighted visibility ratio */
    float *distance;    /* camera-ray hit distance, -1 where the ray misses */
    float *mask;        /* 1: hit, faces the light, inside the shadow-map frustum; else 0 */
    float *v_alt;       /* V_gt again with seed + 1 (gt_obtain only): the noise floor */
    bool cached;        /* gt_obtain found it in the cache */
    double seconds, mrays_per_second;
    long long shadow_rays;
};

/* Renders on all cores, with progress on stderr when it is a terminal.
 * Returns 0 or -1 (logged). */
int gt_render(const struct scene *s, const struct light_frustum *f, const struct gt_desc *d,
              struct gt_image *out);

/* The ground truth of a run: read from cache_dir when an entry with the same
 * key exists (scene hash, size, N, seed, frustum, GT_VERSION), else rendered
 * twice (seed and seed + 1, the second for the noise floor) and stored there.
 * cache_dir NULL: no cache. Returns 0 or -1 (logged). */
int gt_obtain(const struct scene *s, const struct light_frustum *f, const struct gt_desc *d,
              const char *cache_dir, struct gt_image *out);

void gt_image_free(struct gt_image *g);

/* Releases the process's Embree device (made by the first gt_render). */
void gt_shutdown(void);

/* The noise floor (DESIGN.md §6): the rms error of one ground-truth image
 * over mask (1 = counted), estimated from two renderings with independent
 * seeds as rms(v - v_alt) / sqrt(2). */
double gt_noise_floor(const float *v, const float *v_alt, const float *mask, size_t count);

#endif
