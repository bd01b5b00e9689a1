/* Median wall time of the GL stages of a frame (DESIGN.md §7): warm-up
 * frames, then the median of K, each bracketed by glFinish. On llvmpipe GL
 * timer queries do not measure the work, so the wall clock does. Products
 * are timed once per distinct request options and shared by the cells that
 * ask for the same. */
#ifndef SB_STAGE_TIMER_H
#define SB_STAGE_TIMER_H

#include "techniques/shadowmap.h"
#include "receiver.h"

#define STAGE_TIMER_MAX_PRODUCTS 96

struct stage_timer {
    struct shadowmap *sm;
    const struct scene_mesh *mesh;
    int warmup, frames;  /* frames in [1, 1000] */
    struct {
        enum shadowmap_product product;
        struct shadowmap_request request;
        double ms;
    } products[STAGE_TIMER_MAX_PRODUCTS];
    int product_count;
};

/* Median ms of the products of r among `which` (SM_* flags), summed; each
 * is timed the first time it is asked for, which leaves it current. */
double stage_timer_products_ms(struct stage_timer *t, const struct shadowmap_request *r,
                               unsigned which);

/* Median ms of one receiver pass with this program. */
double stage_timer_receiver_ms(struct stage_timer *t, const struct receiver *rc, GLuint program);

#endif
