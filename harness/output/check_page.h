/* The regression check's page, <out>/check.html: each cell that moved
 * against its baseline, its metrics and a V_now - V_baseline heatmap. */
#ifndef SB_CHECK_PAGE_H
#define SB_CHECK_PAGE_H

#include "pipeline/regression.h"

/* Cell c's section of <out>/check.html appended to html and its heatmap
 * written (<out>/<scene>/<cell>.png), if c moved: 1; else 0 (nothing); or
 * -1 (logged). Then the page around the cells' sections, in the check's
 * order (NULL or empty: no cell moved): 0 or -1. A sharded check records
 * its cells' sections, and merge writes them (docs/scale-out.md). */
int check_page_cell(const struct regression_cell *c, const char *out, struct strbuf *html);
int check_page_write_sections(const char *sections, const char *out);

#endif
