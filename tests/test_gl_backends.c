/* Protects issue 16's first part: --gl egl renders what --gl osmesa does
 * (on this machine both are Mesa's llvmpipe, so the same shaders give the
 * same pixels: the metrics must be identical, no tolerance) for a
 * technique of every product of the shared layer; an EGL
 * without a display, an unknown backend or timing method is one line and
 * exit 2; the GL_TIME_ELAPSED path times every stage; run.json names the
 * renderer, vendor, platform and timing method. */
#include "check.h"
#include "read_json.h"
#include "run_cmd.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <string.h>

static const char *sb;
static char dir[] = "/tmp/sb_test_gl_XXXXXX";

/* Techniques that between them sample every product of the shared layer:
 * in registry order, each that needs a product none before it does. */
static int every_product(struct strbuf *list)
{
    unsigned covered = 0;
    int n = 0;
    for (const struct technique *const *t = technique_list; *t; t++)
        if ((*t)->needs & ~covered) {
            strbuf_list_printf(list, ",", "%s", (*t)->name);
            covered |= (*t)->needs, n++;
        }
    CHECK(covered == (1u << SM_PRODUCT_COUNT) - 1, "no technique samples products %#x",
          ((1u << SM_PRODUCT_COUNT) - 1) & ~covered);
    return n;
}

/* The run's matrix.json and run.json under dir/name. */
static int run_with(const char *name, const char *gl, cJSON **matrix, cJSON **run)
{
    struct strbuf techniques = {0};
    every_product(&techniques);
    char *cmd = util_printf("%s run --gl %s --scene floating_box_sphere --technique %s --settings default "
                            "--width 96 --height 96 --gt-samples 64 --frames 1 --no-cache -q --out %s/%s",
                            sb, gl, techniques.data, dir, name);
    strbuf_free(&techniques);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0, "run --gl %s: exit %d: %s", gl, status, err.data);
    strbuf_free(&err);
    free(cmd);
    char *m = util_printf("%s/%s/matrix.json", dir, name), *r = util_printf("%s/%s/run.json", dir, name);
    *matrix = status == 0 ? read_json(m) : NULL;
    *run = status == 0 ? read_json(r) : NULL;
    free(m), free(r);
    return *matrix && *run ? 0 : -1;
}

static void same_metrics(void)
{
    cJSON *mo = NULL, *ro = NULL, *me = NULL, *re = NULL;
    if (run_with("osmesa", "osmesa", &mo, &ro) || run_with("egl", "egl", &me, &re)) {
        cJSON_Delete(mo), cJSON_Delete(ro), cJSON_Delete(me), cJSON_Delete(re);
        return;
    }
    static const char *const keys[] = {"rmse", "penumbra_rmse", "leak_fraction", "dark_fraction", "max_abs",
                                       "p99_abs", "bias", "nonfinite", "scored_pixels"};
    const cJSON *ca = cJSON_GetObjectItem(mo, "cells"), *cb = cJSON_GetObjectItem(me, "cells");
    const cJSON *a = ca ? ca->child : NULL, *b = cb ? cb->child : NULL;
    /* Bit for bit only where EGL found llvmpipe too (no GPU here). */
    const char *renderer = cJSON_GetStringValue(cJSON_GetObjectItem(re, "gl_renderer"));
    if (!renderer || !strstr(renderer, "llvmpipe")) {
        printf("EGL renders on %s, not llvmpipe: metrics not compared\n", renderer ? renderer : "?");
        a = b = NULL;
    }
    int cells = 0;
    for (; a && b; a = a->next, b = b->next, cells++)
        for (size_t k = 0; k < sizeof keys / sizeof *keys; k++) {
            double x = cJSON_GetNumberValue(cJSON_GetObjectItem(a, keys[k]));
            double y = cJSON_GetNumberValue(cJSON_GetObjectItem(b, keys[k]));
            CHECK(x == y, "%s: %s %.9g through OSMesa, %.9g through EGL", cJSON_GetStringValue(
                  cJSON_GetObjectItem(a, "cell")), keys[k], x, y);
        }
    struct strbuf names = {0};
    const int want = every_product(&names);
    strbuf_free(&names);
    CHECK((cells == want || !strstr(renderer ? renderer : "", "llvmpipe")) && !a && !b,
          "both runs must have the same %d cells: %d", want, cells);
    const char *platform = cJSON_GetStringValue(cJSON_GetObjectItem(re, "gl_platform"));
    CHECK(platform && strncmp(platform, "EGL", 3) == 0, "run.json: gl_platform '%s' must name EGL", platform);
    platform = cJSON_GetStringValue(cJSON_GetObjectItem(ro, "gl_platform"));
    CHECK(platform && !strcmp(platform, "OSMesa"), "run.json: gl_platform '%s' must be OSMesa", platform);
    for (int i = 0; i < 2; i++) {
        const cJSON *run = i ? re : ro;
        CHECK(cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_vendor")), "run.json names the GL vendor");
        const char *method = cJSON_GetStringValue(cJSON_GetObjectItem(run, "timing_method"));
        const char *r = cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_renderer"));
        CHECK(!strstr(r ? r : "llvmpipe", "llvmpipe") || (method && !strcmp(method, "wall clock around glFinish")),
              "on llvmpipe auto times by the wall clock, not '%s'", method);
    }
    cJSON_Delete(mo), cJSON_Delete(ro), cJSON_Delete(me), cJSON_Delete(re);
}

/* One line on stderr, exit 2. */
static void refused(const char *env, const char *args, const char *line_start)
{
    char *cmd = util_printf("%s %s %s", env, sb, args);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    const char *nl = strchr(err.data, '\n');
    CHECK(status == 2, "'%s': exit %d, wanted 2", args, status);
    CHECK(strncmp(err.data, line_start, strlen(line_start)) == 0 && nl && !nl[1],
          "'%s': wanted one line starting '%s', got: %s", args, line_start, err.data);
    strbuf_free(&err);
    free(cmd);
}

/* The query path: every stage timed, positive and finite, and named. One
 * timed frame, so the stages must add up to the total: with more, each
 * column is its own median, and a sum of medians is not the median of the
 * frames' sums (3 frames on a loaded machine put them 30 % apart). The
 * tolerance is the printing's: four values rounded to 0.01 ms. */
static void timer_queries(void)
{
    char *cmd = util_printf("%s bench --gl egl --timing query --scene parallel_planes --technique hard,vsm "
                            "--width 64 --height 64 --shadow-map-size 256 --frames 1 --warmup 1", sb);
    struct strbuf out = {0}, err = {0};
    int status = run_cmd(cmd, &err, &out);
    CHECK(status == 0, "bench --timing query: exit %d: %s", status, err.data);
    CHECK(out.data && strstr(out.data, "timed by GL_TIME_ELAPSED queries"), "bench must name its method: %s",
          out.data);
    const char *vsm = out.data ? strstr(out.data, "\nvsm ") : NULL;
    double sm = NAN, prep = NAN, recv = NAN, screen = NAN, total = NAN;
    CHECK(vsm && sscanf(vsm, "\nvsm %lf %lf %lf %lf %lf", &sm, &prep, &recv, &screen, &total) == 5,
          "bench: no vsm row: %s", out.data);
    CHECK(screen == 0, "vsm has no screen-space stage (%g ms)", screen);
    CHECK(sm > 0 && prep > 0 && recv > 0 && fabs(sm + prep + recv - total) <= 0.02 + 1e-9,
          "queries: vsm's stages %g + %g + %g must be positive and make its total %g", sm, prep, recv, total);
    strbuf_free(&out), strbuf_free(&err);
    free(cmd);
}

int main(int argc, char **argv)
{
    if (!(sb = test_begin(argc, argv, dir)))
        return 1;
    same_metrics();
    char *no_egl = util_printf("run --gl egl --scene parallel_planes --technique hard --width 16 --height 16 "
                               "--no-cache -q --out %s/never", dir);
    refused("__EGL_VENDOR_LIBRARY_FILENAMES=/nonexistent.json", no_egl,
            "shadowbench: error: OpenGL: EGL found no display");
    free(no_egl);
    refused("", "run --gl vulkan", "shadowbench: error: --gl vulkan: not a GL backend (osmesa, egl)");
    refused("", "bench --timing sundial", "shadowbench: error: --timing sundial: not a timing method");
    refused("", "stability --timing wall", "shadowbench: error:");
    timer_queries();
    remove_tree(dir);
    return check_finish();
}
