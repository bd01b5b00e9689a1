/* Protects the run's report (docs/design.md §8) as a person opens it: a run with
 * a sweep writes the charts, and report.html, opened from disk in headless
 * Chromium (no server), holds the matrix (sorted by its script when the
 * address asks), every picture (each loads: a broken one is marked
 * "missing", which the test proves it would see), and the inline charts
 * with their Pareto fronts and bars (the front itself: test_policy). */
#include "check.h"
#include "scene/catalog.h"
#include "run_cmd.h"
#include "output/chart.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

static const char *sb;
static char dir[] = "/tmp/sb_test_report_XXXXXX";

#define SCENES 2
#define CONFIGS 3  /* hard, pcss@blocker_samples=16, pcss@blocker_samples=64 */

static int count(const char *text, const char *needle)
{
    int n = 0;
    for (const char *p = text; p && (p = strstr(p, needle)); p += strlen(needle))
        n++;
    return n;
}

/* The DOM of file://<path><suffix> after its scripts ran and its pictures
 * loaded (or failed to). */
static char *dump_dom(const char *path, const char *suffix)
{
    const char *chromium = getenv("CHROMIUM") ? getenv("CHROMIUM") : "/usr/bin/chromium";
    CHECK(util_file_exists(chromium), "%s not found: install Debian's chromium (tools/setup does)",
          chromium);
    char *cmd = util_printf("'%s' --headless --no-sandbox --disable-gpu --disable-quic --no-first-run "
                            "--disable-background-networking --disable-component-update --disable-sync "
                            "--user-data-dir=%s/chromium --dump-dom 'file://%s%s'",
                            chromium, dir, path, suffix);
    struct strbuf out = {0};
    int status = run_cmd(cmd, NULL, &out);
    CHECK(status == 0 && out.data, "chromium exit %d", status);
    free(cmd);
    return out.data ? out.data : xstrdup("");
}

/* The rmse column (the third) of the matrix rows, in DOM order. */
static int rmse_column(const char *dom, double *v, int max)
{
    const char *matrix = strstr(dom, "<table id=\"matrix\""), *body = matrix ? strstr(matrix, "<tbody>") : NULL;
    int n = 0;
    for (const char *row = body; row && (row = strstr(row, "<tr")) && n < max; row++) {
        const char *td = row;
        for (int k = 0; k < 3 && td; k++)
            td = strstr(td + 1, "<td");
        const char *dv = td ? strstr(td, "data-v=\"") : NULL;
        if (dv)
            v[n++] = atof(dv + 8);
    }
    return n;
}

/* The data-style of each legend entry of an SVG, checked distinct: two
 * series of one chart never look alike (colour, dash and marker). Returns
 * the number of entries. */
static int distinct_legend(const char *svg, const char *name)
{
    char styles[64][96];
    int n = 0;
    for (const char *p = svg; (p = strstr(p, "class=\"legend-entry\" data-style=\"")) && n < 64; n++) {
        p += strlen("class=\"legend-entry\" data-style=\"");
        const char *end = strchr(p, '"');
        snprintf(styles[n], sizeof styles[n], "%.*s", end ? (int)(end - p) : 0, p);
        for (int j = 0; j < n; j++)
            CHECK(strcmp(styles[j], styles[n]) != 0, "%s: two legend entries share the style %s", name, styles[n]);
    }
    return n;
}

/* The palette: the first CHART_DISTINCT_STYLES techniques each have a
 * style of their own; those a palette round apart (8: pcf and vssm) differ
 * in marker too. */
static void palette(void)
{
    int techniques = 0;
    while (technique_list[techniques])
        techniques++;
    CHECK(techniques <= CHART_DISTINCT_STYLES, "%d techniques, %d distinct styles: two would look alike", techniques,
          CHART_DISTINCT_STYLES);
    for (int a = 0; a < CHART_DISTINCT_STYLES; a++)
        for (int b = a + 1; b < CHART_DISTINCT_STYLES; b++) {
            const struct chart_style x = chart_style(a), y = chart_style(b);
            CHECK(strcmp(x.colour, y.colour) || strcmp(x.dash, y.dash) || x.marker != y.marker,
                  "techniques %d and %d share colour %s, dash %s and marker %s", a, b, x.colour, x.dash,
                  x.marker_name);
            if (b == a + 8)
                CHECK(x.marker != y.marker, "techniques %d and %d: one colour and one marker", a, b);
        }
    /* And as drawn: a chart of that many techniques has as many legend
     * styles, none twice. */
    struct chart_item items[CHART_DISTINCT_STYLES];
    double values[CHART_DISTINCT_STYLES];
    char names[CHART_DISTINCT_STYLES][8];
    for (int g = 0; g < CHART_DISTINCT_STYLES; g++) {
        snprintf(names[g], sizeof names[g], "t%d", g);
        items[g] = (struct chart_item){names[g], names[g], g};
        values[g] = g + 1;
    }
    const struct chart_series bars = {"rmse", "visibility", values, NULL, NULL, NULL, NAN};
    struct strbuf svg = {0};
    chart_bars_svg(&svg, "palette", "every style", items, CHART_DISTINCT_STYLES, &bars, 1);
    CHECK(distinct_legend(svg.data, "the 24-technique chart") == CHART_DISTINCT_STYLES, "a legend entry per technique");
    strbuf_free(&svg);
}

/* A scene whose file name and description are HTML: the report shows them
 * as text, and nothing in them runs (issue 12: a file name reached id,
 * href and a caption unescaped). */
static void hostile_names(void)
{
    char *src = catalog_resolve("parallel_planes"), *text;
    size_t size;
    CHECK(src && util_read_file(src, &text, &size) == 0, "reading parallel_planes");
    cJSON *g = cJSON_Parse(text);
    free(text);
    cJSON *meta = cJSON_GetObjectItem(cJSON_GetObjectItem(cJSON_GetArrayItem(cJSON_GetObjectItem(g, "scenes"), 0),
                                                          "extras"), "shadowbench");
    /* and a right-to-left override (U+202E) and a control character, which
     * would reorder the page and make the SVG charts invalid XML */
    cJSON_ReplaceItemInObject(meta, "description",
                              cJSON_CreateString("<script>document.title='2'</script> \u202egpj.exe \x01" "end"));
    char *long_text = xmalloc(10001);  /* and a text too long to copy whole */
    memset(long_text, 'x', 10000);
    long_text[10000] = '\0';
    cJSON_ReplaceItemInObject(meta, "shows", cJSON_CreateString(long_text));
    free(long_text);
    char *json = cJSON_Print(g), *path = util_printf("%s/<img src=x onerror=\"document.title=1\">.gltf", dir);
    CHECK(util_write_file_atomic(path, json, strlen(json)) == 0, "writing %s", path);
    cJSON_free(json);
    cJSON_Delete(g);
    char *out = util_printf("%s/hostile", dir);
    char *cmd = util_printf("%s run --scene '%s' --technique hard --width 32 --height 32 --gt-samples 4 "
                            "--frames 1 --warmup 0 --no-cache -q --out %s", sb, path, out);
    struct strbuf err = {0};
    CHECK(run_cmd(cmd, &err, NULL) == 0, "run on the hostile names: %s", err.data);
    char *report = util_printf("%s/report.html", out);
    char *dom = dump_dom(report, "");
    CHECK(strstr(dom, "<title>shadowbench report</title>"), "a script from a name or description ran");
    CHECK(!strstr(dom, "<img src=\"x\"") && !strstr(dom, "<script>document") &&
              strstr(dom, "&lt;img src=x onerror=\"document.title=1\"&gt;") &&
              strstr(dom, "&lt;script&gt;document.title='2'&lt;/script&gt;"),
          "the names show as text, not as markup");
    CHECK(strstr(dom, " [U+202E]gpj.exe \xef\xbf\xbd" "end") && !strstr(dom, "\u202e") && !strstr(dom, "\x01"),
          "the override shows as [U+202E], the control character as U+FFFD");
    CHECK(strstr(dom, "[... 5904 more bytes, in the scene file]") && !strstr(dom, "xxxxx<"),
          "a 10000-byte text is cut at 4096 bytes, with a note");
    strbuf_free(&err);
    free(dom), free(report), free(cmd), free(out), free(path), free(src);
}

int main(int argc, char **argv)
{
    if (!(sb = test_begin(argc, argv, dir)))
        return 1;
    hostile_names();
    palette();

    char *out = util_printf("%s/run", dir);
    char *cmd = util_printf("%s run --scene parallel_planes --scene contact_hardening --technique hard,pcss "
                            "--sweep pcss.blocker_samples=16,64 --width 96 --height 96 --gt-samples 16 "
                            "--frames 1 --warmup 0 --no-cache -q --out %s", sb, out);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0, "run exit %d: %s", status, err.data);
    free(cmd);

    /* Each swept value is a cell with its own folder and matrix row. */
    char *swept = util_printf("%s/parallel_planes/pcss@blocker_samples=64/metrics.json", out);
    CHECK(util_file_exists(swept), "%s missing", swept);
    free(swept);

    /* The charts, as files: labelled axes with units, the device, a legend. */
    const char *charts[] = {"overall_tradeoff",         "parallel_planes_tradeoff",   "parallel_planes_fetches",
                            "parallel_planes_metrics",  "contact_hardening_tradeoff", "contact_hardening_fetches",
                            "contact_hardening_metrics"};
    for (size_t i = 0; i < ARRAY_SIZE(charts); i++) {
        char *path = util_printf("%s/charts/%s.svg", out, charts[i]), *svg = NULL;
        size_t size;
        CHECK(util_read_file(path, &svg, &size) == 0, "%s missing", path);
        if (svg) {
            bool tradeoff = strstr(charts[i], "tradeoff") != NULL, fetches = strstr(charts[i], "fetches") != NULL;
            CHECK(strstr(svg, "<svg") && strstr(svg, fetches ? "counted on the device" : "timed on llvmpipe") &&
                      strstr(svg, ">pcss</text>"),
                  "%s: an SVG naming its device (or its counted cost), with a legend", charts[i]);
            if (fetches)  /* counted: no spread */
                CHECK(strstr(svg, "fetches_per_pixel (shadow-map fetches per covered pixel)") &&
                          strstr(svg, "rmse (visibility, lower is better)") && count(svg, "class=\"pareto\"") == 2 &&
                          count(svg, "class=\"point\"") == 2 * CONFIGS && count(svg, "class=\"spread\"") == 0,
                      "%s: the fetches axis with its unit, two panels with a front, a point per cell", charts[i]);
            else if (tradeoff)
                CHECK(strstr(svg, "ms_total (ms per frame, median; bar: quartiles)") &&
                          strstr(svg, "rmse (visibility, lower is better)") &&
                          count(svg, "class=\"pareto\"") == 2 && count(svg, "class=\"point\"") == 2 * CONFIGS &&
                          count(svg, "class=\"spread\"") == 2 * CONFIGS,
                      "%s: axes with units, two panels with a front, a point and a time spread per "
                      "cell", charts[i]);
            else
                CHECK(count(svg, "class=\"bar\"") == 5 * CONFIGS &&
                          strstr(svg, "leak_fraction (share of scored pixels)") && strstr(svg, "shaded_rmse"),
                      "%s: five metrics, a bar per cell", charts[i]);
            CHECK(fetches || strstr(svg, "CPU rasteriser: ranks techniques for this device only"),
                  "%s: says what llvmpipe times are worth", charts[i]);
            CHECK(distinct_legend(svg, charts[i]) == 2, "%s: a legend entry per technique", charts[i]);
        }
        free(svg), free(path);
    }

    /* The report in a browser, sorted by rmse from its address. */
    char *report = util_printf("%s/report.html", out);
    char *dom = dump_dom(report, "#sort=rmse");
    CHECK(strstr(dom, "<table id=\"matrix\" data-sorted-by=\"rmse\">"), "the script sorted the matrix");
    double v[64];
    int rows = rmse_column(dom, v, 64);
    CHECK(rows == SCENES * CONFIGS, "matrix rows: %d", rows);
    for (int i = 1; i < rows; i++)
        CHECK(v[i - 1] <= v[i], "row %d: rmse %g after %g", i, v[i], v[i - 1]);
    /* In the file the rows are in run order (hard, with no penumbra, before
     * pcss): the sort did reorder them. */
    char *raw = NULL;
    size_t size;
    const bool have_report = util_read_file(report, &raw, &size) == 0;
    CHECK(have_report, "%s cannot be read", report);  /* unreadable is a failure, never a pass */
    if (have_report) {
        double u[64];
        CHECK(rmse_column(raw, u, 64) == rows && u[0] > u[1], "run order is not rmse order");
    }
    free(raw);
    /* The summary first: the budget table, the overall chart and the worst
     * cells before the scenes, the matrix last. */
    const char *summary = strstr(dom, "id=\"summary\""), *budgets = strstr(dom, "<table id=\"budgets\""),
               *overall = strstr(dom, "id=\"chart-overall_tradeoff\""), *worst = strstr(dom, "id=\"worst\""),
               *scene = strstr(dom, "id=\"scene-parallel_planes\""), *matrix = strstr(dom, "<table id=\"matrix\"");
    CHECK(summary && budgets && overall && worst && scene && matrix && summary < budgets && budgets < overall &&
              overall < worst && worst < scene && scene < matrix,
          "the report's order: summary, budgets, overall chart, worst failures, scenes, matrix");
    /* Budget rows: budgets rising, the least error falling, the last row's
     * the least mean penumbra_rmse of any configuration (from matrix.json). */
    double budget[CONFIGS + 1], pen[CONFIGS + 1];
    int budget_rows = 0;
    const char *budget_end = budgets ? strstr(budgets, "</table>") : NULL;
    for (const char *p = budgets; p && budget_end && (p = strstr(p + 1, "<tr><td class=\"l\">\xe2\x89\xa4 ")) &&
                                  p < budget_end && budget_rows <= CONFIGS;) {
        const char *e = strstr(p, "</b></td><td>");
        budget[budget_rows] = atof(p + strlen("<tr><td class=\"l\">\xe2\x89\xa4 "));
        pen[budget_rows++] = e ? atof(e + strlen("</b></td><td>")) : NAN;
    }
    CHECK(budget_rows >= 1 && budget_rows <= CONFIGS, "budget rows: %d", budget_rows);
    for (int i = 1; i < budget_rows && i <= CONFIGS; i++)
        CHECK(budget[i] > budget[i - 1] && pen[i] < pen[i - 1], "budget row %d: %g ms, %g after %g ms, %g", i,
              budget[i], pen[i], budget[i - 1], pen[i - 1]);
    char *matrix_path = util_printf("%s/matrix.json", out), *matrix_text = NULL;
    double least = INFINITY;
    if (util_read_file(matrix_path, &matrix_text, &size) == 0) {
        cJSON *mj = cJSON_Parse(matrix_text), *cells = cJSON_GetObjectItem(mj, "cells"), *c;
        const char *labels[] = {"hard", "pcss@blocker_samples=16", "pcss@blocker_samples=64"};
        for (size_t k = 0; k < ARRAY_SIZE(labels); k++) {
            double sum = 0;
            cJSON_ArrayForEach(c, cells)
                if (strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(c, "cell")), labels[k]) == 0)
                    sum += cJSON_GetNumberValue(cJSON_GetObjectItem(c, "penumbra_rmse"));
            least = fmin(least, sum / SCENES);
        }
        cJSON_Delete(mj);
    }
    CHECK(budget_rows >= 1 && fabs(pen[budget_rows - 1] - least) < 5e-5,
          "the last budget's answer has the least mean penumbra_rmse, %.4f (the table's: %.4f, rounded to 4 digits)",
          least, budget_rows ? pen[budget_rows - 1] : NAN);
    free(matrix_text), free(matrix_path);
    const int failures = count(dom, "class=\"failure\"");
    CHECK(failures >= 1, "the worst cells are shown (hard leaks and darkens)");
    int images = SCENES * (1 + 2 * CONFIGS) + 2 * failures;  /* ground truth, per cell and per failure
                                                                visibility + heatmap */
    CHECK(count(dom, "<img ") == images, "%d pictures, wanted %d", count(dom, "<img "), images);
    CHECK(count(dom, "class=\"missing\"") == 0, "every picture loads");
    CHECK(count(dom, "<figure class=\"chart\"") == (int)ARRAY_SIZE(charts), "inline charts");
    CHECK(count(dom, "class=\"pareto\"") == 2 * (1 + 2 * SCENES), "a Pareto front in every panel");
    CHECK(strstr(dom, "Environment (run.json)") && strstr(dom, "gl_renderer"), "the run's environment");
    free(dom);

    /* Filtered from the address: only pcss's rows of one scene. */
    dom = dump_dom(report, "#scene=contact_hardening&technique=pcss");
    CHECK(count(dom, "data-technique=\"pcss\"><td") == CONFIGS - 1 &&
              count(dom, "hidden=\"\"><td") == SCENES * CONFIGS - (CONFIGS - 1) && strstr(dom, ">2 of 6 cells<"),
          "the matrix filtered to a scene and a technique: %d shown, %d hidden",
          count(dom, "data-technique=\"pcss\"><td"), count(dom, "hidden=\"\"><td"));
    free(dom);

    /* The same check sees a picture that does not load (each place it is shown). */
    char *gone = util_printf("%s/contact_hardening/hard/heatmap.png", out);
    char *page = NULL;
    CHECK(util_read_file(report, &page, &size) == 0, "%s cannot be read", report);
    const int shown = page ? count(page, "contact_hardening/hard/heatmap.png") : 0;
    free(page);
    CHECK(remove(gone) == 0, "removing %s", gone);
    dom = dump_dom(report, "");
    CHECK(shown >= 1 && count(dom, "class=\"missing\"") == shown, "a missing picture is marked: %d of %d",
          count(dom, "class=\"missing\""), shown);
    free(dom), free(gone), free(report), free(out);
    strbuf_free(&err);
    remove_tree(dir);
    return check_finish();
}
