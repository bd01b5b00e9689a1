/* The files of one cell and of one scene's ground truth (docs/design.md §8),
 * each written atomically. Run-level files are report.c's. */
#ifndef SB_CELL_OUTPUT_H
#define SB_CELL_OUTPUT_H

#include "report.h"
#include "truth/groundtruth.h"

/* X(ID, name): the files of a cell's folder (<out>/<scene>/<cell>/) and of
 * a scene's (<out>/<scene>/), each name written once. */
#define CELL_FILES(X)                                                                          \
    X(VISIBILITY_EXR, "visibility.exr") X(ERROR_EXR, "error.exr") X(VISIBILITY_PNG, "visibility.png") \
    X(HEATMAP_PNG, "heatmap.png") X(METRICS_JSON, "metrics.json") X(GROUNDTRUTH_EXR, "groundtruth.exr")   \
    X(GROUNDTRUTH_PNG, "groundtruth.png")

enum cell_file {
#define X(id, name) CELL_##id,
    CELL_FILES(X)
#undef X
    CELL_FILE_COUNT
};
extern const char *const cell_files[CELL_FILE_COUNT];

/* The images of one cell and what they are compared with; width x height,
 * top row first. */
struct cell_images {
    int width, height;
    const float *v;         /* V_tech */
    const float *distance;  /* GL's camera distance, -1 where no geometry */
    const float *v_gt;      /* V_gt */
    const float *scored;    /* 1 where scored */
};

/* <dir>/visibility.exr (V), error.exr (E = V_tech - V_gt where scored, else
 * 0), visibility.png and heatmap.png of a cell. Creates dir. Returns 0 or
 * -1 (logged). */
int output_cell_images(const char *dir, const struct cell_images *im);
/* <dir>/metrics.json of c (once its times are in). Returns 0 or -1. */
int output_cell_metrics(const char *dir, const struct cell *c);

/* <dir>/groundtruth.exr (channels V, V_weighted, mask) and groundtruth.png
 * (V, unscored pixels hatched) of gt, with the scored mask. Returns 0 or -1
 * (logged). */
int output_groundtruth(const char *dir, const struct gt_image *gt, const float *mask);

#endif
