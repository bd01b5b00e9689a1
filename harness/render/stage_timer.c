#include "stage_timer.h"
#include "base/util.h"
#include "gl/gl_context.h"

#include <stdlib.h>
#include <string.h>

enum { STAGE_SHADOWMAP, STAGE_FILTER_PREP, STAGE_MASK, STAGE_RECEIVER, STAGE_DENOISE, STAGE_COUNT };

static const char *const timing_names[] = {"auto", "wall", "query"};

int stage_timing_parse(const char *name, enum stage_timing *out)
{
    for (int m = 0; m < 3; m++)
        if (strcmp(name, timing_names[m]) == 0) {
            *out = (enum stage_timing)m;
            return 0;
        }
    return -1;
}

enum stage_timing stage_timing_resolve(enum stage_timing m)
{
    return m != STAGE_TIMING_AUTO ? m : gl_context_is_cpu() ? STAGE_TIMING_WALL : STAGE_TIMING_QUERY;
}

const char *stage_timing_text(enum stage_timing m)
{
    if (m == STAGE_TIMING_AUTO && strcmp(gl_context_renderer(), "none") == 0)
        return "auto (no GL context yet)";  /* run.json before the context: decided with it */
    return stage_timing_resolve(m) == STAGE_TIMING_QUERY ? "GL_TIME_ELAPSED queries"
                                                          : "wall clock around glFinish";
}

/* A stage's timing: begun, then its ms (query: GL_TIME_ELAPSED, which the
 * read waits for; wall: glFinish, then the clock). */
struct stage_clock {
    GLuint query;  /* 0: wall clock */
    double t0;
};

static void stage_begin(struct stage_clock *k)
{
    if (k->query)
        glBeginQuery(GL_TIME_ELAPSED, k->query);
    k->t0 = util_now_ms();
}

static double stage_end(struct stage_clock *k)
{
    if (!k->query) {
        glFinish();
        return util_now_ms() - k->t0;
    }
    glEndQuery(GL_TIME_ELAPSED);
    GLuint64 ns = 0;
    glGetQueryObjectui64v(k->query, GL_QUERY_RESULT, &ns);
    return (double)ns * 1e-6;
}

/* One timed frame of a cell with requests r (one per cascade), its stages'
 * ms added to ms by clock k: every product of every cascade rendered
 * afresh (a frame's cost is all of its work), then the screen-space stages
 * and the receiver pass, each timed only where the cell has it. */
static void timed_frame(const struct stage_timer *t, const struct stage_timer_cell *c,
                        const struct shadowmap_request *r, struct stage_clock *k, double ms[STAGE_COUNT])
{
    struct shadow_cascades *cs = t->cascades;
    for (int m = 0; m < cs->count; m++)
        for (int p = 0; p < SM_PRODUCT_COUNT; p++)
            if (r[m].products & (1u << p)) {
                stage_begin(k);
                shadowmap_render_product(&cs->map[m], t->mesh, p, &r[m]);
                ms[p == SM_PRODUCT_DEPTH ? STAGE_SHADOWMAP : STAGE_FILTER_PREP] += stage_end(k);
            }
    const struct receiver_programs *p = &c->programs;
    if (p->mask) {
        stage_begin(k);
        receiver_render_mask(t->receiver, p, t->mesh, cs, false);
        ms[STAGE_MASK] += stage_end(k);
    }
    stage_begin(k);
    receiver_render(t->receiver, p, t->mesh, cs, false);
    ms[STAGE_RECEIVER] += stage_end(k);
    if (p->stages.denoise_radius_px) {
        stage_begin(k);
        receiver_render_denoise(t->receiver, p);
        ms[STAGE_DENOISE] += stage_end(k);
    }
}

/* The cell's request of each cascade's map (its options follow the map's
 * frustum: an int32 table's scale), prepared. */
static int request(const struct stage_timer *t, const struct stage_timer_cell *c, struct shadowmap_request *r)
{
    struct shadow_cascades *cs = t->cascades;
    for (int m = 0; m < cs->count; m++) {
        struct shadowmap *sm = &cs->map[m];
        technique_request(c->technique, c->settings, &(struct request_context){&sm->frustum, sm->desc.size_texels},
                          &r[m]);
        if (shadowmap_prepare(sm, &r[m]) != 0)
            return -1;
    }
    return receiver_prepare(t->receiver, &c->programs);
}

int stage_timer_run(const struct stage_timer *t, const struct stage_timer_cell *cells, int n,
                    struct stage_times *out)
{
    const int frames = t->frames < STAGE_TIMER_MAX_FRAMES ? t->frames : STAGE_TIMER_MAX_FRAMES;
    struct shadowmap_request *requests = xcalloc((size_t)n * CASCADES_MAX, sizeof *requests);
    /* samples[(i * STAGE_COUNT + stage) * frames + f], and the frames' totals */
    double *samples = xcalloc((size_t)n * STAGE_COUNT * (size_t)frames, sizeof(double));
    double *totals = xcalloc((size_t)frames, sizeof(double));
    int rc = 0;
    struct stage_clock clock = {0};
    if (stage_timing_resolve(t->timing) == STAGE_TIMING_QUERY)
        glGenQueries(1, &clock.query);
    for (int i = 0; i < n && !rc; i++)
        rc = request(t, &cells[i], &requests[i * CASCADES_MAX]);
    glFinish();
    const int rounds = t->warmup + frames;
    for (int k = 0; k < rounds && !rc; k++) {
        const int f = k - t->warmup;  /* < 0: a warm-up round */
        for (int i = 0; i < n; i++) {
            double ms[STAGE_COUNT] = {0};
            timed_frame(t, &cells[i], &requests[i * CASCADES_MAX], &clock, ms);
            for (int s = 0; s < STAGE_COUNT && f >= 0; s++)
                samples[(i * STAGE_COUNT + s) * frames + f] = ms[s];
        }
        if (t->on_round)
            t->on_round(t->user, k + 1, rounds);
    }
    for (int i = 0; i < n && !rc; i++) {
        double *stage = &samples[i * STAGE_COUNT * frames];
        for (int f = 0; f < frames; f++) {
            totals[f] = 0;
            for (int st = 0; st < STAGE_COUNT; st++)
                totals[f] += stage[st * frames + f];
        }
        out[i] = (struct stage_times){
            .shadowmap_ms = util_quantile(stage + STAGE_SHADOWMAP * frames, frames, 0.5),
            .filter_prep_ms = util_quantile(stage + STAGE_FILTER_PREP * frames, frames, 0.5),
            .mask_ms = util_quantile(stage + STAGE_MASK * frames, frames, 0.5),
            .receiver_ms = util_quantile(stage + STAGE_RECEIVER * frames, frames, 0.5),
            .denoise_ms = util_quantile(stage + STAGE_DENOISE * frames, frames, 0.5),
            .total_ms = util_quantile(totals, frames, 0.5),
            .total_q1_ms = util_quantile(totals, frames, 0.25),
            .total_q3_ms = util_quantile(totals, frames, 0.75),
        };
    }
    if (clock.query)
        glDeleteQueries(1, &clock.query);
    free(totals);
    free(samples);
    free(requests);
    return rc;
}

int stage_timer_render(const struct stage_timer *t, const struct stage_timer_cell *c, bool counting)
{
    struct shadowmap_request r[CASCADES_MAX];
    if (request(t, c, r) != 0)
        return -1;
    for (int m = 0; m < t->cascades->count; m++)  /* the pose's products, shared by the cells that agree */
        for (int p = 0; p < SM_PRODUCT_COUNT; p++)
            if (r[m].products & (1u << p))
                shadowmap_ensure_product(&t->cascades->map[m], t->mesh, p, &r[m]);
    receiver_render_mask(t->receiver, &c->programs, t->mesh, t->cascades, counting);
    receiver_render(t->receiver, &c->programs, t->mesh, t->cascades, counting);
    receiver_render_denoise(t->receiver, &c->programs);
    return 0;
}

double stage_timer_prep_texels(const struct stage_timer *t, const struct stage_timer_cell *c)
{
    double texels = 0;
    for (int m = 0; m < t->cascades->count; m++) {
        const struct shadowmap *sm = &t->cascades->map[m];
        struct shadowmap_request r;
        technique_request(c->technique, c->settings, &(struct request_context){&sm->frustum, sm->desc.size_texels},
                          &r);
        for (int p = 0; p < SM_PRODUCT_COUNT; p++)
            if (p != SM_PRODUCT_DEPTH && (r.products & (1u << p)))
                texels += shadowmap_prep_texels(sm, p, &r);
    }
    return texels;
}
