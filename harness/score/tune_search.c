#include "tune_search.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

const struct tune_entry *tune_find(const struct tune_memo *m, const int *point)
{
    for (int i = 0; i < m->count; i++)
        if (memcmp(m->entries[i].point, point, sizeof(int) * (size_t)m->dims) == 0)
            return &m->entries[i];
    return NULL;
}

static struct tune_entry *entry(struct tune_memo *m, const int *point)
{
    struct tune_entry *e = (struct tune_entry *)tune_find(m, point);
    if (e)
        return e;
    if (m->count == m->capacity) {
        m->capacity = m->capacity ? 2 * m->capacity : 64;
        m->entries = xrealloc(m->entries, sizeof *m->entries * (size_t)m->capacity);
    }
    e = &m->entries[m->count++];
    memset(e, 0, sizeof *e);
    memcpy(e->point, point, sizeof(int) * (size_t)m->dims);
    return e;
}

int tune_mean(struct tune_memo *m, const int *point, const int *scenes, int n, double *mean)
{
    if (n < 1)
        return -1;  /* a mean of nothing: a caller's error */
    double sum = 0;
    for (int i = 0; i < n; i++) {
        struct tune_entry *e = entry(m, point);
        const int k = scenes[i];
        if (!e->done[k]) {
            struct tune_sample s;
            if (m->eval(m->user, point, k, &s) != 0)
                return -1;
            e = entry(m, point);  /* eval may not grow the memo, but stay safe */
            e->s[k] = s;
            e->done[k] = true;
            m->evaluations++;
        }
        sum += e->s[k].objective;
    }
    *mean = sum / n;
    return 0;
}

int tune_descend(struct tune_memo *m, const int *scenes, int n, const int *start, int *best, double *score)
{
    memcpy(best, start, sizeof(int) * (size_t)m->dims);
    if (tune_mean(m, best, scenes, n, score) != 0)
        return -1;
    for (int round = 0; round < TUNE_MAX_ROUNDS; round++) {
        bool moved = false;
        for (int d = 0; d < m->dims; d++) {
            int trial[TUNE_MAX_DIMS], choice = best[d];
            memcpy(trial, best, sizeof trial);
            for (int v = 0; v < m->counts[d]; v++) {
                if (v == best[d])
                    continue;
                trial[d] = v;
                double mean;
                if (tune_mean(m, trial, scenes, n, &mean) != 0)
                    return -1;
                if (mean < *score) {  /* strictly better: ties keep the earlier point */
                    *score = mean;
                    choice = v;
                }
            }
            moved |= choice != best[d];
            best[d] = choice;
        }
        if (!moved)
            break;
    }
    return 0;
}

int tune_cross_validate(struct tune_memo *m, const int *start, const int *group, int (*fold)[TUNE_MAX_DIMS],
                        double *held_out)
{
    for (int k = 0; k < m->scenes; k++) {
        int others[TUNE_MAX_SCENES], n = 0;
        for (int i = 0; i < m->scenes; i++)
            if (i != k && (!group || group[i] == group[k]))
                others[n++] = i;
        if (n == 0)  /* alone in its group: every other scene */
            for (int i = 0; i < m->scenes; i++)
                if (i != k)
                    others[n++] = i;
        double fitted;
        if (tune_descend(m, others, n, start, fold[k], &fitted) != 0 ||
            tune_mean(m, fold[k], &k, 1, &held_out[k]) != 0)
            return -1;
    }
    return 0;
}

void tune_memo_free(struct tune_memo *m)
{
    free(m->entries);
    m->entries = NULL;
    m->count = m->capacity = 0;
}
