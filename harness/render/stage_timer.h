/* Median wall time of the GL stages of a frame (DESIGN.md §7): warm-up
 * frames, then the median of K, each bracketed by glFinish. On llvmpipe GL
 * timer queries do not measure the work, so the wall clock does. Products
 * are timed once per distinct request options and shared by the cells that
 * ask for the same. */
#ifndef SB_STAGE_TIMER_H
#define SB_STAGE_TIMER_H

#include "receiver.h"
#include "techniques/shadowmap.h"

#define STAGE_TIMER_MAX_FRAMES 1000
#define STAGE_TIMER_MAX_PRODUCTS 96

/* Median milliseconds per frame of each stage of one cell. */
struct stage_times {
    double shadowmap_ms;    /* the depth pass */
    double filter_prep_ms;  /* the products derived from it that the technique samples */
    double receiver_ms;     /* the receiver pass */
    double total_ms;        /* their sum */
};

struct stage_timer {
    struct shadowmap *sm;
    const struct scene_mesh *mesh;
    const struct receiver *receiver;
    int warmup, frames;  /* frames in [1, STAGE_TIMER_MAX_FRAMES] */
    struct {
        int product;  /* SM_PRODUCT_* */
        struct shadowmap_request request;
        double ms;
    } products[STAGE_TIMER_MAX_PRODUCTS];
    int product_count;
};

/* The timing sequence of one cell, the same for run and bench: technique
 * t's request at these settings, its products (each timed the first time a
 * request asks for it), made current, then the receiver pass with program,
 * which leaves V_tech in the receiver's targets. Returns 0 or -1 (logged). */
int stage_timer_cell(struct stage_timer *timer, const struct technique *t, const void *settings,
                     GLuint program, struct stage_times *out);

/* Median ms of one receiver pass with this program. */
double stage_timer_receiver_ms(struct stage_timer *timer, GLuint program);

#endif
