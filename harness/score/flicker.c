#include "flicker.h"
#include "metrics.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void flicker_add(struct flicker *f, const float *v_tech, const float *v_gt, const float *noise,
                 const float *scored, const int *from, size_t count)
{
    if (!f->prev_e) {
        f->prev_e = xmalloc(sizeof(float) * count);
        f->prev_noise = xmalloc(sizeof(float) * count);
        f->prev_scored = xmalloc(sizeof(float) * count);
        f->prev_gt = xmalloc(sizeof(float) * count);
    }
    double sum = 0;
    long n = 0;
    for (size_t i = 0; i < count; i++) {
        const float e = v_tech[i] - v_gt[i];
        const bool now = scored[i] > 0.5f && isfinite(e);
        if (now)
            sum += (double)e * e, n++;
        if (f->frames == 0)
            continue;
        const long j = from ? from[i] : (long)i;  /* the last frame's pixel of the same point */
        const bool before = j >= 0 && f->prev_scored[j] > 0.5f;
        if (now && before) {
            if (f->count == f->capacity) {
                f->capacity = f->capacity ? 2 * f->capacity : count;
                f->d = xrealloc(f->d, sizeof(double) * f->capacity);
            }
            const double d = fabs((double)e - f->prev_e[j]), fl = fabs((double)noise[i] - f->prev_noise[j]);
            f->d[f->count++] = d;
            f->floor_sum += fl;
            if ((v_gt[i] > METRICS_PENUMBRA_LO && v_gt[i] < METRICS_PENUMBRA_HI) ||
                (f->prev_gt[j] > METRICS_PENUMBRA_LO && f->prev_gt[j] < METRICS_PENUMBRA_HI))
                f->band_sum += d, f->band_floor_sum += fl, f->band_count++;
        } else if (now != before) {
            f->mask_changes++;
        }
    }
    for (size_t i = 0; i < count; i++) {  /* after: a pixel may read another's last value */
        const float e = v_tech[i] - v_gt[i];
        f->prev_e[i] = e, f->prev_noise[i] = noise[i];
        f->prev_scored[i] = scored[i] > 0.5f && isfinite(e) ? 1.0f : 0.0f;
        f->prev_gt[i] = v_gt[i];
    }
    f->frame_rmse = xrealloc(f->frame_rmse, sizeof(double) * (size_t)(f->frames + 1));
    f->frame_rmse[f->frames] = n ? sqrt(sum / (double)n) : NAN;
    if (n) {
        const double rmse = sqrt(sum / (double)n);
        f->rmse_sum += rmse;
        f->rmse_max = f->scored_frames ? fmax(f->rmse_max, rmse) : rmse;
        if (f->scored_frames)
            f->rmse_jump = fmax(f->rmse_jump, fabs(rmse - f->rmse_last));
        f->rmse_last = rmse;
        f->scored_frames++;
    }
    f->frames++;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

void flicker_finish(struct flicker *f, struct flicker_result *r)
{
    memset(r, 0, sizeof *r);
    r->frames = f->frames;
    r->pairs_pixels = (long)f->count;
    r->mask_changes = f->mask_changes;
    r->scored_frames = f->scored_frames;
    r->rmse_mean = f->scored_frames ? f->rmse_sum / f->scored_frames : NAN;
    r->rmse_max = f->scored_frames ? f->rmse_max : NAN;
    r->rmse_jump = f->scored_frames > 1 ? f->rmse_jump : NAN;
    r->band_pixels = f->band_count;
    r->flicker_penumbra = f->band_count ? f->band_sum / (double)f->band_count : NAN;
    r->floor_penumbra = f->band_count ? f->band_floor_sum / (double)f->band_count : NAN;
    if (!f->count) {
        r->flicker = r->flicker_p99 = r->floor = NAN;
        return;
    }
    double sum = 0;
    for (size_t i = 0; i < f->count; i++)
        sum += f->d[i];
    r->flicker = sum / (double)f->count;
    r->floor = f->floor_sum / (double)f->count;
    r->meaningful = r->flicker > r->floor;
    /* nearest rank, as the metrics' p99_abs: the smallest value >= 99% of them */
    qsort(f->d, f->count, sizeof *f->d, cmp_double);
    const size_t rank = (size_t)ceil(0.99 * (double)f->count);
    r->flicker_p99 = f->d[rank ? rank - 1 : 0];
}

void flicker_free(struct flicker *f)
{
    free(f->d), free(f->prev_e), free(f->prev_noise), free(f->prev_scored), free(f->prev_gt), free(f->frame_rmse);
    memset(f, 0, sizeof *f);
}

void flicker_accumulate(float *history, const float *prev_history, const float *v, const int *from,
                        float alpha, size_t count)
{
    for (size_t i = 0; i < count; i++)
        history[i] = from[i] >= 0 ? prev_history[from[i]] + alpha * (v[i] - prev_history[from[i]]) : v[i];
    /* (in that form a still pixel stays exactly still: h + a (h - h) = h) */
}

void flicker_reproject(const struct scene_camera *now, const struct scene_camera *prev, const float *dist_now,
                       const float *dist_prev, int w, int h, int *from)
{
    const float ty = tanf(0.5f * now->yfov_rad), tx = ty * (float)w / (float)h;
    const float py_ = tanf(0.5f * prev->yfov_rad), px_ = py_ * (float)w / (float)h;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const int i = y * w + x;
            from[i] = -1;
            if (dist_now[i] < 0)
                continue;
            const float sx = (2 * (x + 0.5f) / (float)w - 1) * tx, sy = (1 - 2 * (y + 0.5f) / (float)h) * ty;
            const struct vec3 dir = v3_normalize(
                v3_add(v3_scale(now->z, -1), v3_add(v3_scale(now->x, sx), v3_scale(now->y, sy))));
            const struct vec3 q = v3_sub(v3_add(now->pos, v3_scale(dir, dist_now[i])), prev->pos);
            const float qz = -v3_dot(q, prev->z);
            if (!(qz > 0))
                continue;
            const float fx = (v3_dot(q, prev->x) / qz / px_ + 1) * 0.5f * (float)w;
            const float fy = (1 - v3_dot(q, prev->y) / qz / py_) * 0.5f * (float)h;
            if (!(fx >= 0 && fx < (float)w && fy >= 0 && fy < (float)h))
                continue;
            const int j = (int)fy * w + (int)fx;
            const float expected = v3_length(q);
            if (dist_prev[j] >= 0 && fabsf(dist_prev[j] - expected) <= 1e-2f * expected)
                from[i] = j;
        }
}
