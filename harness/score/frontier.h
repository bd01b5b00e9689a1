/* The Pareto front of error against time (docs/design.md §1, frontier): of a set
 * of settings, those that no other is both faster and more accurate than.
 * The tuning's frontiers, the report's bold cells and the trade-off
 * charts' staircases are all this one rule. */
#ifndef SB_FRONTIER_H
#define SB_FRONTIER_H

/* Indices of the Pareto-optimal items for minimising both x and y, in
 * increasing x; returns their count. Ties in x keep the lower y. */
int frontier_pareto(const double *x, const double *y, int n, int *front);

#endif
