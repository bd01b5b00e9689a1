/* The option table (FFmpeg's OptionDef, git's parse-options): one row per
 * option, the only place an option is named. getopt's table, the check
 * that a command takes an option, the parsing and --help (help.c) come
 * from it. */
#include "options.h"
#include "base/log.h"
#include "base/util.h"
#include "pipeline/stability.h"
#include "scene/motion.h"
#include "score/baseline.h"
#include "score/metrics.h"
#include "score/tuned.h"
#include "techniques/params.h"
#include "techniques/shadowmap.h"
#include "truth/groundtruth.h"
#include "view/script.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define ON(c) (1u << CMD_##c)
#define RENDERING (ON(RUN) | ON(BENCH) | ON(CHECK) | ON(TUNE) | ON(STABILITY) | ON(VIEW))
#define TRACING (ON(RUN) | ON(GT) | ON(TUNE) | ON(STABILITY))  /* a ground truth into an output folder */
#define FIELD(member) offsetof(struct options, member)
#define CASCADED (ON(RUN) | ON(BENCH) | ON(TUNE) | ON(STABILITY) | ON(VIEW))  /* the shared layer's cascades */

/* ---- the options that need more than a field ----------------------------- */

static int set_scene(struct options *o, const char *arg)
{
    if (o->scene_count == CLI_MAX_SCENES) {
        log_error("--scene: too many scenes");
        return -1;
    }
    if (commands[o->cmd].one_scene && o->scene_count == 1) {
        const char *names[COMMAND_COUNT];
        int n = 0;
        for (int k = 0; k < COMMAND_COUNT; k++)
            if (commands[k].one_scene)
                names[n++] = commands[k].name;
        struct strbuf which = {0};  /* "gt, bench and view" */
        for (int i = 0; i < n; i++)
            strbuf_printf(&which, "%s%s", i == 0 ? "" : i == n - 1 ? " and " : ", ", names[i]);
        log_error("--scene: %s take one scene", which.data);
        strbuf_free(&which);
        return -1;
    }
    o->scenes[o->scene_count++] = arg;
    return 0;
}

/* Adds t to the selection, once: it holds every registered technique at
 * most (CLI_MAX_TECHNIQUES is TECHNIQUE_COUNT_MAX, which registry.c
 * asserts the registry fits). */
static void select_technique(struct options *o, const struct technique *t)
{
    for (int i = 0; i < o->technique_count; i++)
        if (o->techniques[i] == t)
            return;
    o->techniques[o->technique_count++] = t;
}

static int set_techniques(struct options *o, const char *list)
{
    char *copy = xstrdup(list), *rest = copy;
    int rc = 0;
    for (char *name = strsep(&rest, ","); name && !rc; name = strsep(&rest, ",")) {
        if (!*name) {  /* "", ",", "a,,b": never "every technique" by accident */
            log_error("--technique: '%s' has an empty name", list);
            rc = -1;
            break;
        }
        const struct technique *t = technique_find(name);
        /* "engines": every engine cell; "presets": every preset; an engine's
         * name: its modes and the presets of its filters (docs/engines.md,
         * docs/presets.md) */
        bool group = false;
        for (const struct technique *const *e = technique_list; *e && !t; e++) {
            const char *of = technique_is_engine(*e) ? (*e)->engine : (*e)->preset_of;
            const char *all = technique_is_engine(*e) ? "engines" : "presets";
            if (of && (!strcmp(name, all) || !strcmp(name, of))) {
                group = true;
                select_technique(o, *e);
            }
        }
        if (t) {
            select_technique(o, t);
        } else if (!group) {
            struct strbuf known = {0};
            technique_names(&known, ", ");
            log_error("--technique: unknown technique '%s' (known: %s; and engines, presets, or an engine's "
                      "name for its modes and presets)", name, known.data);
            strbuf_free(&known);
            rc = -1;
        }
    }
    free(copy);
    return rc;
}

static int set_parameter(struct options *o, const char *arg)
{
    o->set_count++;
    const char *dot = strchr(arg, '.'), *eq = strchr(arg, '=');
    if (!dot || !eq || eq < dot) {
        log_error("--set: '%s' is not technique.parameter=value", arg);
        return -1;
    }
    char tech[64], name[64];
    snprintf(tech, sizeof tech, "%.*s", (int)(dot - arg), arg);
    snprintf(name, sizeof name, "%.*s", (int)(eq - dot - 1), dot + 1);
    const struct technique *t = technique_find(tech);
    if (!t) {
        log_error("--set: unknown technique '%s'", tech);
        return -1;
    }
    const int index = technique_index(t);
    if (!o->settings[index])
        o->settings[index] = params_defaults(t);
    const struct technique_param *p = params_find(t, name);
    if (p && p - t->params < 64)  /* tune holds it there (tuner.h) */
        o->held[index] |= 1ull << (p - t->params);
    return params_set(t, o->settings[index], name, eq + 1);
}

static int set_sweep(struct options *o, const char *arg)
{
    if (o->sweep_count == CONFIG_MAX_SWEEPS) {
        log_error("--sweep: at most %d sweeps", CONFIG_MAX_SWEEPS);
        return -1;
    }
    o->sweeps[o->sweep_count++] = arg;
    return 0;
}

static int set_gt_samples(struct options *o, const char *text)
{
    if (options_int("gt-samples", text, 1, GT_MAX_SAMPLES, &o->gt_samples))
        return -1;
    int n = (int)lround(sqrt((double)o->gt_samples));
    if (n * n != o->gt_samples) {
        int lo = (int)floor(sqrt((double)o->gt_samples));
        log_error("--gt-samples: %d is not a square number (n*n stratified light samples, e.g. "
                  "%d or %d)", o->gt_samples, lo * lo, (lo + 1) * (lo + 1));
        return -1;
    }
    return 0;
}

static int set_frames(struct options *o, const char *text)
{
    const int hi = o->cmd == CMD_STABILITY ? STABILITY_MAX_FRAMES
                   : o->cmd == CMD_VIEW    ? SCRIPT_MAX_FRAME
                                           : STAGE_TIMER_MAX_FRAMES;
    return options_int("frames", text, o->cmd == CMD_STABILITY ? STABILITY_MIN_FRAMES : 1, hi, &o->frames);
}

static int add_spec(const char *opt, const char **list, int *n, int max, const char *arg)
{
    if (*n == max) {
        log_error("--%s: at most %d", opt, max);
        return -1;
    }
    list[(*n)++] = arg;
    return 0;
}

static int set_motion(struct options *o, const char *arg)
{
    return add_spec("motion", o->motions, &o->motion_count, CLI_MAX_MOTIONS, arg);
}

static int set_vary(struct options *o, const char *arg)
{
    return add_spec("vary", o->varies, &o->vary_count, CLI_MAX_VARIES, arg);
}

static int set_accumulate(struct options *o, const char *arg)
{
    char *end;
    errno = 0;
    o->accumulate = strtod(arg, &end);
    if (!*arg || *end || errno || !(o->accumulate > 0 && o->accumulate <= 1)) {
        log_error("--accumulate: '%s' is not a number in (0, 1]", arg);
        return -1;
    }
    return 0;
}

static int set_no_cache(struct options *o, const char *arg)
{
    (void)arg;
    o->cache_dir = NULL;
    return 0;
}

static int set_gl(struct options *o, const char *arg)
{
    if (gl_backend_parse(arg, &o->gl) == 0)
        return 0;
    log_error("--gl %s: not a GL backend (osmesa, egl)", arg);
    return -1;
}

static int set_timing(struct options *o, const char *arg)
{
    if (stage_timing_parse(arg, &o->timing) == 0)
        return 0;
    log_error("--timing %s: not a timing method (auto, wall, query)", arg);
    return -1;
}

static int set_tuned(struct options *o, const char *arg)
{
    o->tuned_given = true;
    return options_folder("tuned", arg, &o->tuned_dir);
}

static int set_shard(struct options *o, const char *arg)
{
    return shard_parse("shard", arg, &o->shard);
}

static int set_settings_mode(struct options *o, const char *arg)
{
    static const char *const modes[] = {"auto", "both", "default", "tuned", NULL};  /* enum config_mode's order */
    int mode;
    const int rc = options_choice("settings", arg, modes, &mode);
    o->settings_mode = rc ? o->settings_mode : (enum config_mode)mode;
    return rc;
}

static const char *const objective_names[] = {"penumbra_rmse", "rmse", "shaded_rmse", NULL};

static const char *const cost_names[] = {"ms", "fetches", NULL};
static int set_cost(struct options *o, const char *arg)
{
    int k = 0;
    const int rc = options_choice("cost", arg, cost_names, &k);
    o->cost_fetches = rc ? o->cost_fetches : k == 1;
    return rc;
}

static int set_objective(struct options *o, const char *arg)
{
    static const int metrics[] = {METRIC_penumbra_rmse, METRIC_rmse, METRIC_shaded_rmse};
    int k;
    const int rc = options_choice("objective", arg, objective_names, &k);
    o->objective = rc ? o->objective : metrics[k];
    return rc;
}

static int set_cascade_split(struct options *o, const char *arg)
{
    struct cascade_settings *c = &o->cascades;
    char *end;
    if (!strncmp(arg, "practical:", 10)) {
        errno = 0;
        const double l = strtod(arg + 10, &end);
        if (!arg[10] || *end || errno || !(l >= 0 && l <= 1)) {
            log_error("--cascade-split %s: practical's lambda is a number in [0, 1]", arg);
            return -1;
        }
        c->split = CASCADE_SPLIT_PRACTICAL, c->lambda = (float)l;
        return 0;
    }
    for (int k = 0; k < CASCADE_SPLIT_FRACTIONS; k++)
        if (!strcmp(arg, cascade_split_names[k])) {
            c->split = (enum cascade_split)k;
            return 0;
        }
    /* f1,f2,...: increasing fractions of the shadow distance */
    o->fractions_given = 0;
    for (const char *at = arg;; at = end + 1) {
        errno = 0;
        const double f = strtod(at, &end);
        const double last = o->fractions_given ? c->fractions[o->fractions_given - 1] : 0.0;
        if (end == at || errno || (*end && *end != ',') || !(f > last && f < 1) ||
            o->fractions_given == CASCADES_MAX - 1) {
            log_error("--cascade-split %s: not uniform, log, practical:LAMBDA, or up to %d increasing fractions "
                      "in (0, 1) separated by commas", arg, CASCADES_MAX - 1);
            return -1;
        }
        c->fractions[o->fractions_given++] = (float)f;
        if (!*end)
            break;
    }
    c->split = CASCADE_SPLIT_FRACTIONS;
    return 0;
}

static int set_shadow_distance(struct options *o, const char *arg)
{
    if (!strcmp(arg, "view")) {
        o->cascades.shadow_distance = 0;
        return 0;
    }
    char *end;
    errno = 0;
    const double d = strtod(arg, &end);
    if (!*arg || *end || errno || !(d > 0 && d < 1e9)) {
        log_error("--shadow-distance %s: not a distance > 0 in world units, or 'view'", arg);
        return -1;
    }
    o->cascades.shadow_distance = (float)d;
    return 0;
}

static int set_on_off(const char *opt, const char *arg, int *out)
{
    static const char *const names[] = {"off", "on", NULL};
    return options_choice(opt, arg, names, out);
}

static int set_cascade_fit(struct options *o, const char *arg)
{
    static const char *const names[] = {"box", "sphere", NULL};  /* enum cascade_fit's order */
    int k;
    const int rc = options_choice("cascade-fit", arg, names, &k);
    o->cascades.fit = rc ? o->cascades.fit : (enum cascade_fit)k;
    return rc;
}

static int set_cascade_width(struct options *o, const char *arg)
{
    static const char *const names[] = {"world", "texel", NULL};  /* enum cascade_width's order */
    int k;
    const int rc = options_choice("cascade-width", arg, names, &k);
    o->cascades.width = rc ? o->cascades.width : (enum cascade_width)k;
    return rc;
}

static int set_cascade_snap(struct options *o, const char *arg)
{
    return set_on_off("cascade-snap", arg, &o->cascades.snap);
}

static int set_depth_clamp(struct options *o, const char *arg)
{
    return set_on_off("depth-clamp", arg, &o->cascades.depth_clamp);
}

static int set_cascade_blend(struct options *o, const char *arg)
{
    char *end;
    errno = 0;
    const double f = strtod(arg, &end);
    if (!*arg || *end || errno || !(f >= 0 && f <= 0.5)) {
        log_error("--cascade-blend %s: not a fraction of a slice in [0, 0.5]", arg);
        return -1;
    }
    o->cascades.blend = (float)f;
    return 0;
}

static int set_quiet(struct options *o, const char *arg)
{
    (void)o, (void)arg;
    log_set_level(LOG_ERROR);
    return 0;
}

static int set_verbose(struct options *o, const char *arg)
{
    (void)o, (void)arg;
    log_set_level(LOG_DEBUG);
    return 0;
}

/* ---- the table ----------------------------------------------------------- */

/* In the order --help lists them. {D} in a help text is the command's
 * default (OPTION_INT, OPTION_FOLDER and OPTION_TEXT rows). */
const struct option_row option_rows[] = {
    {"scene", 0, "S", RENDERING | ON(GT), OPTION_NONE, 0, 0, 0, set_scene,
     "a glTF file, or the name of a shipped scene (repeatable; default: every shipped scene, see "
     "'shadowbench list')"},
    {"technique", 0, "T[,T...]", RENDERING, OPTION_NONE, 0, 0, 0, set_techniques,
     "techniques to run (repeatable; default: all of shadowbench's own, see 'shadowbench list'); engines: every "
     "engine cell (a real engine in headless Chromium, docs/engines.md); presets: every preset (an engine's shipped "
     "filter as shadowbench's shader, docs/presets.md); or an engine's name (three, godot) for its modes and presets"},
    {"engine-timeout", 0, "S", ON(RUN) | ON(TUNE) | ON(CHECK), OPTION_INT, FIELD(engine_timeout), 1, 3600, NULL,
     "the longest an engine cell may take, seconds, its browser's start included (default {D})"},
    {"keep-going", 0, NULL, ON(RUN), OPTION_FLAG, FIELD(keep_going), 0, 0, NULL,
     "an engine cell that fails is marked failed in the matrix and the run goes on (its exit status is still 2)"},
    {"set", 0, "T.P=V", ON(RUN) | ON(BENCH) | ON(TUNE) | ON(STABILITY) | ON(VIEW), OPTION_NONE, 0, 0, 0,
     set_parameter,
     "set parameter P of technique T (repeatable), e.g. --set hard.slope_bias=2; ranges in 'shadowbench list'; "
     "tune holds it there and searches the others"},
    {"sweep", 0, "T.P=V1,V2,...", ON(RUN), OPTION_NONE, 0, 0, 0, set_sweep,
     "one cell per value of parameter P of technique T, on every scene, instead of T's single cell (repeatable; "
     "sweeps of one technique give every combination; a swept value overrides --set), e.g. --sweep "
     "pcss.blocker_samples=16,32,64. Each cell is named T@P=V,... (its folder under each scene)"},
    {"settings", 0, "auto|tuned|default|both", ON(RUN), OPTION_NONE, 0, 0, 0, set_settings_mode,
     "which cells of each technique: T@tuned, the settings --tuned DIR/T.json holds for each scene, chosen by "
     "'shadowbench tune' on the other scenes of its light kind (a scene it did not see gets the setting chosen "
     "on its light kind's scenes, else on all); T at its defaults (with --set, --sweep); or both. auto (default): "
     "T@tuned, or T's default cells when T has no "
     "tuned file or when any --set or --sweep is given (then every technique's)"},
    {"tuned", 0, "DIR", ON(RUN) | ON(CHECK) | ON(TUNE), OPTION_FOLDER, FIELD(tuned_dir), 0, 0, set_tuned,
     "where the tuned settings are (default {D})"},
    {"width", 0, "W", (RENDERING & ~ON(CHECK)) | ON(GT), OPTION_INT, FIELD(width), RECEIVER_MIN_SIZE, RECEIVER_MAX_SIZE, NULL,
     "image width in pixels, " UTIL_STR(RECEIVER_MIN_SIZE) ".." UTIL_STR(RECEIVER_MAX_SIZE) " (default {D})"},
    {"height", 0, "H", (RENDERING & ~ON(CHECK)) | ON(GT), OPTION_INT, FIELD(height), RECEIVER_MIN_SIZE, RECEIVER_MAX_SIZE,
     NULL, "image height in pixels, " UTIL_STR(RECEIVER_MIN_SIZE) ".." UTIL_STR(RECEIVER_MAX_SIZE) " (default {D})"},
    {"gt-samples", 0, "N", TRACING | ON(VIEW), OPTION_INT, FIELD(gt_samples), 0, 0, set_gt_samples,
     "light samples per pixel of the ground truth, a square n*n, 1.." UTIL_STR(GT_MAX_SAMPLES) " (default {D})"},
    {"shadow-map-size", 0, "N", RENDERING & ~ON(CHECK), OPTION_INT, FIELD(shadow_map_size), SHADOWMAP_MIN_SIZE,
     SHADOWMAP_MAX_SIZE, NULL,
     "shadow map resolution in texels, " UTIL_STR(SHADOWMAP_MIN_SIZE) ".." UTIL_STR(SHADOWMAP_MAX_SIZE)
     " (default {D})"},
    {"cascades", 0, "N", CASCADED, OPTION_INT, FIELD(cascades.count), 1, CASCADES_MAX, NULL,
     "the sun's cascaded shadow maps: the view cut by depth into N slices, a map of --shadow-map-size each, "
     "1.." UTIL_STR(CASCADES_MAX) " (default 1: one map over the whole view, Filament's default). Area lights "
     "have one map; the cascade options apply to the sun (docs/cascades.md)"},
    {"cascade-split", 0, "uniform|log|practical:L|F1,F2,...", CASCADED, OPTION_NONE, 0, 0, 0, set_cascade_split,
     "where the slices meet, in view depth: equal steps, equal ratios from the camera's near plane, the mix "
     "L log + (1 - L) uniform (default practical:0.5, three.js's CSM addon), or the N - 1 splits as fractions of "
     "the shadow distance (Filament's default 0.125,0.25,0.5; Unity HDRP's 0.05,0.15,0.3)"},
    {"shadow-distance", 0, "M|view", CASCADED, OPTION_NONE, 0, 0, 0, set_shadow_distance,
     "the far end of the last slice, world units: past it nothing is shadowed and nothing scored (default view: "
     "the farthest point the camera sees, Filament's shadowFar 0)"},
    {"cascade-fit", 0, "box|sphere", CASCADED, OPTION_NONE, 0, 0, 0, set_cascade_fit,
     "each map fitted to the geometry its slice sees (box, default, Filament) or to the slice's bounding sphere, "
     "a size that turning the camera does not change (sphere: Unity's stable fit)"},
    {"cascade-snap", 0, "on|off", CASCADED, OPTION_NONE, 0, 0, 0, set_cascade_snap,
     "move each map's window in whole texels, so that a moving camera does not move the texel grid on the "
     "ground (Godot, Unity; default off, Filament's); holds the grid still only with the sphere fit"},
    {"cascade-blend", 0, "F", CASCADED, OPTION_NONE, 0, 0, 0, set_cascade_blend,
     "the band at each slice's far end where the next cascade fades in, a fraction of the slice in [0, 0.5] "
     "(default 0: a hard switch, Filament; Unity HDRP blends)"},
    {"depth-clamp", 0, "on|off", CASCADED, OPTION_NONE, 0, 0, 0, set_depth_clamp,
     "pancaking: each map's near plane at its slice's nearest receiver, casters in front clamped onto it "
     "(Unity; default off: the near plane at the nearest caster)"},
    {"cascade-width", 0, "world|texel", CASCADED, OPTION_NONE, 0, 0, 0, set_cascade_width,
     "the PCSS family's sizes from the sun's angle in each cascade's own world units (world, default, as Unity "
     "HDRP converts them), or cascade 0's ratio on each cascade's normalised depth (texel: what most engines "
     "compute, so softness jumps at a split)"},
    {"frames", 0, "K", RENDERING & ~ON(CHECK), OPTION_INT, FIELD(frames), 0, 0, set_frames,
     "timed frames per cell, the median and quartiles reported, 1.." UTIL_STR(STAGE_TIMER_MAX_FRAMES)
     " (default {D})"},
    {"warmup", 0, "K", ON(RUN) | ON(BENCH) | ON(TUNE), OPTION_INT, FIELD(warmup), 0, CLI_MAX_WARMUP, NULL,
     "untimed frames per cell before them, 0.." UTIL_STR(CLI_MAX_WARMUP) " (default {D})"},
    {"out", 0, "DIR", TRACING | ON(CHECK), OPTION_FOLDER, FIELD(out_dir), 0, 0, NULL, "output folder (default {D})"},
    {"shard", 0, "K/N", ON(RUN) | ON(TUNE) | ON(CHECK) | ON(STABILITY), OPTION_NONE, 0, 0, 0, set_shard,
     "do shard K of N of the cells (K from 1, as Slurm's array index): every cell belongs to one shard, chosen from "
     "the cells alone and balanced by their expected cost (run, check: a cell; tune: a technique's tuning; "
     "stability: a motion or variation on a scene); --out holds this shard's complete outputs and its "
     "shard.json, and 'shadowbench merge' builds what the command unsharded writes (docs/scale-out.md)"},
    {"cache", 0, "DIR", TRACING | ON(CHECK), OPTION_FOLDER, FIELD(cache_dir), 0, 0, NULL,
     "ground-truth cache (default {D})"},
    {"no-cache", 0, NULL, TRACING | ON(CHECK), OPTION_NONE, 0, 0, 0, set_no_cache,
     "always ray trace the ground truth, store nothing"},
    {"shaders", 0, "DIR", RENDERING, OPTION_TEXT, FIELD(shader_dir), 0, 0, NULL,
     "GLSL folder (default: found next to the executable or in the source tree; or $SHADOWBENCH_SHADERS)"},
    {"gl", 0, "osmesa|egl", RENDERING & ~ON(VIEW), OPTION_NONE, 0, 0, 0, set_gl,
     "the GL context: osmesa (default: llvmpipe, the CPU) or egl (headless: a GPU through EGL's device platform "
     "where one is present, else Mesa's surfaceless llvmpipe); the outputs name the renderer"},
    {"timing", 0, "auto|wall|query", ON(RUN) | ON(BENCH) | ON(TUNE), OPTION_NONE, 0, 0, 0, set_timing,
     "how stages are timed: wall clock around glFinish or GL_TIME_ELAPSED queries; auto (default): wall on a CPU "
     "rasteriser (llvmpipe, where queries do not measure the work), queries on a GPU"},
    {"baselines", 0, "DIR", ON(CHECK), OPTION_FOLDER, FIELD(baselines_dir), 0, 0, NULL,
     "the baselines (default {D})"},
    {"update", 0, NULL, ON(CHECK), OPTION_FLAG, FIELD(update), 0, 0, NULL,
     "record the selected cells anew, as one set (stopped before the end, none is), printing what moved; "
     "tolerances from the metrics' spread over "
     UTIL_STR(BASELINE_SEEDS) " ground-truth seeds. Commit them with the change that moved them, after looking at "
     "the page"},
    {"strict", 0, NULL, ON(CHECK), OPTION_FLAG, FIELD(strict), 0, 0, NULL,
     "an improvement fails too, as do the baselines of a scene not shipped (ORPHANED)"},
    {"allow-uncommitted", 0, NULL, ON(CHECK) | ON(TUNE), OPTION_FLAG, FIELD(allow_uncommitted), 0, 0, NULL,
     "record (--update, --write-tuned) from a source tree whose code that renders or scores has uncommitted "
     "changes, which is refused otherwise; the files say so (their source_tree and command_line)"},
    {"cost", 0, "C", ON(TUNE), OPTION_NONE, 0, 0, 0, set_cost,
     "the frontiers' cost axis: ms (default: ms_total on this device) or fetches (fetches_per_pixel, counted on "
     "the device: a cost that holds on any GPU; the search then scores a counting frame)"},
    {"objective", 0, "M", ON(TUNE), OPTION_NONE, 0, 0, 0, set_objective,
     "the error minimised, averaged over the scenes: penumbra_rmse (default), rmse or shaded_rmse"},
    {"write-tuned", 0, NULL, ON(TUNE), OPTION_FLAG, FIELD(write_tuned), 0, 0, NULL,
     "also write the tuned settings for run (see --tuned), as one set once every technique is tuned (stopped "
     "before, the folder stays as it was)"},
    {"motion", 0, "M[=STEP]", ON(STABILITY), OPTION_NONE, 0, 0, 0, set_motion,
     "a motion of --frames frames (repeatable), one of the motions below"},
    {"vary", 0, "NAME=V1,V2,...", ON(STABILITY), OPTION_NONE, 0, 0, 0, set_vary,
     "one thing at each listed value (repeatable), NAME one of the variables below"},
    {"accumulate", 0, "A", ON(STABILITY), OPTION_NONE, 0, 0, 0, set_accumulate,
     "the new frame's weight in the moving average, (0, 1] (default " UTIL_STR(STABILITY_DEFAULT_ACCUMULATE) ")"},
    {"screenshot", 0, "FILE", ON(VIEW), OPTION_TEXT, FIELD(screenshot), 0, 0, NULL,
     "write the window's last frame to FILE (PNG) and exit (after 1 frame unless --frames); that frame first "
     "waits for the pose's last ground-truth level"},
    {"script", 0, "FILE", ON(VIEW), OPTION_TEXT, FIELD(script), 0, 0, NULL,
     "key events to replay: lines 'FRAME KEY' (the key pressed before frame FRAME, counted from 0; KEY: A-Z, 0-9, "
     "TAB, SPACE, LEFT, RIGHT, UP, DOWN, MINUS, EQUAL, LEFT_BRACKET, RIGHT_BRACKET, ESCAPE, each optionally "
     "shift+KEY); # comments"},
    {"markdown", 0, NULL, ON(HELP), OPTION_FLAG, FIELD(markdown), 0, 0, NULL,
     "every command's help as one Markdown page (docs/cli.md)"},
    {"quiet", 'q', NULL, ~0u, OPTION_NONE, 0, 0, 0, set_quiet, "only errors on stderr"},
    {"verbose", 'v', NULL, ~0u, OPTION_NONE, 0, 0, 0, set_verbose, "GL debug messages too"},
    {"help", 'h', NULL, ~0u, OPTION_HELP, 0, 0, 0, NULL, "this help"},
    {NULL},
};
