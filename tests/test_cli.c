/* Protects the command line's contract (docs/design.md §10): bad usage or input
 * gets one clear line and exit status 2, before any heavy work; --help
 * answers with status 0; list shows every technique's parameters. */
#include "check.h"
#include "gltf_writer.h"
#include "run_cmd.h"
#include "scene/catalog.h"
#include "techniques/params.h"
#include "techniques/technique.h"

#include <string.h>

static const char *sb;
static char dir[] = "/tmp/sb_test_cli_XXXXXX";

static void expect(int status, const char *args, const char *stderr_line)
{
    char *cmd = util_printf("%s %s", sb, args);
    struct strbuf err = {0};
    int got = run_cmd(cmd, &err, NULL);
    CHECK(got == status, "'%s': exit %d, wanted %d", args, got, status);
    if (stderr_line) {
        char *want = util_printf("shadowbench: error: %s\n", stderr_line);
        CHECK(strcmp(err.data, want) == 0, "'%s'\n  got:    %s  wanted: %s", args, err.data, want);
        free(want);
    }
    strbuf_free(&err);
    free(cmd);
}

static void expect_stdout_has(const char *args, const char *needle)
{
    char *cmd = util_printf("%s %s", sb, args);
    struct strbuf out = {0};
    int got = run_cmd(cmd, NULL, &out);
    CHECK(got == 0 && out.data && strstr(out.data, needle), "'%s' must print '%s' and exit 0", args,
          needle);
    strbuf_free(&out);
    free(cmd);
}

/* Every parameter's default is a value --set accepts (in range, one of its
 * list: a tap count outside TAP_COUNTS would only fail later, as a shader
 * that does not compile), and the defaults pass the technique's rules. */
static void defaults_are_settable(void)
{
    for (int i = 0; technique_list[i]; i++) {
        const struct technique *t = technique_list[i];
        void *defaults = params_defaults(t), *scratch = params_defaults(t);
        for (const struct technique_param *p = t->params; p->name; p++) {
            char text[64];
            params_value_text(t, defaults, p->name, text, sizeof text);
            CHECK(params_set(t, scratch, p->name, text) == 0, "%s.%s: default %s refused", t->name,
                  p->name, text);
        }
        CHECK(params_check(t, defaults) == 0, "%s: defaults break its rules", t->name);
        free(defaults), free(scratch);
    }
}

int main(int argc, char **argv)
{
    if (!(sb = test_begin(argc, argv, dir)))
        return 1;
    defaults_are_settable();
    const char *small = "--scene floating_box_sphere --width 16 --height 16 --gt-samples 1 --no-cache";

    expect(2, "", NULL);
    expect(2, "frobnicate", "unknown command 'frobnicate' (commands: run, gt, bench, check, tune, stability, merge, view, list, help; see --help)");
    struct strbuf known = {0};  /* every registered technique, in registry order */
    for (int i = 0; technique_list[i]; i++)
        strbuf_printf(&known, "%s%s", i ? ", " : "", technique_list[i]->name);
    char *line = util_printf("--technique: unknown technique 'nope' (known: %s; and engines, presets, or an "
                             "engine's name for its modes and presets)", known.data);
    expect(2, "run --technique nope", line);
    /* engine cells: one map, no counted cost, and only the commands that take them */
    expect(2, "run --technique three_pcf --cascades 2",
           "--cascades 2: three_pcf is an engine cell, rendered with one map over the view; engine cells take no "
           "cascades (docs/engines.md)");
    expect(2, "tune --technique three_pcf --cost fetches",
           "--cost fetches: three_pcf is an engine cell, whose fetches are the engine's and are not counted "
           "(docs/engines.md)");
    expect(2, "stability --technique babylon_pcf --scene parallel_planes",
           "stability: babylon_pcf is an engine cell (babylon, rendered in a browser): run, tune and check take "
           "engine cells, stability does not (docs/engines.md)");
    free(line), strbuf_free(&known);
    /* Bad input gets exit 2 from every command, before any GL (issue 12). */
    expect(2, "run --scene parallel_planes --shaders /nonexistent",
           "/nonexistent: not a shadowbench shaders folder (no shadow_common.glsl in it)");
    expect(2, "bench --shaders /nonexistent",
           "/nonexistent: not a shadowbench shaders folder (no shadow_common.glsl in it)");
    char *check_out = util_printf("check --shaders /nonexistent --scene parallel_planes --technique hard --out %s/c",
                                  dir);
    expect(2, check_out, "/nonexistent: not a shadowbench shaders folder (no shadow_common.glsl in it)");
    free(check_out);
    char *a_file = util_printf("%s/a_file", dir), *cache_arg = util_printf("gt --scene parallel_planes --cache %s", a_file);
    util_write_file_atomic(a_file, "x", 1);
    char *cache_line = util_printf("--cache %s: not a folder", a_file);
    expect(2, cache_arg, cache_line);
    free(a_file), free(cache_arg), free(cache_line);
    struct mesh_builder m = {0};
    mesh_add_triangle(&m, v3(-1, 0, -1), v3(1, 0, -1), v3(0, 0, 1));
    char *away = util_printf("%s/away.gltf", dir);
    gltf_write(away, &m, &(struct gltf_scene_desc){
                             .description = "", .shows = "", .camera_pos = v3(0, 3, 3),
                             .camera_target = v3(0, 0, 0), .camera_yfov_rad = 0.8f, .camera_znear = 0.1f,
                             .light_pos = v3(0, 4, 0), .light_target = v3(0, 8, 0), .light_width = 1,
                             .light_height = 1});
    mesh_free(&m);
    char *bench_away = util_printf("bench --scene %s", away), *run_away = util_printf("run --scene %s", away);
    char *away_line = util_printf("%s: no geometry in front of the area light (it emits towards its local -Z)", away);
    expect(2, bench_away, away_line);
    expect(2, run_away, away_line);
    free(away), free(bench_away), free(run_away), free(away_line);

    expect(2, "run --out ''", "--out: an empty folder name");
    expect(2, "gt --scene parallel_planes --out ''", "--out: an empty folder name");
    expect(2, "gt --scene parallel_planes --cache ''", "--cache: an empty folder name");
    expect(2, "run --width ' 64'", "--width: ' 64' is not a whole number");
    expect(2, "run --set hard.slope_bias=0x1p1", "hard.slope_bias: '0x1p1' is not a number");
    char *dots = util_printf("%s/....gltf", dir), *dots_cmd = NULL, *dots_line = NULL;
    char *src = catalog_resolve("parallel_planes"), *scene_text;
    size_t scene_size;
    if (src && util_read_file(src, &scene_text, &scene_size) == 0) {
        util_write_file_atomic(dots, scene_text, scene_size);
        free(scene_text);
    }
    dots_cmd = util_printf("gt --scene %s --out %s/gt", dots, dir);
    dots_line = util_printf("%s: its name (the file's stem) cannot name its output folder: it is empty or "
                            "starts with '.'", dots);
    expect(2, dots_cmd, dots_line);
    free(dots), free(dots_cmd), free(dots_line), free(src);
    {   /* a line is never cut: the reason comes after a 5000-byte folder name */
        char *name = xcalloc(5001, 1);
        memset(name, 'x', 5000);
        char *args = util_printf("run --out %s/%s", dir, name), *line = util_printf("%s/%s: cannot create folder: "
                                                                                    "File name too long", dir, name);
        expect(2, args, line);
        free(args), free(line), free(name);
    }
    expect(2, "run --technique ''", "--technique: '' has an empty name");
    expect(2, "run --technique ,", "--technique: ',' has an empty name");
    expect(2, "run --technique hard,,pcf", "--technique: 'hard,,pcf' has an empty name");
    expect(2, "run --sweep hard.constant_bias=,", "--sweep: 'hard.constant_bias=,' has an empty value");
    expect(2, "run --set hard.nope=1", "hard.nope: unknown parameter (hard has: constant_bias, slope_bias)");
    expect(2, "run --set nope.x=1", "--set: unknown technique 'nope'");
    expect(2, "run --set hard.slope_bias=99", "hard.slope_bias: 99 is out of range [0.0, 16.0]");
    expect(2, "run --set hard.slope_bias=abc", "hard.slope_bias: 'abc' is not a number");
    /* too close to 0 for a float: "write 0" only where 0 is allowed */
    expect(2, "run --set msm.moment_bias=1e-500", "msm.moment_bias: 1e-500 is out of range [1e-07, 0.01]");
    expect(2, "run --set msm.depth_bias=1e-500", "msm.depth_bias: 1e-500 is too close to 0 for a float (write 0)");
    expect(2, "run --set hard", "--set: 'hard' is not technique.parameter=value");
    expect(2, "run --set pcss.blocker_samples=30",
           "pcss.blocker_samples: 30 is not one of: 16, 25, 32, 49, 64, 100, 128");
    expect(2, "run --set pcf.pattern=hexagon", "pcf.pattern: 'hexagon' is not one of: poisson, grid, vogel, uniform_disk");
    expect(2, "run --set pcf.pattern=grid",
           "pcf: pattern=grid needs a square sample count (16, 25, 49, 64, 100), not 32");
    expect(2, "bench --set pcf.pattern=grid --set pcf.samples=128",
           "pcf: pattern=grid needs a square sample count (16, 25, 49, 64, 100), not 128");
    expect(2, "run --set pcss.pattern=grid --set pcss.blocker_samples=25",
           "pcss: pattern=grid needs a square filter_samples (16, 25, 49, 64, 100), not 32");
    expect(2, "run --set pcss.pattern=spiral",
           "pcss.pattern: 'spiral' is not one of: poisson, grid, vogel, uniform_disk");
    expect(2, "run --set pcss.rotation=blue",
           "pcss.rotation: 'blue' is not one of: none, hash, ign, ign_2x2, blue_noise");
    expect(2, "run --set savsm.sat_format=fp16",
           "savsm.sat_format: 'fp16' is not one of: fp32, fp32_centered, int32");
    expect(2, "run --set vsm.bleed_reduction=1", "vsm.bleed_reduction: 1 is out of range [0.0, 0.99]");
    expect(2, "bench --gt-samples 16", "--gt-samples: unknown option for bench (see --help)");
    expect(2, "bench --out x", "--out: unknown option for bench (see --help)");
    expect(2, "bench --scene a --scene b", "--scene: gt, bench and view take one scene");
    expect(2, "run --width 8", "--width: 8 is out of range [16, 8192]");
    expect(2, "run --frames x", "--frames: 'x' is not a whole number");
    expect(2, "run --gt-samples 1000",
           "--gt-samples: 1000 is not a square number (n*n stratified light samples, e.g. 961 or 1024)");
    expect(2, "run --bogus", "--bogus: unknown option (see --help)");
    expect(2, "gt --technique hard", "--technique: unknown option for gt (see --help)");
    expect(2, "gt", "gt: --scene is required (see --help)");
    char **paths;  /* every shipped scene, sorted: its file stem */
    int n = catalog_shipped(&paths);
    struct strbuf stems = {0};
    for (int i = 0; i < n; i++) {
        const char *base = strrchr(paths[i], '/') + 1;
        strbuf_list_printf(&stems, ", ", "%.*s", (int)strcspn(base, "."), base);
    }
    CHECK(n >= 11, "the shipped scenes are found: %d", n);
    line = util_printf("unknown scene 'nope' (shipped: %s)", stems.data);
    expect(2, "run --scene nope", line);
    free(line), strbuf_free(&stems), catalog_free(paths, n);

    /* --sweep: each value as --set takes it, each parameter and value once,
     * only selected techniques, every combination consistent. */
    expect(2, "run --sweep pcss.blocker_samples=16,30",
           "pcss.blocker_samples: 30 is not one of: 16, 25, 32, 49, 64, 100, 128");
    expect(2, "run --sweep pcss.blocker_samples=16,16",
           "--sweep: pcss.blocker_samples: 16 is listed twice");
    expect(2, "run --sweep foo.x=1", "--sweep: unknown technique 'foo'");
    expect(2, "run --technique hard --sweep pcss.blocker_samples=16",
           "--sweep: pcss is not among the techniques selected with --technique");
    expect(2, "run --sweep pcss.blocker_samples=16 --sweep pcss.blocker_samples=32",
           "--sweep: pcss.blocker_samples is swept twice");
    expect(2, "run --sweep pcf.pattern=grid,poisson",
           "pcf: pattern=grid needs a square sample count (16, 25, 49, 64, 100), not 32");
    expect(2, "run --sweep pcss.blocker_samples=",
           "--sweep: 'pcss.blocker_samples=' is not technique.parameter=value,value,...");
    expect(2, "gt --scene parallel_planes --sweep pcss.blocker_samples=16",
           "--sweep: unknown option for gt (see --help)");
    expect(2, "run --sweep pcss.blocker_samples=16,,32",
           "--sweep: 'pcss.blocker_samples=16,,32' has an empty value");
    expect(2, "run --sweep pcss.blocker_samples=,",
           "--sweep: 'pcss.blocker_samples=,' has an empty value");
    expect(2, "run --sweep hard.constant_bias=0,-0", "--sweep: hard.constant_bias: -0 is listed twice");
    expect(2, "run --width", "--width: needs a value (see --help)");
    /* The rules across parameters apply to each swept cell, not to the
     * --set values a sweep replaces: grid with 16 or 25 taps is fine. */
    char *args = util_printf("run %s --frames 1 --warmup 0 -q --technique pcf --set pcf.pattern=grid "
                             "--sweep pcf.samples=16,25 --out %s/swept", small, dir);
    expect(0, args, NULL);
    free(args);

    /* An output folder that cannot be created: a path through a file. */
    char *file = util_printf("%s/a_file", dir);
    util_write_file_atomic(file, "x", 1);
    args = util_printf("run %s --out %s/sub", small, file);
    line = util_printf("%s/sub: cannot create folder: Not a directory", file);
    expect(2, args, line);
    free(args), free(line);
    args = util_printf("gt %s --out %s/sub", small, file);
    line = util_printf("%s/sub: cannot create folder: Not a directory", file);
    expect(2, args, line);
    free(args), free(line), free(file);

    /* Two scenes with one name would write into one output folder. */
    char *twin = util_printf("%s/floating_box_sphere.gltf", dir);
    char *shipped = util_printf("%s/scenes/floating_box_sphere.gltf", SB_SOURCE_DIR);
    char *text = NULL;
    size_t size;
    if (util_read_file(shipped, &text, &size) == 0)
        util_write_file_atomic(twin, text, size);
    args = util_printf("run --scene floating_box_sphere --scene %s --no-cache", twin);
    line = util_printf("%s: its name 'floating_box_sphere' is taken by %s (outputs are per scene name)",
                       twin, shipped);
    expect(2, args, line);
    free(text), free(twin), free(shipped), free(args), free(line);

    expect_stdout_has("--help", "commands:");
    expect_stdout_has("run --help", "--shadow-map-size N");
    expect_stdout_has("gt --help", "V_weighted");
    expect_stdout_has("bench --help", "texture-fetch limit");
    expect_stdout_has("list", "slope_bias       float default 1.0        range [0.0, 16.0]");
    expect_stdout_has("list", "floating_box_sphere");
    expect_stdout_has("list", "samples          int   default 32         one of 16|25|32|49|64|100|128");
    expect_stdout_has("list", "sat_format       enum  default int32      one of fp32|fp32_centered|int32");

    remove_tree(dir);
    return check_finish();
}
