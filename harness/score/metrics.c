#include "metrics.h"
#include "base/util.h"
#include "truth/groundtruth.h"

#include <cjson/cJSON.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Whether the truth's distances along one axis break at c (its neighbours
 * a and b, either of which may be missing: NaN). Both there: the second
 * difference of 1 / distance, which is all but 0 on a plane seen at any
 * angle (1 / depth is affine in screen space there; the ray's length
 * adds a curvature of the pixel's angular size squared) and on a smooth
 * surface, and of the order of 1 across a jump. One there: the jump to it. */
static bool breaks(float a, float c, float b)
{
    if (isnan(a) || isnan(b)) {
        const float e = isnan(a) ? b : a;
        return !isnan(e) && fabsf(e - c) > METRICS_SILHOUETTE_JUMP * c;
    }
    return fabsf(c / a + c / b - 2.0f) > METRICS_SILHOUETTE_JUMP;
}

bool metrics_truth_silhouette(const float *gt_distance, int width, int height, int x, int y)
{
    const size_t i = (size_t)y * (size_t)width + (size_t)x, w = (size_t)width;
    const float c = gt_distance[i];
    for (int dy = -1; dy <= 1; dy++)  /* a neighbour the ray misses where this one hits, or the other way */
        for (int dx = -1; dx <= 1; dx++) {
            const int u = x + dx, v = y + dy;
            if (u >= 0 && v >= 0 && u < width && v < height &&
                (gt_distance[(size_t)v * w + (size_t)u] < 0) != (c < 0))
                return true;
        }
    if (c < 0)
        return false;
    const float left = x > 0 ? gt_distance[i - 1] : NAN, right = x + 1 < width ? gt_distance[i + 1] : NAN;
    const float up = y > 0 ? gt_distance[i - w] : NAN, down = y + 1 < height ? gt_distance[i + w] : NAN;
    return breaks(left, c, right) || breaks(up, c, down);
}

long metrics_score_mask(const float *gt_mask, const float *gt_distance, const float *gl_distance, int width,
                        int height, float depth_tolerance, float *scored)
{
    long mismatch = 0;
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            const size_t i = (size_t)y * (size_t)width + (size_t)x;
            const bool gt_hit = gt_distance[i] >= 0.0f, gl_hit = gl_distance[i] >= 0.0f;
            /* a wider tolerance never takes a silhouette in */
            const float tolerance = depth_tolerance > METRICS_DEPTH_TOLERANCE &&
                                            metrics_truth_silhouette(gt_distance, width, height, x, y)
                                        ? METRICS_DEPTH_TOLERANCE
                                        : depth_tolerance;
            const bool agree = gt_hit == gl_hit &&
                               (!gt_hit || fabsf(gl_distance[i] - gt_distance[i]) <= tolerance * gt_distance[i]);
            mismatch += !agree;
            scored[i] = agree && gt_mask[i] > 0.5f ? 1.0f : 0.0f;
        }
    return mismatch;
}

/* Penumbra band of V_gt dilated by METRICS_PENUMBRA_DILATE, within scored. */
void metrics_penumbra_band(const float *v_gt, const float *scored, int width, int height,
                          float *band)
{
    const int r = METRICS_PENUMBRA_DILATE;
    size_t count = (size_t)width * (size_t)height;
    unsigned char *core = xcalloc(count, 1);
    for (size_t i = 0; i < count; i++)
        core[i] = scored[i] > 0.5f && v_gt[i] > METRICS_PENUMBRA_LO && v_gt[i] < METRICS_PENUMBRA_HI;
    /* Square (Chebyshev) dilation, separable: rows, then columns. */
    unsigned char *rows = xcalloc(count, 1);
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            unsigned char any = 0;
            for (int k = x - r; k <= x + r && !any; k++)
                any = k >= 0 && k < width && core[(size_t)y * width + k];
            rows[(size_t)y * width + x] = any;
        }
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            unsigned char any = 0;
            for (int k = y - r; k <= y + r && !any; k++)
                any = k >= 0 && k < height && rows[(size_t)k * width + x];
            size_t i = (size_t)y * width + x;
            band[i] = any && scored[i] > 0.5f ? 1.0f : 0.0f;
        }
    free(rows);
    free(core);
}

/* The k-th smallest of a[0..n) (k from 0), a reordered: Hoare's
 * selection, linear on average where a sort was n log n (most of scoring's
 * time). The pivot is the middle element, so sorted input stays linear. */
static float select_kth(float *a, long n, long k)
{
    long lo = 0, hi = n - 1;
    while (lo < hi) {
        const float pivot = a[lo + (hi - lo) / 2];
        long i = lo, j = hi;
        while (i <= j) {
            while (a[i] < pivot)
                i++;
            while (a[j] > pivot)
                j--;
            if (i <= j) {
                float t = a[i];
                a[i++] = a[j], a[j--] = t;
            }
        }
        /* a[lo..j] <= pivot <= a[i..hi], and a[j+1..i-1] equal the pivot */
        if (k <= j)
            hi = j;
        else if (k >= i)
            lo = i;
        else
            break;
    }
    return a[k];
}

void metrics_compute(const float *v_tech, const struct gt_image *gt, const float *scored,
                     const float *gl_distance, struct metrics *m)
{
    const int width = gt->width, height = gt->height;
    const float *v_gt = gt->v;
    size_t count = (size_t)width * (size_t)height;
    float *band = xmalloc(count * sizeof(float));
    metrics_penumbra_band(v_gt, scored, width, height, band);
    float *abs_err = xmalloc(count * sizeof(float));

    double sum2 = 0, sum_abs = 0, sum = 0, max_abs = 0, pen2 = 0, shaded2 = 0, sum_e = 0;
    long n = 0, pen = 0, leak = 0, dark = 0, nonfinite = 0, scored_n = 0, terminator = 0;
    for (size_t i = 0; i < count; i++) {
        bool finite = isfinite(v_tech[i]);
        if (!finite && gl_distance[i] >= 0.0f)
            nonfinite++;
        if (scored[i] < 0.5f)
            continue;
        scored_n++;
        terminator += gt->h[i] < 1.0f;
        if (!finite)
            continue;
        double e = (double)v_tech[i] - (double)v_gt[i], a = fabs(e);
        sum += e, sum_abs += a, sum2 += e * e;
        max_abs = fmax(max_abs, a);
        abs_err[n++] = (float)a;
        if (band[i] > 0.5f)
            pen2 += e * e, pen++;
        leak += v_gt[i] < (float)METRICS_LEAK_GT && v_tech[i] > (float)METRICS_LEAK_TECH;
        dark += v_gt[i] > (float)METRICS_DARK_GT && v_tech[i] < (float)METRICS_DARK_TECH;
        double shaded = ((double)v_tech[i] - (double)gt->v_weighted[i]) * gt->e[i];
        shaded2 += shaded * shaded, sum_e += gt->e[i];
    }
    double p99 = NAN;
    if (n > 0) {  /* nearest rank: the smallest value >= 99% of the errors */
        long rank = (long)ceil(0.99 * (double)n);
        p99 = select_kth(abs_err, n, rank > 0 ? rank - 1 : 0);
    }
    const double none = NAN;
    struct metrics r = *m;  /* the timings and mismatch_pixels stay */
    r.rmse = n ? sqrt(sum2 / n) : none;
    r.mae = n ? sum_abs / n : none;
    r.bias = n ? sum / n : none;
    r.max_abs = n ? max_abs : none;
    r.p99_abs = p99;
    r.penumbra_rmse = pen ? sqrt(pen2 / pen) : none;
    r.leak_fraction = n ? (double)leak / scored_n : none;
    r.dark_fraction = n ? (double)dark / scored_n : none;
    /* (V_tech - V_gt_weighted) E over mean E: the shaded image's error
     * relative to its mean brightness (docs/design.md §7). */
    r.shaded_rmse = n && sum_e > 0 ? sqrt(shaded2 / n) / (sum_e / n) : none;
    r.nonfinite = nonfinite;
    r.scored_pixels = scored_n;
    r.terminator_pixels = terminator;
    r.penumbra_pixels = pen;
    r.gt_noise_rmse = n ? gt_noise_floor(gt->noise, scored, count) : none;
    r.gt_noise_penumbra_rmse = pen ? gt_noise_floor(gt->noise, band, count) : none;
    *m = r;
    free(abs_err);
    free(band);
}

bool metrics_scored(const struct metrics *m)
{
    return !isnan(m->rmse);
}

void metrics_none(struct metrics *m)
{
#define X(key, type, format, in_report, help) m->key = _Generic(m->key, double: NAN, default: 0);
    METRICS(X)
#undef X
}

const struct metric_info metric_info[METRIC_COUNT] = {
#define X(key, type, format, in_report, help) {#key, format, help, in_report},
    METRICS(X)
#undef X
};

double metrics_value(const struct metrics *m, int k)
{
    switch (k) {
#define X(key, type, format, in_report, help) case METRIC_##key: return (double)m->key;
        METRICS(X)
#undef X
    }
    return NAN;
}

int metrics_read_json(const cJSON *j, struct metrics *m)
{
    long whole;
#define X(key, type, format, in_report, help)                                                           \
    if ((type)0.5 == 0) { /* a count */                                                                 \
        if (!util_json_whole(j, #key, 0, 1e15, &whole))                                                 \
            return -1;                                                                                  \
        m->key = (type)whole;                                                                           \
    } else {                                                                                            \
        const cJSON *v = cJSON_GetObjectItem(j, #key);                                                  \
        if (!cJSON_IsNumber(v) && !cJSON_IsNull(v))                                                     \
            return -1;                                                                                  \
        m->key = (type)util_json_number(j, #key);                                                       \
    }
    METRICS(X)
#undef X
    return 0;
}

void metrics_cost(double fetches, long covered, long expensive, const float *shortcut, const struct gt_image *gt,
                  const float *scored, int count, struct metrics *m)
{
    m->fetches_per_pixel = covered ? fetches / (double)covered : NAN;
    m->expensive_fraction = covered ? (double)expensive / (double)covered : NAN;
    long decided = 0, in_band = 0;
    for (int i = 0; i < count; i++)
        if (scored[i] != 0 && shortcut[i] != 0) {
            decided++;
            in_band += gt->v[i] > METRICS_PENUMBRA_LO && gt->v[i] < METRICS_PENUMBRA_HI;
        }
    m->misclassified_fraction = decided ? (double)in_band / (double)decided : NAN;
}
