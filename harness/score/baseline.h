/* A regression baseline (docs/design.md §8; docs/regression.md):
 * results/baselines/<scene>/<cell>.json and <cell>.png, the settings a cell
 * was rendered at, its metrics, a tolerance per metric and why, and its
 * V_tech as a 16-bit PNG. This module owns the format, the tolerance
 * policy and the comparison; pipeline/regression.c renders the cells.
 *
 * Comparing: a metric worse than its tolerance, or a picture that moved
 * with no metric better, is a regression; a metric better than its
 * tolerance, with none worse, an improvement. Tolerances, measured: twice
 * the sum of the metric's spread when the ground truth is rendered with
 * BASELINE_SEEDS seeds (a metric that moves less than the truth's own noise
 * has not measurably moved) and the most it moved when llvmpipe was built
 * for another CPU. V_tech itself does not depend on the truth: the picture
 * budget is twice the most that moved on another CPU. */
#ifndef SB_BASELINE_H
#define SB_BASELINE_H

#include "metrics.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <stdbool.h>
#include <stdint.h>

/* The size every baseline is recorded at: small enough that checking all of
 * them takes well under a minute here, the shadow map at its default. */
#define BASELINE_SIZE 256
#define BASELINE_GT_SAMPLES 256
#define BASELINE_GT_SEED 1
/* The ground truth is rendered with this many seeds when a baseline is
 * recorded; the metrics' spread over them sets their tolerances. */
#define BASELINE_SEEDS 3
/* A pixel moved when |V_now - V_baseline| exceeds this: far above the PNG's
 * 16-bit steps (1.5e-5) and float reordering, far below a visible change. */
#define BASELINE_PIXEL_THRESHOLD 0.002
/* The share of the image's pixels that may move: twice the most that moved
 * (0.075 %, on stanford_bunny's savsm) when llvmpipe ran without AVX and FMA
 * (GALLIUM_OVERRIDE_CPU_CAPS=sse4.1), as on another CPU; none moved across
 * LP_NUM_THREADS 1/2/4, LP_NATIVE_VECTOR_WIDTH 128/256 or AVX without AVX2
 * (tools/check-variation). */
#define BASELINE_PIXEL_FRACTION 0.0015

/* The metrics a baseline guards, each better lower (bias: its size), with
 * the most each moved over the baselines' cells under those variations. */
struct baseline_guard {
    int metric;     /* METRIC_* */
    double device;  /* the most it moved on another CPU */
};
enum { BASELINE_GUARDS = 9 };
extern const struct baseline_guard baseline_guards[BASELINE_GUARDS];

/* What a cell is rendered at: the image, the truth and the map. */
struct baseline_setup {
    int width, height, gt_samples, shadow_map_size;
    uint32_t gt_seed;
};

/* The setup every baseline is recorded at. */
extern const struct baseline_setup baseline_setup_default;

bool baseline_setup_equal(const struct baseline_setup *a, const struct baseline_setup *b);

/* A baseline as read: the file validated, its picture. */
struct baseline {
    cJSON *doc;                       /* NULL: none */
    struct baseline_setup setup;
    uint16_t *picture;                /* its V_tech, width x height */
    double pixel_threshold, max_moved;  /* its picture budget */
};

/* Reads the baseline of cell `label` (technique t) of scene `scene` from
 * json_path and png_path into b, and its recorded parameters into
 * settings (t->settings_size bytes). Returns 0 (b->doc NULL when there is
 * no file), or -1 after one line naming the file and the problem. */
int baseline_read(const char *json_path, const char *png_path, const char *scene, const char *label,
                  const struct technique *t, struct baseline *b, void *settings);

void baseline_free(struct baseline *b);

/* A metric's value as b holds it (NAN: null), and its tolerance. */
double baseline_metric(const struct baseline *b, int metric);
double baseline_tolerance(const struct baseline *b, int metric);

/* V in [0, 1] as 16-bit grey, NaN as 0: the picture a baseline keeps. */
void baseline_quantize(const float *v, size_t count, uint16_t *out);

enum baseline_status { BASELINE_PASS, BASELINE_REGRESSED, BASELINE_IMPROVED, BASELINE_MISSING };
extern const char *const baseline_status_names[];  /* "pass", "REGRESSED", "improved", "no baseline" */

struct baseline_comparison {
    enum baseline_status status;
    double moved_fraction;          /* of the pixels, by more than the baseline's threshold */
    bool picture_moved;             /* more than its budget */
    int better, worse;              /* metrics beyond their tolerance, each way */
    int direction[BASELINE_GUARDS]; /* per guard: +1 worse, -1 better, 0 within */
};

/* Cell now (metrics m, V_tech v) against baseline b. */
void baseline_compare(const struct baseline *b, const struct metrics *m, const float *v,
                      struct baseline_comparison *out);

/* The largest change of each guarded metric when V_tech v (scored over
 * gl_distance, within the cell's depth_tolerance) is scored against the n
 * other ground truths of other seeds instead of the one m was scored
 * against. */
void baseline_spread(const float *v, const float *gl_distance, float depth_tolerance, const struct metrics *m,
                     const struct gt_image *others, int n, double spread[BASELINE_GUARDS]);

/* What a new baseline records. */
struct baseline_record {
    const char *scene, *label;
    const struct technique *t;
    const void *settings;
    struct baseline_setup setup;
    const struct metrics *m;
    const float *v;                  /* V_tech */
    const double *spread;            /* baseline_spread's */
    const cJSON *provenance;         /* output/provenance.h: copied into the file */
};

/* Writes r to json_path and png_path, each atomically, the picture first
 * (a JSON is never newer than its picture; the hash tells an interrupted
 * pair apart). Returns 0 or -1 (logged). */
int baseline_write(const char *json_path, const char *png_path, const struct baseline_record *r);

#endif
