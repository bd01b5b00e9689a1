/* Where a technique breaks (`shadowbench stability --vary`; docs/stability.md):
 * one thing takes a list of values, and a value breaks a technique when
 * its V has any NaN/Inf or, against the reference value, its rmse is at
 * least BREAK_RULE_RMSE_FACTOR times as large and BREAK_RULE_RMSE_RISE
 * larger, or its leak or dark fraction at least BREAK_RULE_FRACTION_RISE
 * larger. Its break points: the first broken value walking down from the
 * reference, and walking up. */
#ifndef SB_BREAK_RULE_H
#define SB_BREAK_RULE_H

#include "metrics.h"

#include <stdbool.h>

#define BREAK_RULE_RMSE_FACTOR 2.0
#define BREAK_RULE_RMSE_RISE 0.01
#define BREAK_RULE_FRACTION_RISE 0.05

/* The rule in words, for --help, the page and stability.json. */
extern const char break_rule_text[];

/* Whether m breaks against the reference ref. */
bool break_rule_broken(const struct metrics *m, const struct metrics *ref);

/* The break points of values 0..n-1 whose metrics are m[k] (NULL: not
 * measured), the reference at index ref: the first broken value below it
 * (walking down) into *below and above it into *above; -1 for none. */
void break_rule_points(const struct metrics *const *m, int n, int ref, int *below, int *above);

#endif
