#include "stage_timer.h"
#include "base/util.h"

struct job {
    struct stage_timer *t;
    enum shadowmap_product product;
    const struct shadowmap_request *request;
    const struct receiver *receiver;  /* NULL: the job renders the product */
    GLuint program;
};

static void run_job(const struct job *j)
{
    if (j->receiver)
        receiver_render(j->receiver, j->program, j->t->mesh, j->t->sm);
    else
        shadowmap_render_product(j->t->sm, j->t->mesh, j->product, j->request);
}

static double median_ms(const struct job *j)
{
    double samples[1000];
    int frames = j->t->frames < 1000 ? j->t->frames : 1000;
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

double stage_timer_products_ms(struct stage_timer *t, const struct shadowmap_request *r,
                               unsigned which)
{
    double ms = 0;
    for (unsigned p = SM_DEPTH; p <= SM_MOMENTS_SAT; p <<= 1) {
        if (!(r->products & which & p))
            continue;
        int i = 0;
        while (i < t->product_count &&
               !(t->products[i].product == p && shadowmap_same_product(p, &t->products[i].request, r)))
            i++;
        if (i < t->product_count) {
            ms += t->products[i].ms;
            continue;
        }
        double product_ms = median_ms(&(struct job){t, (enum shadowmap_product)p, r, NULL, 0});
        if (t->product_count < STAGE_TIMER_MAX_PRODUCTS) {  /* else: timed again when asked */
            t->products[i].product = (enum shadowmap_product)p;
            t->products[i].request = *r;
            t->products[i].ms = product_ms;
            t->product_count++;
        }
        ms += product_ms;
    }
    return ms;
}

double stage_timer_receiver_ms(struct stage_timer *t, const struct receiver *rc, GLuint program)
{
    return median_ms(&(struct job){t, 0, NULL, rc, program});
}
