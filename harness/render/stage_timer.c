#include "stage_timer.h"
#include "base/util.h"

struct job {
    struct stage_timer *t;
    int product;                          /* SM_PRODUCT_*, or -1: the receiver pass */
    const struct shadowmap_request *request;
    GLuint program;
};

static void run_job(const struct job *j)
{
    if (j->product < 0)
        receiver_render(j->t->receiver, j->program, j->t->mesh, j->t->sm);
    else
        shadowmap_render_product(j->t->sm, j->t->mesh, j->product, j->request);
}

static double median_ms(const struct job *j)
{
    double samples[STAGE_TIMER_MAX_FRAMES];
    int frames = j->t->frames < STAGE_TIMER_MAX_FRAMES ? j->t->frames : STAGE_TIMER_MAX_FRAMES;
    glFinish();
    for (int i = 0; i < j->t->warmup; i++) {
        run_job(j);
        glFinish();
    }
    for (int i = 0; i < frames; i++) {
        double t0 = util_now_ms();
        run_job(j);
        glFinish();
        samples[i] = util_now_ms() - t0;
    }
    return util_median(samples, frames);
}

/* Median ms of product p with r's options: timed the first time, then
 * remembered. Timing renders it, which leaves it current. */
static double product_ms(struct stage_timer *t, int p, const struct shadowmap_request *r)
{
    for (int i = 0; i < t->product_count; i++)
        if (t->products[i].product == p && shadowmap_same_product(p, &t->products[i].request, r))
            return t->products[i].ms;
    double ms = median_ms(&(struct job){t, p, r, 0});
    if (t->product_count < STAGE_TIMER_MAX_PRODUCTS) {  /* else: timed again when asked */
        t->products[t->product_count].product = p;
        t->products[t->product_count].request = *r;
        t->products[t->product_count].ms = ms;
        t->product_count++;
    }
    return ms;
}

int stage_timer_cell(struct stage_timer *timer, const struct technique *t, const void *settings,
                     GLuint program, struct stage_times *out)
{
    struct shadowmap_request r;
    technique_request(t, settings, &timer->sm->frustum, timer->sm->desc.size_texels, &r);
    if (shadowmap_prepare(timer->sm, &r) != 0)
        return -1;
    *out = (struct stage_times){0};
    for (int p = 0; p < SM_PRODUCT_COUNT; p++)
        if (r.products & (1u << p)) {
            double ms = product_ms(timer, p, &r);
            *(p == SM_PRODUCT_DEPTH ? &out->shadowmap_ms : &out->filter_prep_ms) += ms;
        }
    shadowmap_require(timer->sm, timer->mesh, &r);
    out->receiver_ms = stage_timer_receiver_ms(timer, program);
    out->total_ms = out->shadowmap_ms + out->filter_prep_ms + out->receiver_ms;
    return 0;
}

double stage_timer_receiver_ms(struct stage_timer *timer, GLuint program)
{
    return median_ms(&(struct job){timer, -1, NULL, program});
}
