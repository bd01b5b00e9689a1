/* The ground truth traced in the background, refining: one thread traces
 * the pose last asked for at 1, 4, 16, ... light samples per pixel up to a
 * maximum, handing over each level when it is done; asking for another
 * pose cancels the level in progress (gt_desc.cancel) and starts again at
 * 1. The interactive viewer's (`shadowbench view`). */
#ifndef SB_GT_WORKER_H
#define SB_GT_WORKER_H

#include "groundtruth.h"

#include <pthread.h>

struct gt_worker {
    pthread_t thread;
    pthread_mutex_t lock;
    pthread_cond_t wake, done_cond;
    atomic_bool cancel;
    bool started, quit;
    int width, height, max_samples;
    unsigned asked;        /* the pose asked for (the caller's count; 0: none yet) */
    struct scene scene;    /* that pose: a copy of the struct, its arrays the caller's,
                              unchanged while the worker runs */
    struct light_frustum frustum;
    unsigned done_pose;    /* the pose of the levels below */
    int done_samples;      /* of done; -1: tracing done_pose failed (logged) */
    bool fresh, finished;  /* a level not yet taken; done_pose's last level is done (or failed) */
    struct gt_image done;
};

/* Starts the thread for images of width x height and up to max_samples
 * samples per pixel (a square). Returns 0 or -1 (logged). */
int gt_worker_start(struct gt_worker *w, int width, int height, int max_samples);

/* Asks for pose (> 0, a new one each time): the scene s in it, f its light
 * frustum. */
void gt_worker_ask(struct gt_worker *w, unsigned pose, const struct scene *s, const struct light_frustum *f);

/* Waits up to ms for the last level of pose to be done, or to fail.
 * Returns whether it is (at once for a pose not asked for, or 0); *level: the samples per pixel of the newest
 * level done so far (0: none yet). */
bool gt_worker_wait(struct gt_worker *w, unsigned pose, int ms, int *level);

/* Moves the newest level of pose into *out (freeing what it held) and
 * returns its samples per pixel; 0 when none is newer than the last taken,
 * -1 when tracing the pose failed. */
int gt_worker_take(struct gt_worker *w, unsigned pose, struct gt_image *out);

/* Stops the thread (cancelling its level) and frees what it holds; a
 * worker that never started is left as it is. */
void gt_worker_stop(struct gt_worker *w);

#endif
