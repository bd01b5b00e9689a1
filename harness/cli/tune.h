/* `shadowbench tune` (README, Tuning): each technique's parameters explored
 * over the scenes by coordinate descent (score/tune_search.h); per
 * technique its frontier (error against time over every setting tried),
 * the best setting per scene (an oracle) and a setting per scene chosen on
 * the other scenes (leave-one-scene-out), written to <out>/<technique>.json
 * and with --write-tuned to results/tuned/ (tuned.h). */
#ifndef SB_TUNE_H
#define SB_TUNE_H

#include "run.h"

/* How the search is described in every file it writes. */
#define TUNE_SEARCH_TEXT                                                                          \
    "coordinate descent from the defaults: each tuned parameter in table order tried at every "   \
    "one of its values with the others held, the strictly best mean objective over the scenes "   \
    "taken; rounds until one changes nothing (at most " RUN_STR(TUNE_MAX_ROUNDS) "). "            \
    "Deterministic: no random choices, ties keep the earlier point"

int tune_main(const struct run_options *o);

#endif
