/* Shards (docs/scale-out.md, docs/design.md §13): a command's cells split
 * into N parts, every cell in exactly one, chosen from the cells alone
 * (their order and expected costs), so that N copies of one command line
 * that differ only in --shard K/N do the whole command between them and
 * `shadowbench merge` can tell which shard owes which cell. */
#ifndef SB_SHARD_H
#define SB_SHARD_H

#include <stdbool.h>

#define SHARD_MAX 4096

/* Shard index of count (1-based, as Slurm's array index); count 0: the
 * whole command, unsharded. */
struct shard {
    int index, count;
};

/* "K/N" with 1 <= K <= N <= SHARD_MAX into *out. Returns 0 or -1 (logged,
 * naming opt). */
int shard_parse(const char *opt, const char *text, struct shard *out);

/* Whether shard s does the unit owned by shard owner (1-based); every unit
 * when unsharded. */
static inline bool shard_owns(const struct shard *s, int owner)
{
    return s->count == 0 || s->index == owner;
}

/* The owners (1..shards) of n units in their order, each of expected cost
 * cost[i] > 0, in contiguous runs of about equal cost: unit i goes to the
 * shard whose equal share of the total holds the middle of its cost (so
 * neighbours, a scene's cells, stay together). */
void shard_split_contiguous(const double *cost, int n, int shards, int *owner);

/* The owners of n units that share nothing (a technique's tuning): the
 * costliest first, each to the shard least loaded so far (the lowest index
 * on a tie): longest-processing-time scheduling, within 4/3 of the best
 * split. Deterministic: equal costs keep the units' order. */
void shard_split_balanced(const double *cost, int n, int shards, int *owner);

#endif
