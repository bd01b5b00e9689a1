/* The regression check's page, <out>/check.html: each cell that moved
 * against its baseline, its metrics and a V_now - V_baseline heatmap. */
#ifndef SB_CHECK_PAGE_H
#define SB_CHECK_PAGE_H

#include "pipeline/regression.h"

/* What check.html says of a cell that moved (docs/regression.md). */
struct check_section {
    int status;                     /* enum baseline_status */
    const char *scene, *label;
    double moved_fraction, pixel_threshold, max_moved;
    double base[BASELINE_GUARDS], now[BASELINE_GUARDS], tolerance[BASELINE_GUARDS];  /* per guard */
};

/* Whether cell c moved against its baseline (shown on the page), and if so
 * its section's numbers into *s (pointing into c). */
bool check_section_of(const struct regression_cell *c, struct check_section *s);

/* Its section of check.html, appended to html. */
void check_page_section(struct strbuf *html, const struct check_section *s);

/* Cell c's heatmap written (<out>/<scene>/<cell>.png), if c moved: 1;
 * else 0 (nothing); or -1 (logged). Then the page around the cells'
 * sections, in the check's order (NULL or empty: no cell moved): 0 or -1.
 * A sharded check records each section's numbers, and merge writes them
 * (docs/scale-out.md). */
int check_page_heatmap(const struct regression_cell *c, const char *out);
int check_page_write_sections(const char *sections, const char *out);

#endif
