/* The regression check's page, <out>/check.html: each cell that moved
 * against its baseline, its metrics and a V_now - V_baseline heatmap. */
#ifndef SB_CHECK_PAGE_H
#define SB_CHECK_PAGE_H

#include "pipeline/regression.h"

/* Writes <out>/check.html and the heatmaps under <out>/<scene>/. Returns 0
 * or -1 (logged). */
int check_page_write(const struct regression *r, const char *out);

#endif
