/* Technique parameters, driven by each technique's table (STYLE.md item 3):
 * defaults, --set parsing with range checks, the #defines a shader receives,
 * and the values recorded in outputs. No technique parses a string. */
#ifndef SB_PARAMS_H
#define SB_PARAMS_H

#include "technique.h"
#include "base/util.h"

#include <cjson/cJSON.h>
#include <stdio.h>

/* A malloc'ed settings struct for t, every member at its default. */
void *params_defaults(const struct technique *t);

/* Sets one parameter from text. Returns 0, or -1 after logging
 * "<technique>.<name>: <problem>" (unknown name, bad value, out of range). */
int params_set(const struct technique *t, void *settings, const char *name, const char *value);

/* Sets the parameters of a list as a cell's name spells them,
 * "name=value,name=value", each at most once. Returns 0, or -1 after
 * logging one line that names `label` (the cell). */
int params_apply(const struct technique *t, void *settings, const char *list, const char *label);

/* The values of t's PARAM_TAPS parameters (its loops of depth-map fetches),
 * in table order, into taps[0..max-1]; returns how many t has (0: none). */
int params_taps(const struct technique *t, const void *settings, int *taps, int max);

/* The values `tune` explores for p (its .tune list, or with TUNE_CHOICES
 * every choice), at most max, into values; returns how many (0: p is not
 * tuned). */
int params_tune_values(const struct technique_param *p, double *values, int max);

/* Sets p to v (a value of p's type, in range: e.g. one of its tune values). */
void params_put(const struct technique_param *p, void *settings, double v);

/* p's value in settings, as a number (PARAM_ENUM: the index). */
double params_get(const struct technique_param *p, const void *settings);

/* Applies the technique's rules across parameters (technique.check).
 * Returns 0, or -1 after logging "<technique>: <reason>". */
int params_check(const struct technique *t, const void *settings);

/* t's parameter called name, or NULL. */
const struct technique_param *params_find(const struct technique *t, const char *name);

/* For a technique's check: 0 when taps is a square count (the grid
 * pattern's n x n); else -1 and, in why, what `name` needs. */
int params_grid_taps(const char *name, int taps, char *why, size_t why_size);

/* Appends "#define <TECH>_<PARAM> <value>" lines (and, for enums, one
 * "#define <TECH>_<PARAM>_<CHOICE> <index>" per choice). */
void params_defines(const struct technique *t, const void *settings, struct strbuf *out);

/* Settings from {"name": value, ...} as params_json writes it (keys given
 * twice are the caller's to refuse: util_json_duplicate_key): every
 * parameter of t, no other, each a value of its type in range, the
 * whole consistent. NULL after one logged line ("lacks t.p", or
 * params_set's and params_check's). */
void *params_from_json(const struct technique *t, const cJSON *o);

/* {"name": value, ...} with the values in settings. */
cJSON *params_json(const struct technique *t, const void *settings);

/* The value of parameter `name` as `list` and the outputs spell it. Returns
 * 0, or -1 when t has no such parameter (not logged). */
int params_value_text(const struct technique *t, const void *settings, const char *name, char *buf,
                      size_t size);

/* "name=value name=value" (for the matrix row). */
void params_summary(const struct technique *t, const void *settings, struct strbuf *out);

/* Human-readable table for `shadowbench list`. */
void params_print(const struct technique *t, FILE *f);

#endif
