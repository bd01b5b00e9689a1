/* `shadowbench check`: the regression check per technique (README,
 * Regression check). Each baseline cell, results/baselines/<scene>/<cell>.json
 * and .png (DESIGN.md §8), is rendered again at its recorded settings and
 * compared: its metrics within their tolerances, its picture within a
 * changed-pixel budget. --update records the selected cells anew. */
#ifndef SB_CHECK_H
#define SB_CHECK_H

#include "run.h"

/* The size every baseline is recorded at: small enough that checking all of
 * them takes well under a minute here, the shadow map at its default. */
#define CHECK_SIZE 256
#define CHECK_GT_SAMPLES 256
#define CHECK_GT_SEED 1
/* The ground truth is rendered with this many seeds when a baseline is
 * recorded; the metrics' spread over them sets their tolerances. */
#define CHECK_SEEDS 3
/* A pixel moved when |V_now - V_baseline| exceeds this: far above the PNG's
 * 16-bit steps (1.5e-5) and float reordering, far below a visible change. */
#define CHECK_PIXEL_THRESHOLD 0.002

/* Exit status: 0 all passed; 1 a cell regressed, has no baseline, moved
 * with --strict, or a parameter is not covered; 2 bad usage or an
 * unreadable baseline. */
int check_main(const struct run_options *o);

#endif
