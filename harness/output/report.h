/* Run-level outputs of docs/design.md §8: matrix.csv, matrix.json, run.json and
 * report.html. Cell-level files are written by cell_output.c. */
#ifndef SB_REPORT_H
#define SB_REPORT_H

#include "chart.h"
#include "pipeline/cell.h"
#include "score/metrics.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <stdbool.h>

struct report_scene {
    const char *name, *description, *shows;
    double gt_seconds, gt_msamples_per_second;
    bool gt_cached;
    const struct chart_curve *frontier;  /* per tuned technique, from its tuning (may be none) */
    int frontier_count;
};

struct report {
    const char *out_dir;
    int width, height;  /* of every image */
    cJSON *run;         /* run.json, built by the caller */
    const struct report_scene *scenes;
    int scene_count;
    const struct cell *cells;
    int cell_count;
    const struct chart_curve *frontier;  /* over every scene of the tunings (may be none) */
    int frontier_count;
    const char *frontier_source;         /* where and how they were measured */
    const char *frontier_objective;      /* the error they minimise, e.g. "penumbra_rmse" */
    bool frontier_fetches;               /* their cost axis is fetches per pixel, not ms */
};

/* Every metric of a cell as a flat JSON object (scene, technique, params,
 * metrics): the row of matrix.json and the body of metrics.json. */
cJSON *report_cell_json(const struct cell *c);

/* The rest of a cell from its metrics.json j (report_cell_json's), after
 * cell_describe gave it its scene, technique, settings and label: its
 * metrics, device, engine, maps, error by depth, notice and failure. Its
 * device's name points into j, which must outlive c. Returns 0, or -1
 * when j is not such a record. */
int report_cell_read(const cJSON *j, struct cell *c);

/* Writes a JSON value atomically (pretty-printed). Returns 0 or -1. */
int report_write_json(const char *path, const cJSON *value);

/* A CSV field, quoted (a quote doubled). */
void report_csv_field(struct strbuf *sb, const char *s);

/* A path segment or fragment of a URL: anything but unreserved characters
 * and @ = , + percent-encoded (a scene file may be named anything). */
void report_url(struct strbuf *h, const char *s);

/* The pages' style sheet (report.html, stability.html). */
extern const char report_style[];

/* Ends a page: its environment (run, pretty-printed) under a heading, then
 * script, then the closing tags. */
void report_html_end(struct strbuf *h, const char *heading, const cJSON *run, const char *script);

/* matrix.csv, matrix.json, run.json, report.html and the charts in
 * <out>/charts/. Returns 0 or -1. */
int report_write(const struct report *r);

#endif
