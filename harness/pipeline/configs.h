/* The technique configurations of a run: every selected technique with its
 * settings (defaults and --set), and for a technique named by --sweep
 * T.P=v1,v2,... one configuration per combination of its swept values (the
 * cartesian product of its sweeps); each technique's tuned cell,
 * <technique>@tuned, whose settings differ by scene (score/tuned.h); and
 * its presets, <technique>@<name> (technique.h), in the default run. */
#ifndef SB_CONFIGS_H
#define SB_CONFIGS_H

#include "base/util.h"
#include "scene/scene.h"
#include "techniques/technique.h"

#define CONFIG_MAX 256        /* configurations in one run */
#define CONFIG_MAX_SWEEPS 16

/* One technique with one parameter set: a column of the matrix. */
struct run_config {
    const struct technique *technique;
    void *settings;  /* owned */
    char *label;     /* the technique's name, or with its swept values:
                        "pcss@blocker_samples=16,filter_samples=64", or "pcss@tuned";
                        the cell's folder */
    struct tuned *tuned;  /* owned; a tuned cell: its settings differ by scene */
};

/* Which cells of each technique a run makes (--settings). CONFIG_AUTO, the
 * default: the tuned cell, or the default cells when --set or --sweep
 * changes them or the technique has no tuned file; and without --set or
 * --sweep, its presets (so with CONFIG_BOTH). */
enum config_mode { CONFIG_AUTO, CONFIG_BOTH, CONFIG_DEFAULT, CONFIG_TUNED };

struct config_desc {
    const struct technique *const *techniques;  /* selected, at least one */
    int technique_count;
    void *const *settings;                      /* by technique_list index, every one set */
    const char *const *sweeps;                  /* --sweep T.P=V1,V2,... as given */
    int sweep_count;
    int set_count;                              /* --set options given */
    enum config_mode mode;
    const char *tuned_dir;                      /* where the tuned cells' files are */
};

struct config_set {
    struct run_config *configs;
    int count;
    struct strbuf untuned;  /* techniques without a tuned file ("a, b"), run at their defaults */
};

/* Fills out from d. Returns 0, or -1 after logging one line (unknown
 * technique or parameter, a value out of range or listed twice, a
 * parameter swept twice, a technique not selected, an inconsistent
 * combination, too many cells, a tuned file that cannot be read); free
 * out with configs_free either way. */
int configs_build(struct config_set *out, const struct config_desc *d);

void configs_free(struct config_set *s);

/* The settings of configuration c on scene s: a tuned cell's for that scene
 * (tuned_settings). */
const void *config_settings(const struct run_config *c, const struct scene *s);

#endif
