#include "gt_worker.h"
#include "base/log.h"

#include <string.h>
#include <time.h>

/* Hands a finished level (rc 0) or a failure (rc < 0) of pose over, unless
 * the pose is no longer the one asked for; returns whether it still is. */
static bool hand_over(struct gt_worker *w, unsigned pose, int rc, int samples, bool last, struct gt_image *g)
{
    pthread_mutex_lock(&w->lock);
    const bool current = w->asked == pose;
    if (current && rc == 0) {
        gt_image_free(&w->done);
        w->done = *g;
        w->done_samples = samples;
    } else if (rc == 0) {
        gt_image_free(g);
    }
    if (current && rc != GT_CANCELLED) {  /* a cancelled level hands nothing over */
        if (rc < 0)
            w->done_samples = -1;
        w->done_pose = pose, w->fresh = true, w->finished = last || rc < 0;
        pthread_cond_broadcast(&w->done_cond);
    }
    pthread_mutex_unlock(&w->lock);
    return current;
}

static void *worker_main(void *arg)
{
    struct gt_worker *w = arg;
    unsigned taken = 0;
    pthread_mutex_lock(&w->lock);
    for (;;) {
        while (!w->quit && w->asked == taken)
            pthread_cond_wait(&w->wake, &w->lock);
        if (w->quit)
            break;
        taken = w->asked;
        const struct scene scene = w->scene;
        const struct light_frustum frustum = w->frustum;
        atomic_store(&w->cancel, false);
        pthread_mutex_unlock(&w->lock);
        for (int samples = 1, last = 0; !last; samples *= 4) {
            if (samples >= w->max_samples)
                samples = w->max_samples, last = 1;
            struct gt_image g;
            const struct gt_desc d = {.width = w->width, .height = w->height, .samples = samples,
                                      .quiet = true, .cancel = &w->cancel};
            const int rc = gt_render(&scene, &frustum, &d, &g);
            if (rc == GT_CANCELLED)
                gt_image_free(&g);
            if (!hand_over(w, taken, rc, samples, last, &g) || rc != 0)
                break;
        }
        pthread_mutex_lock(&w->lock);
    }
    pthread_mutex_unlock(&w->lock);
    return NULL;
}

int gt_worker_start(struct gt_worker *w, int width, int height, int max_samples)
{
    memset(w, 0, sizeof *w);
    w->width = width, w->height = height, w->max_samples = max_samples;
    pthread_mutex_init(&w->lock, NULL);
    pthread_cond_init(&w->wake, NULL);
    pthread_cond_init(&w->done_cond, NULL);
    if (pthread_create(&w->thread, NULL, worker_main, w) != 0) {
        log_error("ground truth: could not start its thread");
        return -1;
    }
    w->started = true;
    return 0;
}

void gt_worker_ask(struct gt_worker *w, unsigned pose, const struct scene *s, const struct light_frustum *f)
{
    pthread_mutex_lock(&w->lock);
    w->asked = pose, w->scene = *s, w->frustum = *f;
    w->finished = false;
    atomic_store(&w->cancel, true);
    pthread_cond_signal(&w->wake);
    pthread_mutex_unlock(&w->lock);
}

bool gt_worker_wait(struct gt_worker *w, unsigned pose, int ms, int *level)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);  /* the condition variable's clock */
    until.tv_nsec += (long)(ms % 1000) * 1000000L;
    until.tv_sec += ms / 1000 + until.tv_nsec / 1000000000L;
    until.tv_nsec %= 1000000000L;
    pthread_mutex_lock(&w->lock);
    int rc = 0;
    while (rc == 0 && pose && w->asked == pose && !(w->done_pose == pose && w->finished))
        rc = pthread_cond_timedwait(&w->done_cond, &w->lock, &until);
    const bool done = !pose || w->asked != pose || (w->done_pose == pose && w->finished);  /* 0: none asked for */
    *level = w->done_pose == pose && w->done_samples > 0 ? w->done_samples : 0;
    pthread_mutex_unlock(&w->lock);
    return done;
}

int gt_worker_take(struct gt_worker *w, unsigned pose, struct gt_image *out)
{
    int samples = 0;
    pthread_mutex_lock(&w->lock);
    if (w->fresh && w->done_pose == pose) {
        samples = w->done_samples;
        if (samples > 0) {
            gt_image_free(out);
            *out = w->done;
            memset(&w->done, 0, sizeof w->done);
        }
        w->fresh = false;
    }
    pthread_mutex_unlock(&w->lock);
    return samples;
}

void gt_worker_stop(struct gt_worker *w)
{
    if (!w->started)
        return;
    pthread_mutex_lock(&w->lock);
    w->quit = true;
    atomic_store(&w->cancel, true);
    pthread_cond_signal(&w->wake);
    pthread_mutex_unlock(&w->lock);
    pthread_join(w->thread, NULL);
    gt_image_free(&w->done);
    pthread_cond_destroy(&w->wake);
    pthread_cond_destroy(&w->done_cond);
    pthread_mutex_destroy(&w->lock);
    w->started = false;
}
