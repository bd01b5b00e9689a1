#include "depth_metrics.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct sums {
    double e2, pen2, noise2;
    long n, pen;
};

static void add(struct sums *s, double e, bool in_band, double noise)
{
    s->e2 += e * e, s->n++;
    if (in_band)
        s->pen2 += e * e, s->noise2 += noise * noise, s->pen++;
}

static struct depth_group group(float lo, float hi, const struct sums *s)
{
    return (struct depth_group){lo, hi, s->n ? sqrt(s->e2 / s->n) : NAN, s->pen ? sqrt(s->pen2 / s->pen) : NAN,
                                s->pen ? sqrt(s->noise2 / s->pen) : NAN, s->n, s->pen};
}

void depth_metrics_compute(const float *v_tech, const struct gt_image *gt, const float *scored,
                           const float *view_depth, const float *z, const float *band, int slices,
                           struct depth_metrics *d)
{
    const size_t count = (size_t)gt->width * (size_t)gt->height;
    float *pen = xmalloc(sizeof(float) * count);
    metrics_penumbra_band(gt->v, scored, gt->width, gt->height, pen);
    float lo = INFINITY, hi = 0;
    for (size_t i = 0; i < count; i++)
        if (scored[i] > 0.5f && view_depth[i] > 0)
            lo = fminf(lo, view_depth[i]), hi = fmaxf(hi, view_depth[i]);
    *d = (struct depth_metrics){.slices = slices};
    struct sums bins[DEPTH_BINS] = {{0}}, slice[CASCADES_MAX] = {{0}}, near[CASCADES_MAX] = {{0}},
                far[CASCADES_MAX] = {{0}};
    const bool any = hi > lo;
    d->bins = any ? DEPTH_BINS : 0;
    const double log_lo = log(lo), step = any ? (log(hi) - log_lo) / DEPTH_BINS : 0;
    for (size_t i = 0; i < count; i++) {
        const float vz = view_depth[i];
        if (scored[i] < 0.5f || !(vz > 0) || !isfinite(v_tech[i]))
            continue;
        const double e = (double)v_tech[i] - (double)gt->v[i], noise = gt->noise[i];
        const bool in_band = pen[i] > 0.5f;
        if (any) {
            int b = (int)((log(vz) - log_lo) / step);
            add(&bins[b < 0 ? 0 : b >= DEPTH_BINS ? DEPTH_BINS - 1 : b], e, in_band, noise);
        }
        int c = 0;
        while (c < slices - 1 && vz > z[c + 1])
            c++;
        add(&slice[c], e, in_band, noise);
        for (int k = 1; k < slices; k++) {  /* the seams: split k between slices k - 1 and k */
            const float w = DEPTH_SEAM_WIDTH * z[k], inner = z[k] - band[k - 1];
            if (vz >= inner - w && vz < inner)
                add(&near[k - 1], e, in_band, noise);
            else if (vz >= z[k] && vz < z[k] + w)
                add(&far[k - 1], e, in_band, noise);
        }
    }
    for (int b = 0; b < d->bins; b++)
        d->bin[b] = group((float)exp(log_lo + step * b), (float)exp(log_lo + step * (b + 1)), &bins[b]);
    for (int c = 0; c < slices; c++)
        d->slice[c] = group(z[c], z[c + 1], &slice[c]);
    for (int k = 1; k < slices; k++) {
        struct depth_seam *s = &d->seam[k - 1];
        const float w = DEPTH_SEAM_WIDTH * z[k], inner = z[k] - band[k - 1];
        s->at = z[k];
        s->near = group(inner - w, inner, &near[k - 1]);
        s->far = group(z[k], z[k] + w, &far[k - 1]);
        s->seam = fabs(s->far.penumbra_rmse - s->near.penumbra_rmse);
        s->gt_seam = fabs(s->far.gt_noise_penumbra_rmse - s->near.gt_noise_penumbra_rmse);
    }
    free(pen);
}

static cJSON *group_json(const struct depth_group *g)
{
    cJSON *o = cJSON_CreateObject();
    util_json_add_number(o, "from", g->lo);
    util_json_add_number(o, "to", g->hi);
    util_json_add_number(o, "rmse", g->rmse);
    util_json_add_number(o, "penumbra_rmse", g->penumbra_rmse);
    util_json_add_number(o, "gt_noise_penumbra_rmse", g->gt_noise_penumbra_rmse);
    cJSON_AddNumberToObject(o, "pixels", (double)g->pixels);
    cJSON_AddNumberToObject(o, "penumbra_pixels", (double)g->penumbra_pixels);
    return o;
}

cJSON *depth_metrics_json(const struct depth_metrics *d)
{
    cJSON *o = cJSON_CreateObject();
    cJSON *bins = cJSON_AddArrayToObject(o, "distance_bins");
    for (int b = 0; b < d->bins; b++)
        cJSON_AddItemToArray(bins, group_json(&d->bin[b]));
    cJSON *slices = cJSON_AddArrayToObject(o, "slices");
    for (int c = 0; c < d->slices; c++)
        cJSON_AddItemToArray(slices, group_json(&d->slice[c]));
    cJSON *seams = cJSON_AddArrayToObject(o, "seams");
    for (int k = 0; k + 1 < d->slices; k++) {
        const struct depth_seam *s = &d->seam[k];
        cJSON *j = cJSON_CreateObject();
        util_json_add_number(j, "at", s->at);
        util_json_add_number(j, "seam", s->seam);
        util_json_add_number(j, "gt_seam", s->gt_seam);
        cJSON_AddItemToObject(j, "near", group_json(&s->near));
        cJSON_AddItemToObject(j, "far", group_json(&s->far));
        cJSON_AddItemToArray(seams, j);
    }
    return o;
}

static int group_read(const cJSON *o, struct depth_group *g)
{
    g->lo = (float)util_json_number(o, "from"), g->hi = (float)util_json_number(o, "to");
    g->rmse = util_json_number(o, "rmse"), g->penumbra_rmse = util_json_number(o, "penumbra_rmse");
    g->gt_noise_penumbra_rmse = util_json_number(o, "gt_noise_penumbra_rmse");
    return util_json_whole(o, "pixels", 0, 1e15, &g->pixels) &&
                   util_json_whole(o, "penumbra_pixels", 0, 1e15, &g->penumbra_pixels)
               ? 0 : -1;
}

int depth_metrics_read(const cJSON *j, struct depth_metrics *d)
{
    const cJSON *bins = cJSON_GetObjectItem(j, "distance_bins"), *slices = cJSON_GetObjectItem(j, "slices"),
                *seams = cJSON_GetObjectItem(j, "seams");
    memset(d, 0, sizeof *d);
    d->bins = cJSON_GetArraySize(bins), d->slices = cJSON_GetArraySize(slices);
    if (!cJSON_IsArray(bins) || !cJSON_IsArray(slices) || !cJSON_IsArray(seams) || d->bins > DEPTH_BINS ||
        d->slices > CASCADES_MAX || cJSON_GetArraySize(seams) != (d->slices ? d->slices - 1 : 0))
        return -1;
    int rc = 0;
    for (int b = 0; b < d->bins; b++)
        rc |= group_read(cJSON_GetArrayItem(bins, b), &d->bin[b]);
    for (int c = 0; c < d->slices; c++)
        rc |= group_read(cJSON_GetArrayItem(slices, c), &d->slice[c]);
    for (int k = 0; k + 1 < d->slices; k++) {
        const cJSON *s = cJSON_GetArrayItem(seams, k);
        d->seam[k].at = (float)util_json_number(s, "at");
        d->seam[k].seam = util_json_number(s, "seam"), d->seam[k].gt_seam = util_json_number(s, "gt_seam");
        rc |= group_read(cJSON_GetObjectItem(s, "near"), &d->seam[k].near);
        rc |= group_read(cJSON_GetObjectItem(s, "far"), &d->seam[k].far);
    }
    return rc ? -1 : 0;
}
