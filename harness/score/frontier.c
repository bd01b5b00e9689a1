#include "frontier.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>

static int cmp_by_x(const void *a, const void *b, void *ctx)
{
    const double *const *xy = ctx;
    int i = *(const int *)a, j = *(const int *)b;
    if (xy[0][i] != xy[0][j])
        return xy[0][i] < xy[0][j] ? -1 : 1;
    return (xy[1][i] > xy[1][j]) - (xy[1][i] < xy[1][j]);
}

int frontier_pareto(const double *x, const double *y, int n, int *front)
{
    int *order = xmalloc(sizeof(int) * (size_t)(n ? n : 1));
    for (int i = 0; i < n; i++)
        order[i] = i;
    const double *xy[2] = {x, y};
    qsort_r(order, (size_t)n, sizeof *order, cmp_by_x, xy);
    int count = 0;
    double best = INFINITY;
    for (int k = 0; k < n; k++)
        if (y[order[k]] < best) {
            best = y[order[k]];
            front[count++] = order[k];
        }
    free(order);
    return count;
}

