/* The command table (git's cmd_struct): every command's name, summary,
 * entry, defaults and help, the only place a command is described. */
#include "options.h"
#include "pipeline/stability.h"
#include "scene/motion.h"
#include "score/baseline.h"
#include "score/break_rule.h"
#include "score/tune_search.h"
#include "view/script.h"
#include "view/viewer.h"

#include <ctype.h>
#include <stdlib.h>

#define NOTES(...) ((const struct option_note[]){__VA_ARGS__, {NULL, NULL}})

/* stability's motions and variables, from their tables. */
static void stability_more(struct strbuf *out)
{
    strbuf_printf(out, "\nmotions (--motion NAME[=STEP]):\n");
    for (int k = 0; k < MOTION_KIND_COUNT; k++) {
        const struct motion_kind_info *m = &motion_kinds[k];
        struct strbuf line = {0};
        if (k == MOTION_STATIC)
            strbuf_printf(&line, "%s: every deterministic technique's flicker is exactly the floor (0)", m->help);
        else
            strbuf_printf(&line, "%s; STEP in %s (default %g, at most %g)", m->help, m->unit, m->def, m->max);
        cli_help_item(out, k == MOTION_CASTER_SHIFT ? "caster_shift:NODE" : m->name, line.data);
        strbuf_free(&line);
    }
    cli_help_item(out, "scene", "each scene's own motions, listed in its file as extras.shadowbench.motions "
                                "(strings as above, e.g. \"caster_shift:sphere=0.25\")");
    strbuf_printf(out, "\nvariables (--vary NAME=V1,V2,...; the reference value is added when not listed):\n");
    for (int k = 0; k < VARY_PARAM; k++) {
        char *line = util_printf("%s, %g..%g", stability_variables[k].help, stability_variables[k].lo,
                                 stability_variables[k].hi);
        cli_help_item(out, stability_variables[k].name, line);
        free(line);
    }
    cli_help_item(out, "T.P", "a parameter of technique T (its values as for --set), e.g. "
                              "pcf.radius_texels=1,2,4,8; reference: its setting");
    char *rule = util_printf("%s. Its break points: the first broken value below and above the reference.",
                             break_rule_text);
    rule[0] = (char)toupper((unsigned char)rule[0]);  /* the rule is written to follow "Break rule: " */
    strbuf_printf(out, "\n");
    cli_help_wrap(out, rule, 0, 0);
    free(rule);
    struct strbuf d = {0};
    strbuf_printf(&d, "With no --motion and no --vary: --motion");
    for (int i = 0; i < STABILITY_DEFAULT_MOTIONS; i++)
        strbuf_printf(&d, "%s%s", i ? ", " : " ", stability_default_motions[i]);
    strbuf_printf(&d, " (at their default steps) and --vary");
    for (int i = 0; i < STABILITY_DEFAULT_VARIES; i++)
        strbuf_printf(&d, "%s%s", i ? ", " : " ", stability_default_varies[i]);
    strbuf_printf(&d, ". With no --scene: the scenes");
    for (int i = 0; i < STABILITY_DEFAULT_SCENES; i++)
        strbuf_printf(&d, "%s%s", i ? ", " : " ", stability_default_scenes[i]);
    strbuf_printf(&d, ".");
    strbuf_printf(out, "\n");
    cli_help_wrap(out, d.data, 0, 0);
    strbuf_free(&d);
}

const struct command_def commands[COMMAND_COUNT] = {
    [CMD_RUN] = {
        .name = "run", .main = run_main, .synopsis = "run [options]",
        .summary = "every scene x technique: render, score, write the report (the main job)",
        .size = CLI_DEFAULT_SIZE, .frames = 2, .warmup = 0, .out = "results/runs/latest",
        .about =
            "Renders every selected technique on every selected scene headless (OSMesa, or\n"
            "EGL with --gl egl), scores its visibility V_tech against the ray-traced ground\n"
            "truth V_gt and writes, under --out: report.html (open it in a browser, no\n"
            "server needed), matrix.csv, matrix.json, run.json, charts/*.svg (error against\n"
            "time with the Pareto front, per scene and over all scenes; failure metrics per\n"
            "technique) and per scene/cell visibility.exr, error.exr, visibility.png,\n"
            "heatmap.png, metrics.json (docs/outputs.md). With no options: every shipped\n"
            "scene x every technique at its tuned settings (--settings both adds each one's\n"
            "defaults, twice the cells). The total time is printed at the end.\n",
        .notes = NOTES({"warmup", "untimed frames per cell before them, 0.." UTIL_STR(CLI_MAX_WARMUP)
                                  " (default {D}: the render that scores each cell comes first and warms it)"},
                       {"gl", "the GL context: osmesa (default: llvmpipe, the CPU) or egl (headless: a GPU "
                              "through EGL's device platform where one is present, else Mesa's surfaceless "
                              "llvmpipe); run.json names the renderer, vendor, platform and timing method"}),
        .after =
            "Timing: a scene's cells are first rendered and scored, one by one, then timed\n"
            "interleaved, one frame of each in turn, so a slow spell of the machine is\n"
            "shared ('bench' times one scene with more frames); a cell's frame renders its\n"
            "shadow-map products afresh, then its receiver pass. On llvmpipe these are\n"
            "CPU-rasteriser times: full-map passes cost far more against texture fetches\n"
            "than on a GPU, so they rank techniques for this device only.\n"
            "\n"
            "The ground truth is cached by the scene file's hash, image size, sample count\n"
            "and ground-truth code version; a second run of the same settings reuses it.\n"
            "A cell with no pixel to score reports null metrics and makes the exit status 1.\n",
    },
    [CMD_GT] = {
        .name = "gt", .main = gt_main, .synopsis = "gt --scene S [options]",
        .summary = "ray trace one scene's ground truth into an EXR",
        .one_scene = true, .needs_scene = true, .out = "results/gt",
        .about =
            "Ray traces the ground truth of one scene (Embree, all cores) and writes\n"
            "DIR/<scene>/groundtruth.exr with channels V (of the light above the surface's\n"
            "tangent plane, the fraction that reaches it unblocked), V_weighted (the same,\n"
            "cos-weighted), H (the fraction of the light above the tangent plane), E\n"
            "(unshadowed irradiance, unit radiance) and mask (1 where H >= 0.05 inside the\n"
            "light's frustum), plus a PNG. Prints the noise floor (the rms error of V\n"
            "itself, from the two halves of the same samples).\n",
        .notes = NOTES({"scene", "a glTF file, or the name of a shipped scene (required)"}),
    },
    [CMD_BENCH] = {
        .name = "bench", .main = bench_main, .synopsis = "bench [options]",
        .summary = "median time of each stage of each technique on one scene",
        .one_scene = true, .size = 1024, .frames = 9, .warmup = 3,
        .about =
            "Times every selected technique on one scene, without ground truth or files:\n"
            "the median time (--timing) of K frames after warm-up, per stage: shadow map\n"
            "(the depth pass), filter prep (moments, blur, mipmaps, summed-area table) and\n"
            "receiver pass, and the median and quartiles of the frame totals. Each column\n"
            "is its own median, so with several frames the stages need not add up to the\n"
            "total. Then the texture-fetch limit on the same scene: a receiver pass that\n"
            "does only the depth fetches of each PCF-family technique, and the ratio of\n"
            "the technique's receiver pass to it. The techniques and probes are timed\n"
            "interleaved, one frame of each in turn.\n",
        .notes = NOTES({"scene", "a glTF file or shipped scene (default: the first shipped)"},
                       {"technique", "techniques to time (default: all)"}),
    },
    [CMD_CHECK] = {
        .name = "check", .main = check_main, .synopsis = "check [options]",
        .summary = "the regression check: every baseline cell rendered again and compared",
        .out = "results/check",
        .about =
            "The regression check per technique. Renders every baseline cell again at the\n"
            "settings it records (results/baselines/<scene>/<cell>.json and its V_tech,\n"
            "<cell>.png: " UTIL_STR(BASELINE_SIZE) "x" UTIL_STR(BASELINE_SIZE) ", " UTIL_STR(BASELINE_GT_SAMPLES)
            " ground-truth samples, the default shadow map)\n"
            "and compares: a metric worse than its recorded tolerance, or a picture that\n"
            "moved (a share of more than " UTIL_STR(BASELINE_PIXEL_FRACTION) " of its pixels by more than "
            UTIL_STR(BASELINE_PIXEL_THRESHOLD) ") with no\n"
            "metric better, is REGRESSED; a metric better than its tolerance with none\n"
            "worse is 'improved'. Cells: every technique at its defaults (and at its tuned\n"
            "settings) on every shipped scene, and the cells each technique declares in\n"
            "its descriptor (.regression in techniques/<name>.c) that set each parameter\n"
            "away from its default. For each of those, setting the parameter back must\n"
            "change the picture. One line per cell; what moved under it. Under --out:\n"
            "check.html with a V_now - V_baseline heatmap of each cell that moved.\n",
        .notes = NOTES({"scene", "check only this scene's cells (repeatable)"},
                       {"technique", "check only these techniques' cells"},
                       {"out", "where check.html goes (default {D})"},
                       {"tuned", "the tuned settings of the T@tuned cells (default {D})"}),
        .after =
            "exit status: 0 every cell passed; 1 a cell regressed, has no baseline or\n"
            "records parameters its name no longer means, an improvement or baselines of a\n"
            "scene not shipped (ORPHANED) with --strict, or a parameter that no cell sets or\n"
            "that changes nothing; 2 bad usage or an unreadable baseline (one line naming\n"
            "the file and the problem), or an engine that cannot render. --update records the cells as one set: stopped\n"
            "before the end, it leaves the baselines as they were.\n",
    },
    [CMD_TUNE] = {
        .name = "tune", .main = tune_main, .synopsis = "tune [options]",
        .summary = "each technique's parameters explored: its frontier (error against time) and a setting "
                   "per scene chosen on the other scenes",
        .size = CLI_DEFAULT_SIZE, .frames = 3, .warmup = 0, .out = "results/tune/latest",
        .about =
            "Explores each technique's parameters over the scenes, to answer: for a time\n"
            "budget, which technique and which setting is least wrong? The values explored\n"
            "are each parameter's tune values ('shadowbench list'); the search is\n"
            "coordinate descent on the mean objective from the defaults: each parameter in\n"
            "turn at every value with the others held, the best taken, rounds until nothing\n"
            "moves (at most " UTIL_STR(TUNE_MAX_ROUNDS) "). No randomness: the same code gives the same choices. Per\n"
            "technique, it searches every scene; every scene but one, for each scene (that\n"
            "scene's tuned setting, scored on it: leave-one-scene-out cross-validation).\n"
            "Each scene's oracle is the best of every setting tried on it (fitted to it,\n"
            "not a prediction). Every cell is timed; the frontier is the Pareto front of\n"
            "error against time over every setting tried, over all scenes and per scene.\n"
            "\n"
            "Writes DIR/<technique>.json (settings, folds, frontier, provenance) and\n"
            "DIR/tune.json (\"complete\" once every technique is done); with --write-tuned\n"
            "also the --tuned folder's <technique>.json, which 'run' uses for its T@tuned\n"
            "cells.\n",
        .notes = NOTES({"scene", "scenes to tune on (repeatable, at least 2; default: every shipped scene)"},
                       {"technique", "techniques to tune (default: all)"},
                       {"tuned", "where --write-tuned writes (default {D})"},
                       {"shadow-map-size", "shadow map resolution in texels, " UTIL_STR(SHADOWMAP_MIN_SIZE) ".."
                                           UTIL_STR(SHADOWMAP_MAX_SIZE) " (default {D}): the texel-sized "
                                           "parameters are tuned for this size"},
                       {"frames", "timed frames of each cell the files report (the search times one), 1.."
                                  UTIL_STR(STAGE_TIMER_MAX_FRAMES) " (default {D})"},
                       {"warmup", "untimed frames first, 0.." UTIL_STR(CLI_MAX_WARMUP) " (default {D}: those "
                                  "cells were rendered before)"}),
        .after =
            "The default (every technique on every shipped scene) takes about half an hour\n"
            "on a 2-core CPU with llvmpipe; progress and an ETA go to stderr.\n",
    },
    [CMD_STABILITY] = {
        .name = "stability", .main = stability_main, .synopsis = "stability [options]",
        .summary = "flicker under motion, and where each technique breaks as the shadow map, the light or a "
                   "parameter varies",
        .size = 256, .frames = 16, .out = "results/stability/latest",
        .about =
            "Where methods fail, on purpose. Two modes, both run when neither is named:\n"
            "\n"
            "--motion: the scene moves for --frames frames; every frame is ray traced anew\n"
            "(cached per pose) and rendered by every technique. Per technique: flicker, the\n"
            "mean over pixels and frame pairs of |dV_tech - dV_gt|, i.e. of\n"
            "|e_t - e_(t-1)| with e = V_tech - V_gt (pixels scored in both frames of a pair\n"
            "count; one that enters or leaves the mask is counted as mask_changes), its\n"
            "99th percentile, the ground truth's own frame-to-frame noise (flicker_floor: a\n"
            "flicker not above it is marked not meaningful) and the frames' rmse.\n"
            "Techniques with per-pixel noise (pcf's and pcss's rotation) are measured with\n"
            "the noise still (T) and animated by the frame index (T~anim: animate_noise on,\n"
            "Jimenez 2014), and each also accumulated by the moving average TAA keeps\n"
            "(T+ema, T~anim+ema), reprojected where the camera moves.\n"
            "\n"
            "--vary: one thing takes each listed value; every technique's rmse,\n"
            "penumbra_rmse, leak_fraction and dark_fraction against it, and where it\n"
            "breaks. With neither, and without --scene, the defaults below.\n"
            "\n"
            "Writes, under --out: stability.html (open it in a browser: tables, charts, each\n"
            "motion's frames with a slider), stability.csv (one row per technique x motion\n"
            "variant or varied value), stability.json (the same, the break points, the\n"
            "rule), charts/*.svg, and <scene>/<motion>/<row>/visibility_frames.png and\n"
            "error_frames.png (the frames side by side). A run first removes what the last\n"
            "run into --out listed in its stability.json (its frames and charts), and\n"
            "nothing else.\n",
        .notes = NOTES({"scene", "a glTF file, or the name of a shipped scene (repeatable; default: see "
                                 "below)"},
                       {"frames", "frames of each motion, " UTIL_STR(STABILITY_MIN_FRAMES) ".."
                                  UTIL_STR(STABILITY_MAX_FRAMES) " (default {D})"}),
        .after =
            "exit status: 0 done; 1 a technique produced NaN/Inf or a motion had nothing\n"
            "to score, or a runtime error; 2 bad usage or input.\n",
        .more = stability_more,
    },
    [CMD_MERGE] = {
        .name = "merge", .main = merge_main, .synopsis = "merge OUT SHARD...", .operands = true,
        .summary = "the shards of a run, tuning, check or stability study (--shard K/N) into the one output the "
                   "command writes unsharded",
        .about =
            "Builds in the folder OUT what the command the shards split would have written\n"
            "unsharded: a run's matrix, report, charts and cell folders (every metric as\n"
            "its shard measured it; each cell's times on the device that timed it); a\n"
            "tuning's records and tune.json, and with --write-tuned its --tuned folder as\n"
            "one set; a check's lines (on stdout), check.html and heatmaps, and the\n"
            "checks of the whole selection; a stability study's pages, data, charts and\n"
            "frames. Its record (run.json, tune.json, stability.json's run) lists every\n"
            "shard. Each SHARD is a folder a command with --shard K/N finished (its\n"
            "shard.json).\n"
            "\n"
            "It refuses, in one line, shards of another command line, of other code, of\n"
            "other scenes or of another ground-truth version, a shard given twice or one\n"
            "missing, and code of its own other than the shards'. tools/slurm-submit runs\n"
            "the shards as a Slurm array job and merges them (docs/scale-out.md).\n",
        .after =
            "exit status: that of the command unsharded over the merged cells (run: 1\n"
            "for a cell with NaN/Inf or none to score; check: 1 for a failure); 2 shards\n"
            "that do not merge.\n",
    },
    [CMD_VIEW] = {
        .name = "view", .main = view_main, .synopsis = "view --scene S [options]",
        .summary = "one scene in a window (GLFW): switch techniques, move the light and the camera, step "
                   "parameters, the ground truth refining behind",
        .one_scene = true, .needs_scene = true, .gt_samples = 256, .size = 512,
        .about =
            "Opens one scene in a window (GLFW, OpenGL 4.5 core) shaded by a technique:\n"
            "unshadowed shading (the area light's irradiance E, closed form) times V_tech.\n"
            "Each frame renders the technique's products afresh, then its receiver pass,\n"
            "each stage timed as bench times it, one frame at a time (the overlay shows a\n"
            "moving average; the ground truth's tracing shares the CPU with llvmpipe). The\n"
            "ground truth of each pose is ray traced on a second thread (all cores), at 1,\n"
            "4, 16, ... light samples per pixel up to --gt-samples, each level shown when\n"
            "done; with it the overlay gives rmse and penumbra_rmse. Without a display (a\n"
            "server, CI) run it under xvfb-run.\n"
            "\n"
            "keys:\n"
            "  Tab, Shift+Tab        next, previous technique (those of --technique, else all)\n"
            "  1 2 3 4 5             view: shaded (E x V_tech), V_tech, V_gt, signed error\n"
            "                        (V_tech - V_gt), E alone (" UTIL_STR(VIEWER_WHITE) " x its mean is white)\n"
            "  Space                 split screen: left technique | right technique\n"
            "  B, Shift+B            next, previous right-hand technique\n"
            "  [ ]                   select the left technique's previous, next parameter\n"
            "  - =                   its previous, next value (its tune list or choices;\n"
            "                        else int +-1, float x/1.25, within its range)\n"
            "  arrows                move the light along its own x and y\n"
            "  A D, W S, Q E         orbit the camera (yaw, pitch), move it closer, away\n"
            "  mouse                 left drag: orbit; right drag: move the light; wheel: closer\n"
            "  C, Shift+C            the sun's cascades: one more, one fewer (1..8)\n"
            "  V                     the PCSS family's widths per cascade: world, texel\n"
            "  R                     reset the light and the camera\n"
            "  H                     overlay on, off\n"
            "  Esc                   quit\n",
        .notes = NOTES({"scene", "a glTF file, or the name of a shipped scene (required)"},
                       {"technique", "the techniques Tab steps through, the first shown (default: all); the "
                                     "second is the split's right side"},
                       {"set", "as for run (repeatable): the settings the view starts from"},
                       {"gt-samples", "the ground truth's last level, a square n*n (default {D})"},
                       {"frames", "draw N frames, then exit, 1.." UTIL_STR(SCRIPT_MAX_FRAME) " (default: until the "
                                  "window closes)"},
                       {"quiet", "only errors on stderr (key events and refusals are logged at the default "
                                 "level)"}),
        .after =
            "exit status: 0 done; 1 a runtime error (a shader that does not compile, a\n"
            "screenshot not written); 2 bad usage or input, or no window system.\n",
    },
    [CMD_LIST] = {
        .name = "list", .main = list_main, .synopsis = "list", .about =
            "Lists every technique with its parameters (type, default, range, meaning) and\n"
            "every shipped scene with its description and the phenomenon it isolates.\n",
        .summary = "techniques with every parameter (default, range, meaning), and scenes",
    },
    [CMD_HELP] = {
        .name = "help", .main = help_main, .synopsis = "help [COMMAND] [--markdown]",
        .summary = "this list, a command's options, or every command's as Markdown",
        .about =
            "Prints the commands; with a command, its options (as 'shadowbench COMMAND\n"
            "--help'); with --markdown, every command's help as one page (docs/cli.md is\n"
            "this output).\n",
    },
};
