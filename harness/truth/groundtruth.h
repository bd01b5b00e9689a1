/* The ground truth (docs/design.md §6, contract): at each camera-ray hit p, the
 * fraction of the area light above p's tangent plane that other geometry
 * does not hide, ray traced with Embree 3. The receiver's own horizon is
 * shading's business (N.L, the area-light integral), not shadowing's, so it
 * is reported apart (H, E) and left out of V. */
#ifndef SB_GROUNDTRUTH_H
#define SB_GROUNDTRUTH_H

#include "scene/light_frustum.h"
#include "scene/scene.h"

#include <stdatomic.h>
#include <stdbool.h>
#include <stdint.h>

/* Bump whenever anything that changes the ground truth's pixels changes:
 * it is part of the cache key. */
#define GT_VERSION 2

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
    bool trace_all;     /* trace every sample, none decided by cull.h: the same pixels, slower
                           (the tests compare the two) */
    bool quiet;         /* no progress line, even on a terminal */
    const atomic_bool *cancel;  /* optional: once it reads true the render stops early, its
                                   image incomplete (gt_render returns GT_CANCELLED) */
};

/* A scored pixel sees at least this fraction of the light above its
 * tangent plane: enough samples for a stable ratio (docs/design.md §6). */
#define GT_MIN_H 0.05f

struct gt_image {
    int width, height;
    float *v;           /* V_gt: of the light samples above p's tangent plane, the fraction
                           unblocked (0 where none is above) */
    float *v_weighted;  /* V_gt_weighted: the same samples weighted by cos*cos/r^2 (the sun's: cos theta_p) */
    float *h;           /* H: fraction of the light's area (the sun's solid angle) above the tangent plane */
    float *e;           /* E: unshadowed irradiance from a light of unit radiance */
    float *noise;       /* a sample of V's error: the two halves of the samples disagree by
                           this much, scaled so its rms over a region estimates V's rms
                           error there (gt_noise_floor) */
    float *distance;    /* camera-ray hit distance, -1 where the ray misses */
    float *mask;        /* 1: hit, H >= GT_MIN_H, inside the shadow-map frustum; else 0 */
    bool cached;        /* gt_obtain found it in the cache */
    double seconds, msamples_per_second;
    long long samples;      /* light samples resolved: above the horizon of a live pixel */
    long long shadow_rays;  /* of them, traced (the rest were decided without a ray, cull.h) */
};

enum gt_render_result {
    GT_RENDER_FAILED = -1,  /* logged */
    GT_RENDERED = 0,
    GT_CANCELLED = 1,       /* d->cancel stopped it: out is allocated but incomplete (free it) */
};

/* Renders on all cores, with progress on stderr (base/log.h). */
enum gt_render_result gt_render(const struct scene *s, const struct light_frustum *f, const struct gt_desc *d,
                                struct gt_image *out);

/* The ground truth of a run: read from cache_dir when an entry with the same
 * key exists (scene hash, size, N, seed, frustum, GT_VERSION) and records
 * that key itself, else rendered and stored there. cache_dir NULL: no
 * cache. Returns 0 or -1 (logged). */
int gt_obtain(const struct scene *s, const struct light_frustum *f, const struct gt_desc *d,
              const char *cache_dir, struct gt_image *out);

void gt_image_free(struct gt_image *g);

/* Releases the process's Embree device (made by the first gt_render). */
void gt_shutdown(void);

/* The noise floor (docs/design.md §6): the rms error of V over mask (1 =
 * counted), estimated as the rms of gt_image.noise; NAN over an empty mask. */
double gt_noise_floor(const float *noise, const float *mask, size_t count);

#endif
