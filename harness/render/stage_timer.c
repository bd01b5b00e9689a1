#include "stage_timer.h"
#include "base/util.h"

#include <stdlib.h>

enum { STAGE_SHADOWMAP, STAGE_FILTER_PREP, STAGE_RECEIVER, STAGE_COUNT };

/* One frame of a cell with request r, its stages' ms added to ms (may be
 * NULL: untimed). */
static void frame(const struct stage_timer *t, const struct stage_timer_cell *c,
                  const struct shadowmap_request *r, double ms[STAGE_COUNT])
{
    for (int p = 0; p < SM_PRODUCT_COUNT; p++)
        if (r->products & (1u << p)) {
            double t0 = util_now_ms();
            shadowmap_render_product(t->sm, t->mesh, p, r);
            glFinish();
            if (ms)
                ms[p == SM_PRODUCT_DEPTH ? STAGE_SHADOWMAP : STAGE_FILTER_PREP] += util_now_ms() - t0;
        }
    double t0 = util_now_ms();
    receiver_render(t->receiver, c->program, t->mesh, t->sm);
    glFinish();
    if (ms)
        ms[STAGE_RECEIVER] += util_now_ms() - t0;
}

static int request(const struct stage_timer *t, const struct stage_timer_cell *c,
                   struct shadowmap_request *r)
{
    technique_request(c->technique, c->settings, &t->sm->frustum, t->sm->desc.size_texels, r);
    return shadowmap_prepare(t->sm, r);
}

int stage_timer_run(const struct stage_timer *t, const struct stage_timer_cell *cells, int n,
                    struct stage_times *out)
{
    const int frames = t->frames < STAGE_TIMER_MAX_FRAMES ? t->frames : STAGE_TIMER_MAX_FRAMES;
    struct shadowmap_request *requests = xcalloc((size_t)n, sizeof *requests);
    /* samples[(i * STAGE_COUNT + stage) * frames + f], and the frames' totals */
    double *samples = xcalloc((size_t)n * STAGE_COUNT * (size_t)frames, sizeof(double));
    double *totals = xcalloc((size_t)frames, sizeof(double));
    int rc = 0;
    for (int i = 0; i < n && !rc; i++)
        rc = request(t, &cells[i], &requests[i]);
    glFinish();
    const int rounds = t->warmup + frames;
    for (int k = 0; k < rounds && !rc; k++) {
        const int f = k - t->warmup;  /* < 0: a warm-up round */
        for (int i = 0; i < n; i++) {
            double ms[STAGE_COUNT] = {0};
            frame(t, &cells[i], &requests[i], ms);
            for (int s = 0; s < STAGE_COUNT && f >= 0; s++)
                samples[(i * STAGE_COUNT + s) * frames + f] = ms[s];
        }
        if (t->on_round)
            t->on_round(t->user, k + 1, rounds);
    }
    for (int i = 0; i < n && !rc; i++) {
        double *stage = &samples[i * STAGE_COUNT * frames];
        for (int f = 0; f < frames; f++)
            totals[f] = stage[f] + stage[frames + f] + stage[2 * frames + f];
        out[i] = (struct stage_times){
            .shadowmap_ms = util_quantile(stage, frames, 0.5),
            .filter_prep_ms = util_quantile(stage + frames, frames, 0.5),
            .receiver_ms = util_quantile(stage + 2 * frames, frames, 0.5),
            .total_ms = util_quantile(totals, frames, 0.5),
            .total_q1_ms = util_quantile(totals, frames, 0.25),
            .total_q3_ms = util_quantile(totals, frames, 0.75),
        };
    }
    free(totals);
    free(samples);
    free(requests);
    return rc;
}

int stage_timer_render(const struct stage_timer *t, const struct stage_timer_cell *c)
{
    struct shadowmap_request r;
    if (request(t, c, &r) != 0)
        return -1;
    frame(t, c, &r, NULL);
    return 0;
}
