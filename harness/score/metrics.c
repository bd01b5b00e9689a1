#include "metrics.h"
#include "base/util.h"
#include "truth/groundtruth.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

long metrics_score_mask(const float *gt_mask, const float *gt_distance, const float *gl_distance,
                        int count, float *scored)
{
    long mismatch = 0;
    for (int i = 0; i < count; i++) {
        bool gt_hit = gt_distance[i] >= 0.0f, gl_hit = gl_distance[i] >= 0.0f;
        bool agree = gt_hit == gl_hit &&
                     (!gt_hit || fabsf(gl_distance[i] - gt_distance[i]) <=
                                     METRICS_DEPTH_TOLERANCE * gt_distance[i]);
        mismatch += !agree;
        scored[i] = agree && gt_mask[i] > 0.5f ? 1.0f : 0.0f;
    }
    return mismatch;
}

/* Penumbra band of V_gt dilated by METRICS_PENUMBRA_DILATE, within scored. */
static void penumbra_mask(const float *v_gt, const float *scored, int width, int height,
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

static int cmp_float(const void *a, const void *b)
{
    float x = *(const float *)a, y = *(const float *)b;
    return (x > y) - (x < y);
}

void metrics_compute(const float *v_tech, const float *v_gt, const float *v_gt_alt,
                     const float *scored, const float *gl_distance, int width, int height,
                     struct metrics *m)
{
    size_t count = (size_t)width * (size_t)height;
    float *band = xmalloc(count * sizeof(float));
    penumbra_mask(v_gt, scored, width, height, band);
    float *abs_err = xmalloc(count * sizeof(float));

    double sum2 = 0, sum_abs = 0, sum = 0, max_abs = 0, pen2 = 0;
    long n = 0, pen = 0, leak = 0, dark = 0, nonfinite = 0, scored_n = 0;
    for (size_t i = 0; i < count; i++) {
        bool finite = isfinite(v_tech[i]);
        if (!finite && gl_distance[i] >= 0.0f)
            nonfinite++;
        if (scored[i] < 0.5f)
            continue;
        scored_n++;
        if (!finite)
            continue;
        double e = (double)v_tech[i] - (double)v_gt[i], a = fabs(e);
        sum += e, sum_abs += a, sum2 += e * e;
        max_abs = fmax(max_abs, a);
        abs_err[n++] = (float)a;
        if (band[i] > 0.5f)
            pen2 += e * e, pen++;
        leak += v_gt[i] < 0.05f && v_tech[i] > 0.25f;
        dark += v_gt[i] > 0.95f && v_tech[i] < 0.75f;
    }
    double p99 = 0;
    if (n > 0) {  /* nearest rank: the smallest value >= 99% of the errors */
        qsort(abs_err, (size_t)n, sizeof(float), cmp_float);
        long rank = (long)ceil(0.99 * (double)n);
        p99 = abs_err[rank > 0 ? rank - 1 : 0];
    }
    struct metrics r = {
        .rmse = n ? sqrt(sum2 / n) : 0,
        .mae = n ? sum_abs / n : 0,
        .bias = n ? sum / n : 0,
        .max_abs = max_abs,
        .p99_abs = p99,
        .penumbra_rmse = pen ? sqrt(pen2 / pen) : 0,
        .leak_fraction = scored_n ? (double)leak / scored_n : 0,
        .dark_fraction = scored_n ? (double)dark / scored_n : 0,
        .nonfinite = nonfinite,
        .scored_pixels = scored_n,
        .mismatch_pixels = m->mismatch_pixels,
        .penumbra_pixels = pen,
        .ms_shadowmap = m->ms_shadowmap,
        .ms_filter_prep = m->ms_filter_prep,
        .ms_receiver = m->ms_receiver,
        .ms_total = m->ms_total,
        .gt_noise_rmse = v_gt_alt ? gt_noise_floor(v_gt, v_gt_alt, scored, count) : 0,
        .gt_noise_penumbra_rmse = v_gt_alt ? gt_noise_floor(v_gt, v_gt_alt, band, count) : 0,
    };
    *m = r;
    free(abs_err);
    free(band);
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
