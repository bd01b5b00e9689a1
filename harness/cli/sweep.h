/* The technique configurations of a run: every selected technique with its
 * settings (defaults and --set), and for a technique named by --sweep
 * T.P=v1,v2,... one configuration per combination of its swept values (the
 * cartesian product of its sweeps). */
#ifndef SB_SWEEP_H
#define SB_SWEEP_H

#include "run.h"

/* Fills o->configs from o->techniques, o->settings and o->sweeps. Returns 0,
 * or -1 after logging one line (unknown technique or parameter, a value out
 * of range or listed twice, a parameter swept twice or also --set, a
 * technique not selected, an inconsistent combination, too many cells). */
int sweep_configs(struct run_options *o);

void sweep_free(struct run_options *o);

#endif
