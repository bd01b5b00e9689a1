/* Protects the output contract (docs/design.md §8) end to end: `run` on a small
 * image writes every file with sane values, `hard` produces no NaN/Inf on
 * the shipped scene, and the ground-truth cache is reused only when its key
 * (scene, size, samples, version) matches. */
#include "check.h"
#include "read_json.h"
#include "run_cmd.h"
#include "scene_library.h"
#include "base/image.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <string.h>

#define W 96
#define H 80

static const char *sb;
static int technique_count;  /* a default run has one cell per registered technique (engine
                                cells and engines' presets apart: they run only when named), */
static int preset_count;     /* and one per named setting of those (pcss@seed003, ...) */
static char dir[] = "/tmp/sb_test_e2e_XXXXXX";

static bool exists(const char *folder, const char *file)
{
    char *p = util_printf("%s/%s", folder, file);
    bool ok = util_file_exists(p);
    CHECK(ok, "missing output %s", p);
    free(p);
    return ok;
}

/* folder/file as JSON. */
static cJSON *read_json_in(const char *folder, const char *file)
{
    char *p = util_printf("%s/%s", folder, file);
    cJSON *j = read_json(p);
    free(p);
    return j;
}

static double num(const cJSON *o, const char *key)
{
    const cJSON *v = cJSON_GetObjectItem(o, key);
    CHECK(cJSON_IsNumber(v), "metric %s missing", key);
    return cJSON_IsNumber(v) ? v->valuedouble : NAN;
}

/* PNG width and height from the IHDR chunk. */
static void png_size(const char *path, int *w, int *h)
{
    char *data = NULL;
    size_t size = 0;
    *w = *h = -1;
    if (util_read_file(path, &data, &size) == 0 && size > 24 && memcmp(data + 1, "PNG", 3) == 0) {
        const unsigned char *p = (const unsigned char *)data;
        *w = p[16] << 24 | p[17] << 16 | p[18] << 8 | p[19];
        *h = p[20] << 24 | p[21] << 16 | p[22] << 8 | p[23];
    }
    free(data);
}

static int run(const char *out, const char *extra, struct strbuf *err, struct strbuf *stdout_text)
{
    char *cmd = util_printf("%s run --scene floating_box_sphere --width %d --height %d --gt-samples 64 "
                            "--shadow-map-size 512 --frames 2 --warmup 1 --cache %s/cache --out %s %s",
                            sb, W, H, dir, out, extra);
    int status = run_cmd(cmd, err, stdout_text);
    free(cmd);
    return status;
}

static void check_outputs(const char *out)
{
    const char *top[] = {"run.json", "matrix.csv", "matrix.json", "report.html",
                         "floating_box_sphere/groundtruth.exr", "floating_box_sphere/groundtruth.png"};
    const char *cell[] = {"visibility.exr", "error.exr", "visibility.png", "heatmap.png", "metrics.json"};
    for (size_t i = 0; i < ARRAY_SIZE(top); i++)
        exists(out, top[i]);
    char *cell_dir = util_printf("%s/floating_box_sphere/hard", out);
    for (size_t i = 0; i < ARRAY_SIZE(cell); i++)
        exists(cell_dir, cell[i]);

    /* metrics.json: every contract key, sane values. */
    cJSON *m = read_json_in(cell_dir, "metrics.json");
    if (m) {
        CHECK(num(m, "nonfinite") == 0, "hard on the shipped scene must not produce NaN/Inf");
        double scored = num(m, "scored_pixels");
        CHECK(scored > 0.3 * W * H && scored <= W * H, "scored_pixels %g of %d", scored, W * H);
        /* hard has no penumbra, the scene has wide ones: error must show, bounded by 1. */
        CHECK(num(m, "rmse") > 0.01 && num(m, "rmse") < 0.5, "rmse %g", num(m, "rmse"));
        CHECK(num(m, "penumbra_rmse") > num(m, "rmse"), "penumbra error exceeds the overall error");
        CHECK(num(m, "penumbra_pixels") > 0, "penumbra present");
        CHECK(num(m, "max_abs") <= 1.0 && num(m, "p99_abs") <= num(m, "max_abs"), "error bounds");
        CHECK(fabs(num(m, "bias")) <= num(m, "mae"), "|bias| <= mae");
        /* GL and the ray tracer sample the same pixel centres of the same
         * triangles: only silhouette pixels may disagree, a few % at most. */
        CHECK(num(m, "mismatch_pixels") < 0.03 * W * H, "mismatch_pixels %g",
              num(m, "mismatch_pixels"));
        CHECK(num(m, "ms_shadowmap") > 0 && num(m, "ms_receiver") > 0 && num(m, "ms_filter_prep") == 0,
              "timings: hard needs the depth product only");
        CHECK(num(m, "ms_total_q1") <= num(m, "ms_total") && num(m, "ms_total") <= num(m, "ms_total_q3"),
              "the median frame lies between its quartiles: %g <= %g <= %g", num(m, "ms_total_q1"),
              num(m, "ms_total"), num(m, "ms_total_q3"));
        CHECK(num(m, "shaded_rmse") > 0 && num(m, "terminator_pixels") >= 0, "shaded_rmse, terminator_pixels");
        CHECK(cJSON_IsTrue(cJSON_GetObjectItem(m, "scored")), "the cell is marked scored");
        CHECK(num(m, "gt_noise_rmse") > 0 && num(m, "gt_noise_rmse") < 0.05, "noise floor %g",
              num(m, "gt_noise_rmse"));
        const cJSON *dev = cJSON_GetObjectItem(m, "gl_renderer");
        CHECK(cJSON_IsString(dev) && strlen(dev->valuestring) > 0, "timings name their device");
        const cJSON *params = cJSON_GetObjectItem(m, "params");
        CHECK(cJSON_GetObjectItem(params, "slope_bias") && cJSON_GetObjectItem(params, "constant_bias"),
              "parameter values recorded");
        cJSON_Delete(m);
    }

    /* EXR channels and the error identity E = V_tech - V_gt on scored pixels. */
    char *gt_path = util_printf("%s/floating_box_sphere/groundtruth.exr", out);
    char *v_path = util_printf("%s/visibility.exr", cell_dir), *e_path = util_printf("%s/error.exr", cell_dir);
    struct exr_channel gt[] = {{"V", NULL}, {"V_weighted", NULL}, {"mask", NULL}, {"H", NULL}, {"E", NULL}};
    struct exr_channel v[] = {{"V", NULL}}, e[] = {{"E", NULL}};
    CHECK(image_read_exr(gt_path, W, H, gt, 5, NULL) == 0, "groundtruth.exr has V, V_weighted, mask, H, E");
    CHECK(image_read_exr(v_path, W, H, v, 1, NULL) == 0, "visibility.exr has V");
    CHECK(image_read_exr(e_path, W, H, e, 1, NULL) == 0, "error.exr has E");
    if (gt[0].data && v[0].data && e[0].data) {
        int bad = 0, scored = 0;
        for (int i = 0; i < W * H; i++) {
            bool s = gt[2].data[i] > 0.5f;
            scored += s;
            float expect = s ? v[0].data[i] - gt[0].data[i] : 0.0f;
            bad += fabsf(e[0].data[i] - expect) > 1e-6f || gt[0].data[i] < 0 || gt[0].data[i] > 1 ||
                   gt[1].data[i] < 0 || gt[1].data[i] > 1 || gt[3].data[i] < 0 || gt[3].data[i] > 1 ||
                   gt[4].data[i] < 0 || (s && (gt[3].data[i] < 0.05f || !(gt[4].data[i] > 0)));
        }
        CHECK(bad == 0, "%d pixels break E = V_tech - V_gt, leave [0,1] or are scored with H < 0.05 "
              "or no irradiance", bad);
        CHECK(scored > 0, "mask has scored pixels");
    }
    for (int i = 0; i < 5; i++)
        free(gt[i].data);
    free(v[0].data), free(e[0].data), free(gt_path), free(v_path), free(e_path);

    int pw, ph;
    char *png = util_printf("%s/visibility.png", cell_dir);
    png_size(png, &pw, &ph);
    CHECK(pw == W && ph == H, "visibility.png is %dx%d", pw, ph);
    free(png);
    png = util_printf("%s/heatmap.png", cell_dir);
    png_size(png, &pw, &ph);
    CHECK(pw == W && ph > H, "heatmap.png is %dx%d: the image plus its legend", pw, ph);
    free(png);
    free(cell_dir);

    /* Run-level files. */
    cJSON *run = read_json_in(out, "run.json");
    if (run) {
        const cJSON *r = cJSON_GetObjectItem(run, "gl_renderer");
        CHECK(cJSON_IsString(r) && strlen(r->valuestring) > 0, "run.json records GL_RENDERER");
        CHECK(cJSON_GetObjectItem(run, "command_line") && cJSON_GetObjectItem(run, "date") &&
              cJSON_GetObjectItem(run, "cpu") && cJSON_GetObjectItem(run, "git_describe"),
              "run.json records command line, date, CPU, git describe");
        cJSON_Delete(run);
    }
    cJSON *matrix = read_json_in(out, "matrix.json");
    if (matrix) {
        const cJSON *cells = cJSON_GetObjectItem(matrix, "cells");
        CHECK(cJSON_GetArraySize(cells) == technique_count + preset_count,
              "one cell per technique and per preset (%d + %d), got %d", technique_count, preset_count,
              cJSON_GetArraySize(cells));
        cJSON_Delete(matrix);
    }
    char *csv = util_printf("%s/matrix.csv", out), *text = NULL;
    size_t size;
    const bool have_csv = util_read_file(csv, &text, &size) == 0;
    CHECK(have_csv, "%s cannot be read", csv);  /* unreadable is a failure, never a pass */
    if (have_csv) {
        int lines = 0;
        for (size_t i = 0; i < size; i++)
            lines += text[i] == '\n';
        CHECK(lines == 1 + technique_count + preset_count,
              "matrix.csv: header + a row per technique and preset, got %d lines", lines);
        CHECK(strncmp(text, "scene,technique,params,rmse,", 28) == 0, "matrix.csv header");
    }
    free(text), free(csv);
    char *html = util_printf("%s/report.html", out);
    text = NULL;
    const bool have_html = util_read_file(html, &text, &size) == 0;
    CHECK(have_html, "%s cannot be read", html);  /* unreadable is a failure, never a pass */
    if (have_html)
        CHECK(strstr(text, "<table id=\"matrix\">") && strstr(text, "floating_box_sphere/hard/heatmap.png"),
              "report.html has the matrix and the cell's pictures");
    free(text), free(html);
}

/* A cell with nothing to score (the camera looks at the sky) is not a
 * perfect cell: null metrics, marked unscored, said on stderr, exit 1. */
static void check_unscored(void)
{
    struct mesh_builder mb = {0};
    struct gltf_scene_desc d;
    scene_parallel_planes(&mb, &d, 1.0f, false);
    d.camera_pos = v3(0, 3, 20), d.camera_target = v3(0, 3, 40);  /* away from everything */
    char *scene = util_printf("%s/sky.gltf", dir), *out = util_printf("%s/sky", dir);
    CHECK(gltf_write(scene, &mb, &d) == 0, "writing %s", scene);
    mesh_free(&mb);
    char *cmd = util_printf("%s run --scene %s --technique hard --width 32 --height 32 --gt-samples 16 "
                            "--shadow-map-size 256 --frames 1 --warmup 0 --no-cache --out %s", sb, scene, out);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 1, "an unscored cell must exit 1, got %d", status);
    CHECK(err.data && strstr(err.data, "sky/hard: unscored"), "stderr says which cell and why: %s",
          err.data ? err.data : "");
    char *cell_dir = util_printf("%s/sky/hard", out);
    cJSON *m = read_json_in(cell_dir, "metrics.json");
    if (m) {
        CHECK(cJSON_IsFalse(cJSON_GetObjectItem(m, "scored")), "marked unscored");
        CHECK(cJSON_IsNull(cJSON_GetObjectItem(m, "rmse")) && cJSON_IsNull(cJSON_GetObjectItem(m, "shaded_rmse")),
              "error metrics are null, not 0");
        CHECK(num(m, "scored_pixels") == 0, "scored_pixels 0");
        cJSON_Delete(m);
    }
    char *csv = util_printf("%s/matrix.csv", out), *text = NULL;
    size_t size;
    const bool have_csv = util_read_file(csv, &text, &size) == 0;
    CHECK(have_csv, "%s cannot be read", csv);  /* unreadable is a failure, never a pass */
    if (have_csv)
        CHECK(strstr(text, "\",,,,,") && strstr(text, ",false,,,\n"),
              "matrix.csv: empty fields for null, scored false, failed and an engine's texel ratios empty: %s",
              text);
    free(text), free(csv), free(cell_dir), free(cmd), free(scene), free(out);
    strbuf_free(&err);
}

int main(int argc, char **argv)
{
    if (!(sb = test_begin(argc, argv, dir)))
        return 1;
    for (int i = 0; technique_list[i]; i++) {
        if (technique_named_only(technique_list[i]))
            continue;
        technique_count++;
        for (const struct technique_preset *p = technique_list[i]->presets; p && p->name; p++)
            preset_count++;
    }

    char *out1 = util_printf("%s/run1", dir), *out2 = util_printf("%s/run2", dir),
         *out3 = util_printf("%s/run3", dir);
    struct strbuf err = {0}, out = {0};
    int status = run(out1, "", &err, &out);
    CHECK(status == 0, "run exit %d: %s", status, err.data);
    char *where = util_printf("report: %s/report.html", out1);
    CHECK(out.data && strstr(out.data, where), "run prints where the report is");
    free(where);
    CHECK(!strstr(err.data, "from cache"), "first run must ray trace");
    check_outputs(out1);

    /* Same key: the ground truth comes from the cache, identical. */
    strbuf_free(&err);
    status = run(out2, "", &err, NULL);
    CHECK(status == 0 && strstr(err.data, "from cache"), "second run must reuse the cache");
    char *a = util_printf("%s/floating_box_sphere/groundtruth.exr", out1);
    char *b = util_printf("%s/floating_box_sphere/groundtruth.exr", out2);
    struct exr_channel va[] = {{"V", NULL}}, vb[] = {{"V", NULL}};
    const bool read = image_read_exr(a, W, H, va, 1, NULL) == 0 && image_read_exr(b, W, H, vb, 1, NULL) == 0;
    CHECK(read, "%s and %s have V", a, b);  /* an unreadable file is a failure, never a pass */
    if (read)
        CHECK(memcmp(va[0].data, vb[0].data, sizeof(float) * W * H) == 0, "cached V is the same V");
    free(va[0].data), free(vb[0].data), free(a), free(b);

    /* Another sample count is another key: never silently reused. */
    strbuf_free(&err);
    char *cmd = util_printf("%s run --scene floating_box_sphere --width %d --height %d --gt-samples 16 "
                            "--shadow-map-size 512 --frames 1 --cache %s/cache --out %s", sb, W, H, dir, out3);
    status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0 && !strstr(err.data, "from cache"), "a changed key must ray trace again");
    free(cmd);

    check_unscored();

    strbuf_free(&err), strbuf_free(&out);
    free(out1), free(out2), free(out3);
    remove_tree(dir);
    return check_finish();
}
