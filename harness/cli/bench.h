/* `shadowbench bench`: the median time of each stage (shadow map, filter
 * prep, receiver pass) of each technique on one scene, and the texture-fetch
 * limit measured on the same scene. No ground truth, no files. */
#ifndef SB_BENCH_H
#define SB_BENCH_H

#include "run.h"

int bench_main(const struct run_options *o);

#endif
