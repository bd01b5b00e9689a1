/* shadowbench: measures real-time shadow techniques against a ray-traced
 * area-light ground truth. This file is the command line only. */
#include "bench.h"
#include "check.h"
#include "catalog.h"
#include "run.h"
#include "stability.h"
#include "sweep.h"
#include "tune.h"
#include "tuned.h"
#include "view.h"
#include "base/log.h"
#include "base/util.h"
#include "render/stage_timer.h"
#include "scene/scene.h"
#include "techniques/params.h"
#include "techniques/shadowmap.h"
#include "techniques/technique.h"
#include "truth/groundtruth.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIZE_RANGE RUN_STR(RUN_MIN_SIZE) ".." RUN_STR(RUN_MAX_SIZE)
#define MAP_RANGE RUN_STR(SHADOWMAP_MIN_SIZE) ".." RUN_STR(SHADOWMAP_MAX_SIZE)

static const char usage_main[] =
    "usage: shadowbench <command> [options]\n"
    "\n"
    "Measures real-time shadow techniques against an Embree ray-traced area-light\n"
    "ground truth: error numbers, signed-error heatmaps, a comparison matrix, timings.\n"
    "\n"
    "commands:\n"
    "  run    every scene x technique: render, score, write the report (the main job)\n"
    "  gt     ray trace one scene's ground truth into an EXR\n"
    "  bench  median time of each stage of each technique on one scene\n"
    "  check  the regression check: every baseline cell rendered again and compared\n"
    "  tune   each technique's parameters explored: its frontier (error against\n"
    "         time) and a setting per scene chosen on the other scenes\n"
    "  stability  flicker under motion, and where each technique breaks as the\n"
    "         shadow map, the light or a parameter varies\n"
    "  view   one scene in a window (GLFW): switch techniques, move the light and\n"
    "         the camera, step parameters, the ground truth refining behind\n"
    "  list   techniques with every parameter (default, range, meaning), and scenes\n"
    "\n"
    "'shadowbench <command> --help' explains each command's options.\n"
    "exit status: 0 ok, 1 a check failed (e.g. NaN in a technique's output) or a\n"
    "runtime error, 2 bad usage or input.\n";

static const char usage_run[] =
    "usage: shadowbench run [options]\n"
    "\n"
    "Renders every selected technique on every selected scene headless (OSMesa, or\n"
    "EGL with --gl egl), scores its visibility V_tech against the ray-traced\n"
    "ground truth V_gt and\n"
    "writes, under --out: report.html (open it in a browser, no server needed),\n"
    "matrix.csv, matrix.json, run.json, charts/*.svg (error against time with the\n"
    "Pareto front, per scene and over all scenes; failure metrics per technique)\n"
    "and per scene/cell visibility.exr, error.exr, visibility.png, heatmap.png,\n"
    "metrics.json (see README.md, 'Outputs'). With no options: every shipped scene\n"
    "x every technique at its defaults. The total time is printed at the end.\n"
    "\n"
    "options:\n"
    "  --scene S             a glTF file, or the name of a shipped scene (repeatable;\n"
    "                        default: every shipped scene, see 'shadowbench list')\n"
    "  --technique T[,T...]  techniques to run (repeatable; default: all)\n"
    "  --set T.P=V           set parameter P of technique T (repeatable), e.g.\n"
    "                        --set hard.slope_bias=2; ranges in 'shadowbench list'\n"
    "  --settings default|tuned|both  which cells of each technique (default both):\n"
    "                        T at its defaults (with --set, --sweep), and T@tuned,\n"
    "                        the settings " TUNED_DEFAULT_DIR "/T.json holds for each\n"
    "                        scene, chosen by 'shadowbench tune' on the other scenes\n"
    "                        (a scene it did not see gets the setting chosen on all)\n"
    "  --tuned DIR           where the tuned settings are (default " TUNED_DEFAULT_DIR ")\n"
    "  --sweep T.P=V1,V2,... one cell per value of parameter P of technique T, on\n"
    "                        every scene, instead of T's single cell (repeatable;\n"
    "                        sweeps of one technique give every combination; a\n"
    "                        swept value overrides --set), e.g.\n"
    "                        --sweep pcss.blocker_samples=16,32,64. Each cell is\n"
    "                        named T@P=V,... (its folder under each scene)\n"
    "  --width W, --height H image size in pixels, " SIZE_RANGE " (default " RUN_STR(RUN_DEFAULT_SIZE)
    " x " RUN_STR(RUN_DEFAULT_SIZE) ")\n"
    "  --gt-samples N        light samples per pixel for the ground truth, a square\n"
    "                        n*n, 1.." RUN_STR(GT_MAX_SAMPLES) " (default " RUN_STR(GT_DEFAULT_SAMPLES) ")\n"
    "  --shadow-map-size N   shadow map resolution, " MAP_RANGE " (default "
    RUN_STR(SHADOWMAP_DEFAULT_SIZE) ")\n"
    "  --frames K            timed frames per cell; the median and quartiles are\n"
    "                        reported, 1.." RUN_STR(STAGE_TIMER_MAX_FRAMES) " (default " RUN_STR(RUN_DEFAULT_FRAMES) ")\n"
    "  --warmup K            untimed frames per cell before them, 0.." RUN_STR(RUN_MAX_WARMUP) " (default "
    RUN_STR(RUN_DEFAULT_WARMUP) ": the\n"
    "                        render that scores each cell comes first and warms it)\n"
    "  --out DIR             output folder (default " RUN_DEFAULT_OUT ")\n"
    "  --cache DIR           ground-truth cache (default " RUN_DEFAULT_CACHE ")\n"
    "  --no-cache            always ray trace the ground truth, store nothing\n"
    "  --shaders DIR         GLSL folder (default: found next to the executable or in\n"
    "                        the source tree; or $SHADOWBENCH_SHADERS)\n"
    "  --gl osmesa|egl       the GL context: osmesa (default: llvmpipe, the CPU) or egl\n"
    "                        (headless: a GPU through EGL's device platform where one\n"
    "                        is present, else Mesa's surfaceless llvmpipe); run.json\n"
    "                        names the renderer, vendor, platform and timing method\n"
    "  --timing auto|wall|query  how stages are timed: wall clock around glFinish or\n"
    "                        GL_TIME_ELAPSED queries; auto (default): wall on a CPU\n"
    "                        rasteriser (llvmpipe, where queries do not measure the\n"
    "                        work), queries on a GPU\n"
    "  -q, --quiet           only errors on stderr;  -v, --verbose: GL debug messages\n"
    "\n"
    "Timing: a scene's cells are first rendered and scored, one by one, then timed\n"
    "interleaved, one frame of each in turn, so a slow spell of the machine is\n"
    "shared ('bench' times one scene with more frames); a cell's frame renders its shadow-map\n"
    "products afresh, then its receiver pass, each stage timed by the wall clock\n"
    "around glFinish. On llvmpipe these are CPU-rasteriser times: full-map passes\n"
    "cost far more against texture fetches than on a GPU, so they rank techniques\n"
    "for this device only.\n"
    "\n"
    "The ground truth is cached by the scene file's hash, image size, sample count\n"
    "and ground-truth code version; a second run of the same settings reuses it.\n"
    "A cell with no pixel to score reports null metrics and makes the exit status 1.\n";

static const char usage_gt[] =
    "usage: shadowbench gt --scene S [options]\n"
    "\n"
    "Ray traces the ground truth of one scene (Embree, all cores) and writes\n"
    "DIR/<scene>/groundtruth.exr with channels V (of the light above the surface's\n"
    "tangent plane, the fraction that reaches it unblocked), V_weighted (the same,\n"
    "cos-weighted), H (the fraction of the light above the tangent plane), E\n"
    "(unshadowed irradiance, unit radiance) and mask (1 where H >= 0.05 inside the\n"
    "light's frustum), plus a PNG. Prints the light samples resolved per second\n"
    "and the noise floor (the rms error of V itself, from the two halves of the\n"
    "same samples).\n"
    "\n"
    "options:\n"
    "  --scene S             a glTF file, or the name of a shipped scene (required)\n"
    "  --width W, --height H image size in pixels, " SIZE_RANGE " (default " RUN_STR(RUN_DEFAULT_SIZE)
    " x " RUN_STR(RUN_DEFAULT_SIZE) ")\n"
    "  --gt-samples N        light samples per pixel, a square n*n, 1.." RUN_STR(GT_MAX_SAMPLES)
    " (default " RUN_STR(GT_DEFAULT_SAMPLES) ")\n"
    "  --out DIR             output folder (default " GT_DEFAULT_OUT ")\n"
    "  --cache DIR, --no-cache   as for run (default " RUN_DEFAULT_CACHE ")\n"
    "  -q, --quiet, -v, --verbose\n";

static const char usage_bench[] =
    "usage: shadowbench bench [options]\n"
    "\n"
    "Times every selected technique on one scene, without ground truth or files:\n"
    "the median time (--timing: wall clock around glFinish on llvmpipe, where GL\n"
    "timer queries do not measure the work; GL_TIME_ELAPSED queries on a GPU) of\n"
    "K frames after warm-up, per stage: shadow map (the depth\n"
    "pass), filter prep (moments, blur, mipmaps, summed-area table) and receiver\n"
    "pass, and the quartiles of the frame totals. Then the texture-fetch limit on\n"
    "the same scene: a receiver pass that does only the depth fetches of each\n"
    "PCF-family technique, and the ratio of the technique's receiver pass to it.\n"
    "The techniques and probes are timed interleaved, one frame of each in turn.\n"
    "\n"
    "options:\n"
    "  --scene S             a glTF file or shipped scene (default: the first shipped)\n"
    "  --technique T[,T...]  techniques to time (default: all)\n"
    "  --set T.P=V           set a technique parameter (repeatable)\n"
    "  --width W, --height H receiver size in pixels, " SIZE_RANGE " (default "
    RUN_STR(BENCH_DEFAULT_SIZE) " x " RUN_STR(BENCH_DEFAULT_SIZE) ")\n"
    "  --shadow-map-size N   shadow map resolution, " MAP_RANGE " (default "
    RUN_STR(SHADOWMAP_DEFAULT_SIZE) ")\n"
    "  --frames K            timed frames, the median and quartiles are reported, 1.." RUN_STR(STAGE_TIMER_MAX_FRAMES)
    " (default " RUN_STR(BENCH_DEFAULT_FRAMES) ")\n"
    "  --warmup K            untimed frames first, 0.." RUN_STR(RUN_MAX_WARMUP) " (default "
    RUN_STR(BENCH_DEFAULT_WARMUP) ")\n"
    "  --shaders DIR         GLSL folder, as for run\n"
    "  --gl osmesa|egl       the GL context, as for run\n"
    "  --timing auto|wall|query  how stages are timed, as for run\n"
    "  -q, --quiet, -v, --verbose\n";

static const char usage_check[] =
    "usage: shadowbench check [options]\n"
    "\n"
    "The regression check per technique. Renders every baseline cell again at the\n"
    "settings it records (results/baselines/<scene>/<cell>.json and its V_tech,\n"
    "<cell>.png: " RUN_STR(CHECK_SIZE) "x" RUN_STR(CHECK_SIZE) ", " RUN_STR(CHECK_GT_SAMPLES) " ground-truth samples, the default shadow map) and\n"
    "compares: a metric worse than its recorded tolerance, or a picture that moved\n"
    "(more than 0.15 % of its pixels by more than 0.002) with no metric better, is\n"
    "REGRESSED; a metric better than its tolerance with none worse is 'improved'.\n"
    "Cells: every technique at its defaults on every shipped scene, and a table of\n"
    "cells that set each parameter away from its default (harness/cli/check.c).\n"
    "For each of those, setting the parameter back must change the picture. One\n"
    "line per cell; what moved under it. Under --out: check.html with a\n"
    "V_now - V_baseline heatmap of each cell that moved.\n"
    "\n"
    "options:\n"
    "  --scene S             check only this scene's cells (repeatable)\n"
    "  --technique T[,T...]  check only these techniques' cells\n"
    "  --baselines DIR       the baselines (default " CHECK_DEFAULT_BASELINES ")\n"
    "  --update              record the selected cells anew (atomically), printing\n"
    "                        what moved; tolerances from the metrics' spread over\n"
    "                        " RUN_STR(CHECK_SEEDS) " ground-truth seeds. Commit them with the change that\n"
    "                        moved them, after looking at the page\n"
    "  --strict              an improvement fails too\n"
    "  --out DIR             where check.html goes (default " CHECK_DEFAULT_OUT ")\n"
    "  --cache DIR, --no-cache   ground-truth cache, as for run\n"
    "  --shaders DIR         GLSL folder, as for run\n"
    "  --gl osmesa|egl       the GL context, as for run\n"
    "  -q, --quiet, -v, --verbose\n"
    "\n"
    "exit status: 0 every cell passed; 1 a cell regressed, has no baseline or\n"
    "records parameters its name no longer means, an improvement with --strict, or\n"
    "a parameter that no cell sets or that changes nothing; 2 bad usage or an\n"
    "unreadable baseline (one line naming the file and the problem).\n";

static const char usage_tune[] =
    "usage: shadowbench tune [options]\n"
    "\n"
    "Explores each technique's parameters over the scenes, to answer: for a time\n"
    "budget, which technique and which setting is least wrong? The values explored\n"
    "are each parameter's tune values ('shadowbench list'); the search is " /* */
    "coordinate\n"
    "descent on the mean objective from the defaults: each parameter in turn at\n"
    "every value with the others held, the best taken, rounds until nothing moves\n"
    "(at most " RUN_STR(TUNE_MAX_ROUNDS) "). No randomness: the same code gives the same choices. Per\n"
    "technique, it searches every scene; every scene but one, for each scene (that\n"
    "scene's tuned setting, scored on it: leave-one-scene-out cross-validation).\n"
    "Each scene's oracle is the best of every setting tried on it (fitted to it,\n"
    "not a prediction). Every cell is timed; the frontier is the Pareto front of\n"
    "error against time over every setting tried, over all scenes and per scene.\n"
    "\n"
    "Writes DIR/<technique>.json (settings, folds, frontier, command, date) and\n"
    "DIR/tune.json (\"complete\" once every technique is done); with --write-tuned\n"
    "also " TUNED_DEFAULT_DIR "/<technique>.json, which 'run' uses for its T@tuned cells.\n"
    "\n"
    "options:\n"
    "  --technique T[,T...]  techniques to tune (default: all)\n"
    "  --scene S             scenes to tune on (repeatable, at least 2; default:\n"
    "                        every shipped scene)\n"
    "  --objective M         the error minimised, averaged over the scenes:\n"
    "                        penumbra_rmse (default), rmse or shaded_rmse\n"
    "  --write-tuned         also write the tuned settings for run (see --tuned)\n"
    "  --tuned DIR           where --write-tuned writes (default " TUNED_DEFAULT_DIR ")\n"
    "  --width W, --height H image size in pixels, " SIZE_RANGE " (default " RUN_STR(TUNE_DEFAULT_SIZE)
    " x " RUN_STR(TUNE_DEFAULT_SIZE) ")\n"
    "  --gt-samples N        ground-truth light samples per pixel (default " RUN_STR(GT_DEFAULT_SAMPLES) ")\n"
    "  --shadow-map-size N   shadow map resolution, " MAP_RANGE " (default "
    RUN_STR(SHADOWMAP_DEFAULT_SIZE) "): the\n"
    "                        texel-sized parameters are tuned for this size\n"
    "  --frames K            timed frames per cell (default " RUN_STR(TUNE_DEFAULT_FRAMES) "); --warmup K (default "
    RUN_STR(TUNE_DEFAULT_WARMUP) ": the\n"
    "                        untimed frame that scores a cell warms it)\n"
    "  --out DIR             output folder (default " TUNE_DEFAULT_OUT ")\n"
    "  --cache DIR, --no-cache   ground-truth cache, as for run\n"
    "  --shaders DIR         GLSL folder, as for run\n"
    "  --gl osmesa|egl       the GL context, as for run\n"
    "  --timing auto|wall|query  how stages are timed, as for run\n"
    "  -q, --quiet, -v, --verbose\n"
    "\n"
    "The default (every technique on every shipped scene) takes about 10 minutes\n"
    "on a 2-core CPU with llvmpipe; progress and an ETA go to stderr.\n";

static const char usage_stability[] =
    "usage: shadowbench stability [options]\n"
    "\n"
    "Where methods fail, on purpose. Two modes, both run when neither is named:\n"
    "\n"
    "--motion: the scene moves for --frames frames; every frame is ray traced\n"
    "anew (cached per pose) and rendered by every technique. Per technique:\n"
    "  flicker       mean over pixels and frame pairs of |dV_tech - dV_gt|, i.e.\n"
    "                of |e_t - e_(t-1)| with e = V_tech - V_gt: the change of the\n"
    "                error from frame to frame. Pixels scored in both frames of a\n"
    "                pair count; one that enters or leaves the mask is left out\n"
    "                (counted: mask_changes)\n"
    "  flicker_p99   its 99th percentile\n"
    "  flicker_floor the ground truth's own frame-to-frame noise, from its two\n"
    "                halves of samples: a flicker not above it is marked not\n"
    "                meaningful\n"
    "  rmse_mean, rmse_max  the frames' rmse\n"
    "Techniques with per-pixel noise (pcf's disk, pcss) are measured with the\n"
    "noise still (T) and animated by the frame index (T~anim, Jimenez 2014), and\n"
    "each also accumulated by the moving average TAA keeps (T+ema, T~anim+ema),\n"
    "reprojected where the camera moves.\n"
    "  --motion M[=STEP]     (repeatable) one of:\n"
    "      static            nothing moves: every deterministic technique's flicker\n"
    "                        is exactly the floor (0)\n"
    "      light_shift=S     the light along its own x axis, S shadow-map texels per\n"
    "                        frame at the depth of the scene's centre (default 0.125)\n"
    "      light_rotate=D    the light turned about its own y axis, D degrees per\n"
    "                        frame (default 0.01)\n"
    "      camera_shift=P    the camera along its own x axis, P pixels per frame at\n"
    "                        the depth of the scene's centre (default 0.25)\n"
    "      caster_shift:NODE=S  the scene's glTF node named NODE (1 to 64 bytes), with\n"
    "                        its children, along the light's x axis, S shadow-map\n"
    "                        texels per frame at the depth of the node's centre\n"
    "                        (default 0.125; in front of the light); the map's\n"
    "                        window stays put, as a fixed-fit map's would\n"
    "      scene             each scene's own motions, listed in its file as\n"
    "                        extras.shadowbench.motions (strings as above, e.g.\n"
    "                        \"caster_shift:sphere=0.25\")\n"
    "  --frames K            frames of each motion, " RUN_STR(STABILITY_MIN_FRAMES) ".." RUN_STR(STABILITY_MAX_FRAMES)
    " (default " RUN_STR(STABILITY_DEFAULT_FRAMES) ")\n"
    "  --accumulate A        the new frame's weight in the moving average, (0, 1]\n"
    "                        (default " RUN_STR(STABILITY_DEFAULT_ACCUMULATE) ")\n"
    "\n"
    "--vary: one thing takes each listed value (the reference value is added when\n"
    "not listed); every technique's rmse, penumbra_rmse, leak_fraction and\n"
    "dark_fraction against it, and where it breaks:\n"
    "  --vary NAME=V1,V2,... (repeatable) NAME is one of:\n"
    "      shadow_map_size   the map's side, " RUN_STR(SHADOWMAP_MIN_SIZE) ".." RUN_STR(SHADOWMAP_MAX_SIZE)
    " (reference: --shadow-map-size)\n"
    "      light_scale       the light's size times this, 1/64..64 (reference 1); the\n"
    "                        ground truth follows\n"
    "      depth_range       the map's near plane pulled in to near / this, 1..1e6\n"
    "                        (reference 1): the scene fills less of the map's depth\n"
    "                        range, as with an engine's fixed small near plane\n"
    "      T.P               a parameter of technique T (its values as for --set),\n"
    "                        e.g. pcf.radius_texels=1,2,4,8; reference: its setting\n"
    "  A value breaks a technique where its V has any NaN/Inf, or, against the\n"
    "  reference value, its rmse is at least " RUN_STR(STABILITY_BREAK_RMSE_FACTOR) " times as large and "
    RUN_STR(STABILITY_BREAK_RMSE_RISE) " larger,\n"
    "  or its leak_fraction or dark_fraction " RUN_STR(STABILITY_BREAK_FRACTION_RISE) " larger. Its break points: the first\n"
    "  broken value below and above the reference.\n"
    "\n"
    "With neither: --motion static, light_shift, light_rotate, camera_shift (at\n"
    "their default steps) and scene, and --vary shadow_map_size=256,512,1024,2048,4096,\n"
    "light_scale=0.25,0.5,1,2,4 and depth_range=1,10,100,1000,10000, on the\n"
    "scenes floating_box_sphere and overlapping_occluders.\n"
    "\n"
    "Writes, under --out: stability.html (open it in a browser: tables, charts,\n"
    "each motion's frames with a slider), stability.csv (one row per technique x\n"
    "motion variant or varied value), stability.json (the same, the break points,\n"
    "the rule), charts/*.svg, and <scene>/<motion>/<row>/visibility_frames.png and\n"
    "error_frames.png (the frames side by side). A run first removes what the last\n"
    "run into --out listed in its stability.json (its frames and charts), and\n"
    "nothing else.\n"
    "\n"
    "other options:\n"
    "  --scene S             (repeatable; default as above)\n"
    "  --technique T[,T...]  (default: all)\n"
    "  --set T.P=V           as for run (repeatable)\n"
    "  --width W, --height H image size, " SIZE_RANGE " (default " RUN_STR(STABILITY_DEFAULT_SIZE) " x "
    RUN_STR(STABILITY_DEFAULT_SIZE) ")\n"
    "  --gt-samples N        light samples per pixel of the ground truth (default "
    RUN_STR(GT_DEFAULT_SAMPLES) ")\n"
    "  --shadow-map-size N   texels, " MAP_RANGE " (default " RUN_STR(SHADOWMAP_DEFAULT_SIZE) ")\n"
    "  --out DIR             (default " STABILITY_DEFAULT_OUT ")\n"
    "  --cache DIR, --no-cache   ground-truth cache, as for run\n"
    "  --shaders DIR         GLSL folder, as for run\n"
    "  --gl osmesa|egl       the GL context, as for run\n"
    "  -q, --quiet, -v, --verbose\n"
    "\n"
    "exit status: 0 done; 1 a technique produced NaN/Inf or a motion had nothing\n"
    "to score, or a runtime error; 2 bad usage or input.\n";

static const char usage_view[] =
    "usage: shadowbench view --scene S [options]\n"
    "\n"
    "Opens one scene in a window (GLFW, OpenGL 4.5 core) shaded by a technique:\n"
    "unshadowed shading (the area light's irradiance E, closed form) times V_tech.\n"
    "Each frame renders the technique's products afresh, then its receiver pass,\n"
    "each stage timed as bench times it, one frame at a time (the overlay shows a\n"
    "moving average; the ground truth's tracing shares the CPU with llvmpipe).\n"
    "The ground truth of each pose is ray traced on a second thread (all cores),\n"
    "at 1, 4, 16, ... light samples per pixel up to --gt-samples,\n"
    "each level shown when done; with it the overlay gives rmse and penumbra_rmse.\n"
    "Without a display (a server, CI) run it under xvfb-run.\n"
    "\n"
    "keys:\n"
    "  Tab, Shift+Tab        next, previous technique (those of --technique, else all)\n"
    "  1 2 3 4 5             view: shaded (E x V_tech), V_tech, V_gt, signed error\n"
    "                        (V_tech - V_gt), E alone (" RUN_STR(VIEW_WHITE) " x its mean is white)\n"
    "  Space                 split screen: left technique | right technique\n"
    "  B, Shift+B            next, previous right-hand technique\n"
    "  [ ]                   select the left technique's previous, next parameter\n"
    "  - =                   its previous, next value (its tune list or choices;\n"
    "                        else int +-1, float x/1.25, within its range)\n"
    "  arrows                move the light along its own x and y\n"
    "  A D, W S, Q E         orbit the camera (yaw, pitch), move it closer, away\n"
    "  mouse                 left drag: orbit; right drag: move the light; wheel: closer\n"
    "  R                     reset the light and the camera\n"
    "  H                     overlay on, off\n"
    "  Esc                   quit\n"
    "\n"
    "options:\n"
    "  --scene S             a glTF file, or the name of a shipped scene (required)\n"
    "  --technique T[,T...]  the techniques Tab steps through, the first shown\n"
    "                        (default: all); the second is the split's right side\n"
    "  --set T.P=V           as for run (repeatable); the view starts from defaults\n"
    "  --width W, --height H the picture in pixels, " SIZE_RANGE " (default " RUN_STR(RUN_DEFAULT_SIZE) " x "
    RUN_STR(RUN_DEFAULT_SIZE) ")\n"
    "  --gt-samples N        the ground truth's last level, a square n*n (default "
    RUN_STR(VIEW_DEFAULT_GT_SAMPLES) ")\n"
    "  --shadow-map-size N   texels, " MAP_RANGE " (default " RUN_STR(SHADOWMAP_DEFAULT_SIZE) ")\n"
    "  --frames N            draw N frames, then exit (default: until the window closes)\n"
    "  --screenshot FILE     write the window's last frame to FILE (PNG) and exit\n"
    "                        (after 1 frame unless --frames); that frame first waits\n"
    "                        for the pose's last ground-truth level\n"
    "  --script FILE         key events to replay: lines 'FRAME KEY' (the key pressed\n"
    "                        before frame FRAME, counted from 0; KEY: A-Z, 0-9, TAB,\n"
    "                        SPACE, LEFT, RIGHT, UP, DOWN, MINUS, EQUAL, LEFT_BRACKET,\n"
    "                        RIGHT_BRACKET, ESCAPE, each optionally shift+KEY); # comments\n"
    "  --shaders DIR         GLSL folder, as for run\n"
    "  -q, --quiet, -v, --verbose  (key events and refusals are logged at the default level)\n"
    "\n"
    "exit status: 0 done; 1 a runtime error (a shader that does not compile, a\n"
    "screenshot not written); 2 bad usage or input, or no window system.\n";

static const char usage_list[] =
    "usage: shadowbench list\n"
    "\n"
    "Lists every technique with its parameters (type, default, range, meaning) and\n"
    "every shipped scene with its description and the phenomenon it isolates.\n";

enum {
    OPT_SCENE = 256, OPT_TECHNIQUE, OPT_SET, OPT_WIDTH, OPT_HEIGHT, OPT_GT_SAMPLES,
    OPT_SM_SIZE, OPT_FRAMES, OPT_WARMUP, OPT_OUT, OPT_CACHE, OPT_NO_CACHE, OPT_SHADERS, OPT_SWEEP,
    OPT_BASELINES, OPT_UPDATE, OPT_STRICT, OPT_TUNED, OPT_SETTINGS, OPT_OBJECTIVE, OPT_WRITE_TUNED,
    OPT_MOTION, OPT_VARY, OPT_ACCUMULATE, OPT_GL, OPT_TIMING, OPT_SCREENSHOT, OPT_SCRIPT,
};

static const struct option long_options[] = {
    {"scene", required_argument, NULL, OPT_SCENE},
    {"technique", required_argument, NULL, OPT_TECHNIQUE},
    {"set", required_argument, NULL, OPT_SET},
    {"sweep", required_argument, NULL, OPT_SWEEP},
    {"width", required_argument, NULL, OPT_WIDTH},
    {"height", required_argument, NULL, OPT_HEIGHT},
    {"gt-samples", required_argument, NULL, OPT_GT_SAMPLES},
    {"shadow-map-size", required_argument, NULL, OPT_SM_SIZE},
    {"frames", required_argument, NULL, OPT_FRAMES},
    {"warmup", required_argument, NULL, OPT_WARMUP},
    {"out", required_argument, NULL, OPT_OUT},
    {"cache", required_argument, NULL, OPT_CACHE},
    {"no-cache", no_argument, NULL, OPT_NO_CACHE},
    {"shaders", required_argument, NULL, OPT_SHADERS},
    {"gl", required_argument, NULL, OPT_GL},
    {"timing", required_argument, NULL, OPT_TIMING},
    {"baselines", required_argument, NULL, OPT_BASELINES},
    {"update", no_argument, NULL, OPT_UPDATE},
    {"strict", no_argument, NULL, OPT_STRICT},
    {"tuned", required_argument, NULL, OPT_TUNED},
    {"settings", required_argument, NULL, OPT_SETTINGS},
    {"objective", required_argument, NULL, OPT_OBJECTIVE},
    {"write-tuned", no_argument, NULL, OPT_WRITE_TUNED},
    {"motion", required_argument, NULL, OPT_MOTION},
    {"vary", required_argument, NULL, OPT_VARY},
    {"accumulate", required_argument, NULL, OPT_ACCUMULATE},
    {"screenshot", required_argument, NULL, OPT_SCREENSHOT},
    {"script", required_argument, NULL, OPT_SCRIPT},
    {"quiet", no_argument, NULL, 'q'},
    {"verbose", no_argument, NULL, 'v'},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

static int parse_int(const char *opt, const char *text, int lo, int hi, int *out)
{
    char *end;
    errno = 0;
    long v = strtol(text, &end, 10);
    if (!*text || *end || errno || !(text[0] == '-' || (text[0] >= '0' && text[0] <= '9'))) {
        log_error("--%s: '%s' is not a whole number", opt, text);
        return -1;
    }
    if (v < lo || v > hi) {
        log_error("--%s: %ld is out of range [%d, %d]", opt, v, lo, hi);
        return -1;
    }
    *out = (int)v;
    return 0;
}

/* A folder option: not empty, and not something other than a folder (it
 * may not exist yet). */
static int folder_option(const char *opt, const char *text, const char **out)
{
    if (!*text) {
        log_error("--%s: an empty folder name", opt);
        return -1;
    }
    if (util_file_exists(text) && !util_is_dir(text)) {
        log_error("--%s %s: not a folder", opt, text);
        return -1;
    }
    *out = text;
    return 0;
}

static int add_techniques(struct run_options *o, const char *list)
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
        if (!t) {
            struct strbuf known = {0};
            technique_names(&known, ", ");
            log_error("--technique: unknown technique '%s' (known: %s)", name, known.data);
            strbuf_free(&known);
            rc = -1;
        } else if (o->technique_count < RUN_MAX_TECHNIQUES) {
            bool dup = false;
            for (int i = 0; i < o->technique_count; i++)
                dup |= o->techniques[i] == t;
            if (!dup)
                o->techniques[o->technique_count++] = t;
        }
    }
    free(copy);
    return rc;
}

static int apply_set(struct run_options *o, const char *arg)
{
    const char *dot = strchr(arg, '.'), *eq = strchr(arg, '=');
    if (!dot || !eq || eq < dot) {
        log_error("--set: '%s' is not technique.parameter=value", arg);
        return -1;
    }
    char tech[64], name[64];
    snprintf(tech, sizeof tech, "%.*s", (int)(dot - arg), arg);
    snprintf(name, sizeof name, "%.*s", (int)(eq - dot - 1), dot + 1);
    int index = 0;
    while (technique_list[index] && strcmp(technique_list[index]->name, tech) != 0)
        index++;
    if (!technique_list[index]) {
        log_error("--set: unknown technique '%s'", tech);
        return -1;
    }
    if (!o->settings[index])
        o->settings[index] = params_defaults(technique_list[index]);
    return params_set(technique_list[index], o->settings[index], name, eq + 1);
}

/* Does the command take this option? */
static bool takes(enum run_command cmd, int c)
{
    bool gl = c == OPT_TECHNIQUE || c == OPT_SET || c == OPT_SM_SIZE || c == OPT_FRAMES ||
              c == OPT_WARMUP || c == OPT_SHADERS || c == OPT_GL;
    bool gt = c == OPT_GT_SAMPLES || c == OPT_OUT || c == OPT_CACHE || c == OPT_NO_CACHE;
    bool check = c == OPT_BASELINES || c == OPT_UPDATE || c == OPT_STRICT;
    if (c == OPT_SWEEP || c == OPT_SETTINGS)
        return cmd == RUN_CMD_RUN;
    if (c == OPT_MOTION || c == OPT_VARY || c == OPT_ACCUMULATE)
        return cmd == RUN_CMD_STABILITY;
    if (c == OPT_SCREENSHOT || c == OPT_SCRIPT)
        return cmd == RUN_CMD_VIEW;
    if (c == OPT_OBJECTIVE || c == OPT_WRITE_TUNED)
        return cmd == RUN_CMD_TUNE;
    if (c == OPT_TIMING)  /* the commands that time */
        return cmd == RUN_CMD_RUN || cmd == RUN_CMD_BENCH || cmd == RUN_CMD_TUNE;
    if (c == OPT_TUNED)
        return cmd == RUN_CMD_RUN || cmd == RUN_CMD_CHECK || cmd == RUN_CMD_TUNE;
    switch (cmd) {
    case RUN_CMD_RUN: return !check;
    case RUN_CMD_TUNE: return !check && c != OPT_SET;  /* the search starts from the defaults */
    case RUN_CMD_GT: return !gl && !check;
    case RUN_CMD_BENCH: return !gt && !check;
    case RUN_CMD_STABILITY: return !check && c != OPT_WARMUP && c != OPT_TUNED;
    case RUN_CMD_VIEW:  /* a window: no --gl, --timing (auto) or output folder */
        return c == OPT_SCENE || c == OPT_TECHNIQUE || c == OPT_SET || c == OPT_WIDTH || c == OPT_HEIGHT ||
               c == OPT_GT_SAMPLES || c == OPT_SM_SIZE || c == OPT_FRAMES || c == OPT_SHADERS;
    case RUN_CMD_CHECK:  /* the settings are the baselines' */
        return check || c == OPT_SCENE || c == OPT_TECHNIQUE || c == OPT_OUT || c == OPT_CACHE ||
               c == OPT_NO_CACHE || c == OPT_SHADERS || c == OPT_GL;
    }
    return false;
}

static int parse_gt_samples(const char *text, int *out)
{
    if (parse_int("gt-samples", text, 1, GT_MAX_SAMPLES, out))
        return -1;
    int n = (int)lround(sqrt((double)*out));
    if (n * n != *out) {
        int lo = (int)floor(sqrt((double)*out));
        log_error("--gt-samples: %d is not a square number (n*n stratified light samples, e.g. "
                  "%d or %d)", *out, lo * lo, (lo + 1) * (lo + 1));
        return -1;
    }
    return 0;
}

static const char *const command_names[] = {"run", "gt", "bench", "check", "tune", "stability", "view"};

static int parse_choice(const char *opt, const char *text, const char *const *names, int *out)
{
    for (int i = 0; names[i]; i++)
        if (strcmp(names[i], text) == 0) {
            *out = i;
            return 0;
        }
    struct strbuf known = {0};
    strbuf_join(&known, names, ", ");
    log_error("--%s: '%s' is not one of: %s", opt, text, known.data);
    strbuf_free(&known);
    return -1;
}

/* Every technique selected when none is, every setting at its default
 * unless --set, and the rules across parameters checked. */
static int finish_techniques(struct run_options *o)
{
    if (!o->technique_count)
        for (const struct technique *const *t = technique_list; *t; t++)
            o->techniques[o->technique_count++] = *t;
    for (int i = 0; technique_list[i]; i++)
        if (!o->settings[i])
            o->settings[i] = params_defaults(technique_list[i]);
    return 0;
}

/* The rules across parameters, for the commands without sweeps (run checks
 * each configuration once its swept values are in: sweep_configs). */
static int check_settings(const struct run_options *o)
{
    for (int i = 0; i < o->technique_count; i++)
        if (params_check(o->techniques[i], run_settings(o, o->techniques[i])) != 0)
            return -1;
    return 0;
}

/* Parses the options of run, gt and bench into o. Returns 0, 1 after
 * --help, or -1. */
static int parse_options(int argc, char **argv, const char *usage, enum run_command cmd,
                         struct run_options *o)
{
    run_options_defaults(o, cmd);
    bool tuned_given = false;
    int c, index = 0;
    optind = 1;
    opterr = 0;
    while ((c = getopt_long(argc, argv, ":qvh", long_options, &index)) != -1) {
        if (c == '?') {
            log_error("%s: unknown option (see --help)", argv[optind - 1]);
            return -1;
        }
        if (c == ':') {
            log_error("%s: needs a value (see --help)", argv[optind - 1]);
            return -1;
        }
        if (c >= OPT_SCENE && !takes(cmd, c)) {
            log_error("--%s: unknown option for %s (see --help)", long_options[index].name,
                      command_names[cmd]);
            return -1;
        }
        int rc = 0;
        switch (c) {
        case OPT_SCENE:
            if (o->scene_count == RUN_MAX_SCENES ||
                ((cmd == RUN_CMD_GT || cmd == RUN_CMD_BENCH || cmd == RUN_CMD_VIEW) && o->scene_count == 1)) {
                log_error("--scene: %s", o->scene_count == RUN_MAX_SCENES ? "too many scenes"
                                                                          : "gt, bench and view take one scene");
                return -1;
            }
            o->scenes[o->scene_count++] = optarg;
            break;
        case OPT_TECHNIQUE: rc = add_techniques(o, optarg); break;
        case OPT_SET:
            rc = apply_set(o, optarg);
            o->set_count++;
            break;
        case OPT_SWEEP:
            if (o->sweep_count == RUN_MAX_SWEEPS) {
                log_error("--sweep: at most %d sweeps", RUN_MAX_SWEEPS);
                return -1;
            }
            o->sweeps[o->sweep_count++] = optarg;
            break;
        case OPT_WIDTH: rc = parse_int("width", optarg, RUN_MIN_SIZE, RUN_MAX_SIZE, &o->width); break;
        case OPT_HEIGHT: rc = parse_int("height", optarg, RUN_MIN_SIZE, RUN_MAX_SIZE, &o->height); break;
        case OPT_GT_SAMPLES: rc = parse_gt_samples(optarg, &o->gt_samples); break;
        case OPT_SM_SIZE:
            rc = parse_int("shadow-map-size", optarg, SHADOWMAP_MIN_SIZE, SHADOWMAP_MAX_SIZE,
                           &o->shadow_map_size);
            break;
        case OPT_FRAMES:
            rc = cmd == RUN_CMD_STABILITY ? parse_int("frames", optarg, STABILITY_MIN_FRAMES, STABILITY_MAX_FRAMES, &o->frames)
                 : cmd == RUN_CMD_VIEW    ? parse_int("frames", optarg, 1, VIEW_MAX_FRAMES, &o->frames)
                                          : parse_int("frames", optarg, 1, STAGE_TIMER_MAX_FRAMES, &o->frames);
            break;
        case OPT_MOTION:
        case OPT_VARY: {
            const bool motion = c == OPT_MOTION;
            int *n = motion ? &o->motion_count : &o->vary_count;
            if (*n == (motion ? RUN_MAX_MOTIONS : RUN_MAX_VARIES)) {
                log_error("--%s: at most %d", motion ? "motion" : "vary", motion ? RUN_MAX_MOTIONS : RUN_MAX_VARIES);
                return -1;
            }
            (motion ? o->motions : o->varies)[(*n)++] = optarg;
            break;
        }
        case OPT_ACCUMULATE: {
            char *end;
            errno = 0;
            o->accumulate = strtod(optarg, &end);
            if (!*optarg || *end || errno || !(o->accumulate > 0 && o->accumulate <= 1)) {
                log_error("--accumulate: '%s' is not a number in (0, 1]", optarg);
                return -1;
            }
            break;
        }
        case OPT_WARMUP: rc = parse_int("warmup", optarg, 0, RUN_MAX_WARMUP, &o->warmup); break;
        case OPT_OUT: rc = folder_option("out", optarg, &o->out_dir); break;
        case OPT_CACHE: rc = folder_option("cache", optarg, &o->cache_dir); break;
        case OPT_NO_CACHE: o->cache_dir = NULL; break;
        case OPT_SHADERS: o->shader_dir = optarg; break;
        case OPT_GL:
            if ((rc = gl_backend_parse(optarg, &o->gl)) != 0)
                log_error("--gl %s: not a GL backend (osmesa, egl)", optarg);
            break;
        case OPT_TIMING:
            if ((rc = stage_timing_parse(optarg, &o->timing)) != 0)
                log_error("--timing %s: not a timing method (auto, wall, query)", optarg);
            break;
        case OPT_BASELINES: rc = folder_option("baselines", optarg, &o->baselines_dir); break;
        case OPT_UPDATE: o->update = true; break;
        case OPT_STRICT: o->strict = true; break;
        case OPT_TUNED:
            rc = folder_option("tuned", optarg, &o->tuned_dir);
            tuned_given = true;
            break;
        case OPT_SETTINGS: {
            static const char *const modes[] = {"both", "default", "tuned", NULL};
            int mode;
            rc = parse_choice("settings", optarg, modes, &mode);
            o->settings_mode = (enum run_settings_mode)mode;
            break;
        }
        case OPT_OBJECTIVE: {
            static const char *const names[] = {"penumbra_rmse", "rmse", "shaded_rmse", NULL};
            static const int metrics[] = {METRIC_penumbra_rmse, METRIC_rmse, METRIC_shaded_rmse};
            int k;
            rc = parse_choice("objective", optarg, names, &k);
            o->objective = rc ? o->objective : metrics[k];
            break;
        }
        case OPT_WRITE_TUNED: o->write_tuned = true; break;
        case OPT_SCREENSHOT: o->screenshot = optarg; break;
        case OPT_SCRIPT: o->script = optarg; break;
        case 'q': log_set_level(LOG_ERROR); break;
        case 'v': log_set_level(LOG_DEBUG); break;
        case 'h': fputs(usage, stdout); return 1;
        }
        if (rc)
            return -1;
    }
    if (optind < argc) {
        log_error("%s: unexpected argument (see --help)", argv[optind]);
        return -1;
    }
    if (o->update && o->strict) {
        log_error("--strict: has no effect with --update (which records every cell)");
        return -1;
    }
    if ((cmd == RUN_CMD_GT || cmd == RUN_CMD_VIEW) && o->scene_count == 0) {
        log_error("%s: --scene is required (see --help)", command_names[cmd]);
        return -1;
    }
    if (cmd == RUN_CMD_VIEW && o->screenshot && o->frames == 0)
        o->frames = 1;
    if (tuned_given && cmd == RUN_CMD_TUNE && !o->write_tuned) {
        log_error("--tuned: tune writes there only with --write-tuned");
        return -1;
    }
    if (tuned_given && cmd != RUN_CMD_TUNE && !util_is_dir(o->tuned_dir)) {  /* a typo would drop every tuned cell */
        log_error("--tuned %s: no such folder", o->tuned_dir);
        return -1;
    }
    for (int i = 0; technique_list[i] && o->technique_count; i++) {
        bool selected = false;
        for (int k = 0; k < o->technique_count; k++)
            selected |= o->techniques[k] == technique_list[i];
        if (o->settings[i] && !selected) {  /* set, so meant: as a sweep of it would be */
            log_error("--set: %s is not among the techniques selected with --technique", technique_list[i]->name);
            return -1;
        }
    }
    if (finish_techniques(o) != 0)
        return -1;
    return cmd == RUN_CMD_RUN ? sweep_configs(o) : check_settings(o);
}

static int cmd_list(int argc, char **argv)
{
    if (argc > 1) {
        if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
            fputs(usage_list, stdout);
            return EXIT_OK;
        }
        log_error("%s: unknown option (see --help)", argv[1]);
        return EXIT_USAGE;
    }
    printf("techniques (set a parameter with --set <technique>.<parameter>=<value>):\n\n");
    for (const struct technique *const *t = technique_list; *t; t++) {
        printf("  %-10s %s\n", (*t)->name, (*t)->summary);
        params_print(*t, stdout);
        printf("\n");
    }
    char **paths;
    int n = catalog_shipped(&paths);
    if (n < 0)
        return EXIT_CHECK_FAILED;
    printf("scenes (use with --scene <name>):\n\n");
    int status = EXIT_OK;
    for (int i = 0; i < n; i++) {
        struct scene s;
        if (scene_load(paths[i], &s) != 0) {
            status = EXIT_CHECK_FAILED;
            continue;
        }
        printf("  %s\n    %s\n    shows: %s\n    %zu triangles, %s light\n\n", s.name,
               s.description, *s.shows ? s.shows : "-", s.triangle_count,
               light_shape_names[s.light.shape]);
        scene_free(&s);
    }
    catalog_free(paths, n);
    return status;
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fputs(usage_main, stderr);
        return EXIT_USAGE;
    }
    util_exit_cleanly_on_signals();
    const char *cmd = argv[1];
    if (strcmp(cmd, "--help") == 0 || strcmp(cmd, "-h") == 0 || strcmp(cmd, "help") == 0) {
        fputs(usage_main, stdout);
        return EXIT_OK;
    }
    if (strcmp(cmd, "list") == 0)
        return cmd_list(argc - 1, argv + 1);
    static const char *const usages[] = {usage_run, usage_gt, usage_bench, usage_check, usage_tune,
                                         usage_stability, usage_view};
    static int (*const mains[])(const struct run_options *) = {run_main, run_gt, bench_main, check_main,
                                                               tune_main, stability_main, view_main};
    const int commands = (int)(sizeof mains / sizeof *mains);
    int k = 0;
    while (k < commands && strcmp(cmd, command_names[k]) != 0)
        k++;
    if (k == commands) {
        log_error("unknown command '%s' (commands: run, gt, bench, check, tune, stability, view, list; see --help)", cmd);
        return EXIT_USAGE;
    }
    struct run_options o = {.argc = argc, .argv = argv};
    int rc = parse_options(argc - 1, argv + 1, usages[k], (enum run_command)k, &o);
    int status = rc > 0 ? EXIT_OK : rc < 0 ? EXIT_USAGE : mains[k](&o);
    for (int i = 0; i < RUN_MAX_TECHNIQUES; i++)
        free(o.settings[i]);
    sweep_free(&o);
    gt_shutdown();
    return status;
}
