#include "shard.h"
#include "base/log.h"
#include "base/util.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

int shard_parse(const char *opt, const char *text, struct shard *out)
{
    char *end = NULL;
    errno = 0;
    const long k = strtol(text, &end, 10);
    const char *slash = end;
    long n = -1;
    if (!errno && end != text && *slash == '/' && slash[1] >= '0' && slash[1] <= '9') {
        n = strtol(slash + 1, &end, 10);
        if (errno || *end)
            n = -1;
    }
    if (!(text[0] >= '0' && text[0] <= '9') || n < 0) {
        log_error("--%s: '%s' is not K/N (this shard's number K of N, from 1)", opt, text);
        return -1;
    }
    if (n < 1 || n > SHARD_MAX || k < 1 || k > n) {
        log_error("--%s %s: K/N needs 1 <= K <= N <= %d", opt, text, SHARD_MAX);
        return -1;
    }
    *out = (struct shard){(int)k, (int)n};
    return 0;
}

void shard_split_contiguous(const double *cost, int n, int shards, int *owner)
{
    double total = 0, before = 0;
    for (int i = 0; i < n; i++)
        total += cost[i];
    for (int i = 0; i < n; i++) {
        const int k = (int)((before + 0.5 * cost[i]) / total * shards);
        owner[i] = 1 + (k < shards ? k : shards - 1);
        before += cost[i];
    }
}

void shard_split_balanced(const double *cost, int n, int shards, int *owner)
{
    int *order = xmalloc(sizeof *order * (size_t)(n ? n : 1));
    double *load = xcalloc((size_t)shards, sizeof *load);
    for (int i = 0; i < n; i++) {  /* insertion sort, costliest first, stable */
        int j = i;
        for (; j > 0 && cost[order[j - 1]] < cost[i]; j--)
            order[j] = order[j - 1];
        order[j] = i;
    }
    for (int i = 0; i < n; i++) {
        int least = 0;
        for (int k = 1; k < shards; k++)
            if (load[k] < load[least])
                least = k;
        owner[order[i]] = least + 1;
        load[least] += cost[order[i]];
    }
    free(order);
    free(load);
}
