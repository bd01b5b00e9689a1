#include "report.h"
#include "cell_output.h"
#include "chart.h"
#include "score/frontier.h"
#include "picture.h"
#include "base/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

cJSON *report_cell_json(const struct cell *c)
{
    cJSON *o = cJSON_CreateObject();
    cJSON_AddStringToObject(o, "scene", c->scene);
    cJSON_AddStringToObject(o, "technique", c->technique->name);
    cJSON_AddStringToObject(o, "cell", c->label);
    cJSON_AddItemToObject(o, "params", cJSON_Duplicate(c->params, 1));
    cJSON_AddBoolToObject(o, "scored", metrics_scored(&c->m));
    for (int k = 0; k < METRIC_COUNT; k++) {
        double v = metrics_value(&c->m, k);
        if (isnan(v))  /* nothing to score: null, never a perfect 0 (docs/design.md §7) */
            cJSON_AddNullToObject(o, metric_info[k].key);
        else
            cJSON_AddNumberToObject(o, metric_info[k].key, v);
    }
    cJSON_AddStringToObject(o, "gl_renderer", c->gl_renderer);
    if (c->engine_version) {  /* rendered by an engine, timed on its browser's device (docs/engines.md) */
        cJSON *e = cJSON_AddObjectToObject(o, "engine");
        cJSON_AddStringToObject(e, "name", c->technique->engine);
        cJSON_AddStringToObject(e, "package", c->technique->engine_package);
        cJSON_AddStringToObject(e, "version", c->engine_version);
        cJSON_AddStringToObject(e, "renderer", c->engine_renderer);
        if (isfinite(c->engine_texel_ratio[0]) && isfinite(c->engine_texel_ratio[1]))
            cJSON_AddItemToObject(e, "texel_ratio", cJSON_CreateDoubleArray(c->engine_texel_ratio, 2));
    }
    if (technique_is_preset(c->technique)) {  /* the engine filter it re-implements (docs/presets.md) */
        cJSON *p = cJSON_AddObjectToObject(o, "preset");
        cJSON_AddStringToObject(p, "of", c->technique->preset_of);
        cJSON_AddStringToObject(p, "source", c->technique->preset_source);
    }
    /* the scored mask's camera-distance tolerance off the truth's silhouettes (score/metrics.h) */
    char tolerance[32];  /* the float's shortest decimal, not its double's digits */
    snprintf(tolerance, sizeof tolerance, "%g", (double)metrics_depth_tolerance(c->technique->depth_tolerance));
    cJSON_AddRawToObject(o, "depth_tolerance", tolerance);
    if (c->cascades)
        cJSON_AddItemToObject(o, "cascades", cJSON_Duplicate(c->cascades, 1));
    if (c->cascades)  /* scored with its maps in hand */
        cJSON_AddItemToObject(o, "depth", depth_metrics_json(&c->depth));
    if (c->notice)
        cJSON_AddStringToObject(o, "notice", c->notice);
    if (c->failed)
        cJSON_AddStringToObject(o, "failed", c->failed);
    return o;
}

static char *dup_string(const cJSON *j, const char *key)
{
    const char *s = cJSON_GetStringValue(cJSON_GetObjectItem(j, key));
    return s ? xstrdup(s) : NULL;
}

int report_cell_read(const cJSON *j, struct cell *c)
{
    if (metrics_read_json(j, &c->m) != 0)
        return -1;
    c->gl_renderer = cJSON_GetStringValue(cJSON_GetObjectItem(j, "gl_renderer"));
    const cJSON *e = cJSON_GetObjectItem(j, "engine"), *ratio = cJSON_GetObjectItem(e, "texel_ratio");
    c->engine_texel_ratio[0] = c->engine_texel_ratio[1] = NAN;
    if (e) {
        c->engine_version = dup_string(e, "version");
        c->engine_renderer = dup_string(e, "renderer");
        c->gl_renderer = c->engine_renderer;
        for (int k = 0; k < 2 && cJSON_GetArraySize(ratio) == 2; k++)
            c->engine_texel_ratio[k] = cJSON_GetNumberValue(cJSON_GetArrayItem(ratio, k));
    }
    const cJSON *cascades = cJSON_GetObjectItem(j, "cascades");
    c->cascades = cascades ? cJSON_Duplicate(cascades, 1) : NULL;
    c->notice = dup_string(j, "notice");
    c->failed = dup_string(j, "failed");
    return c->gl_renderer && (!e || c->engine_version) &&
                   (!cascades || depth_metrics_read(cJSON_GetObjectItem(j, "depth"), &c->depth) == 0)
               ? 0 : -1;
}

int report_write_json(const char *path, const cJSON *value)
{
    char *text = cJSON_Print(value);
    struct strbuf sb = {0};
    strbuf_printf(&sb, "%s\n", text);
    int rc = util_write_file_atomic(path, sb.data, sb.len);
    strbuf_free(&sb);
    cJSON_free(text);
    return rc ? -1 : 0;
}

void report_csv_field(struct strbuf *sb, const char *s)
{
    strbuf_append(sb, "\"", 1);
    for (; *s; s++)
        strbuf_append(sb, *s == '"' ? "\"\"" : s, *s == '"' ? 2 : 1);
    strbuf_append(sb, "\"", 1);
}

static void depth_row(struct strbuf *csv, const struct cell *c, const char *kind, int index,
                      const struct depth_group *g, double seam, double gt_seam)
{
    report_csv_field(csv, c->scene);
    strbuf_printf(csv, ",");
    report_csv_field(csv, c->label);
    strbuf_printf(csv, ",%s,%d", kind, index);
    const double x[] = {g->lo, g->hi, g->rmse, g->penumbra_rmse, g->gt_noise_penumbra_rmse, seam, gt_seam};
    for (size_t k = 0; k < ARRAY_SIZE(x); k++)
        strbuf_printf(csv, isfinite(x[k]) ? ",%.9g" : ",", x[k]);  /* none: an empty field */
    strbuf_printf(csv, ",%ld,%ld\n", g->pixels, g->penumbra_pixels);
}

/* depth.csv (docs/outputs.md): every cell's error by view depth, one row
 * per distance bin, cascade slice and seam side. */
static int write_depth(const struct report *r)
{
    struct strbuf csv = {0};
    strbuf_printf(&csv, "scene,cell,kind,index,from,to,rmse,penumbra_rmse,gt_noise_penumbra_rmse,seam,gt_seam,"
                        "pixels,penumbra_pixels\n");
    for (int i = 0; i < r->cell_count; i++) {
        const struct cell *c = &r->cells[i];
        const struct depth_metrics *d = &c->depth;
        for (int b = 0; b < d->bins; b++)
            depth_row(&csv, c, "bin", b, &d->bin[b], NAN, NAN);
        for (int k = 0; k < d->slices; k++)
            depth_row(&csv, c, "slice", k, &d->slice[k], NAN, NAN);
        for (int k = 0; k + 1 < d->slices; k++) {
            depth_row(&csv, c, "seam_near", k, &d->seam[k].near, d->seam[k].seam, d->seam[k].gt_seam);
            depth_row(&csv, c, "seam_far", k, &d->seam[k].far, d->seam[k].seam, d->seam[k].gt_seam);
        }
    }
    char *path = util_printf("%s/depth.csv", r->out_dir);
    const int rc = util_write_file_atomic(path, csv.data, csv.len);
    free(path);
    strbuf_free(&csv);
    return rc ? -1 : 0;
}

static int write_matrix(const struct report *r)
{
    struct strbuf csv = {0};
    strbuf_printf(&csv, "scene,technique,params");
    for (int k = 0; k < METRIC_COUNT; k++)
        strbuf_printf(&csv, ",%s", metric_info[k].key);
    strbuf_printf(&csv, ",gl_renderer,cell,scored,failed,engine_texel_ratio_x,engine_texel_ratio_y\n");
    cJSON *matrix = cJSON_CreateObject();
    cJSON *cells = cJSON_AddArrayToObject(matrix, "cells");
    for (int i = 0; i < r->cell_count; i++) {
        cJSON *row = report_cell_json(&r->cells[i]);
        report_csv_field(&csv, r->cells[i].scene);
        strbuf_printf(&csv, ",");
        report_csv_field(&csv, r->cells[i].technique->name);
        strbuf_printf(&csv, ",");
        report_csv_field(&csv, r->cells[i].params_text);
        for (int k = 0; k < METRIC_COUNT; k++) {
            double v = metrics_value(&r->cells[i].m, k);
            strbuf_printf(&csv, isnan(v) ? "," : ",%.9g", v);  /* null: an empty field */
        }
        strbuf_printf(&csv, ",");
        report_csv_field(&csv, r->cells[i].gl_renderer);
        strbuf_printf(&csv, ",");
        report_csv_field(&csv, r->cells[i].label);
        strbuf_printf(&csv, ",%s,", metrics_scored(&r->cells[i].m) ? "true" : "false");
        if (r->cells[i].failed)  /* run --keep-going's reason; an empty field: none */
            report_csv_field(&csv, r->cells[i].failed);
        for (int k = 0; k < 2; k++) {  /* an engine's map's texel over shadowbench's; empty: none said */
            const double ratio = r->cells[i].engine_version ? r->cells[i].engine_texel_ratio[k] : NAN;
            strbuf_printf(&csv, isfinite(ratio) ? ",%.6g" : ",", ratio);
        }
        strbuf_printf(&csv, "\n");
        cJSON_AddItemToArray(cells, row);
    }
    char *csv_path = util_printf("%s/matrix.csv", r->out_dir);
    char *json_path = util_printf("%s/matrix.json", r->out_dir);
    int rc = util_write_file_atomic(csv_path, csv.data, csv.len) ||
             report_write_json(json_path, matrix);
    free(csv_path);
    free(json_path);
    cJSON_Delete(matrix);
    strbuf_free(&csv);
    return rc || write_depth(r) ? -1 : 0;
}

/* ---- charts ------------------------------------------------------------- */

static struct chart_item item_of(const struct cell *c)
{
    return (struct chart_item){c->label, c->technique->name, technique_index(c->technique)};
}


/* A scene's own text, escaped, and cut at REPORT_TEXT_MAX bytes (at a
 * character boundary) with a note: a file's text is not the report's to
 * copy whole. */
#define REPORT_TEXT_MAX 4096
static void text_capped(struct strbuf *h, const char *s)
{
    const size_t n = strlen(s);
    if (n <= REPORT_TEXT_MAX) {
        strbuf_xml(h, s);
        return;
    }
    size_t cut = REPORT_TEXT_MAX;
    while (cut > 0 && ((unsigned char)s[cut] & 0xc0) == 0x80)  /* not inside a UTF-8 sequence */
        cut--;
    char *head = util_printf("%.*s", (int)cut, s);
    strbuf_xml(h, head);
    strbuf_printf(h, " <i>[... %zu more bytes, in the scene file]</i>", n - cut);
    free(head);
}

/* Writes <out>/charts/<name>.svg and appends the SVG to html. */
static int emit_chart(const struct report *r, const char *name, struct strbuf *svg, struct strbuf *html)
{
    char *path = util_printf("%s/charts/%s.svg", r->out_dir, name);
    int rc = util_write_file_atomic(path, svg->data, svg->len);
    /* name holds a scene's name, i.e. a file name: escaped wherever it goes. */
    strbuf_printf(html, "<figure class=\"chart\" id=\"chart-");
    report_url(html, name);
    strbuf_printf(html, "\">\n%s<figcaption><a href=\"charts/", svg->data);
    report_url(html, name);
    strbuf_printf(html, ".svg\">charts/");
    strbuf_xml(html, name);
    strbuf_printf(html, ".svg</a></figcaption></figure>\n");
    free(path);
    strbuf_free(svg);
    return rc ? -1 : 0;
}

/* What the charts plot: a point or bar per item (a cell, or a configuration's
 * mean over the scenes). Arrays of r->cell_count, the most there can be. */
struct chart_points {
    int n;
    struct chart_item *items;
    double *ms, *q1, *q3, *rmse, *pen, *shaded, *leak, *dark, *fetches;
    int *count;
};

static void points_alloc(struct chart_points *p, int capacity)
{
    size_t n = (size_t)capacity;
    *p = (struct chart_points){.items = xcalloc(n, sizeof *p->items), .count = xcalloc(n, sizeof(int))};
    double **arrays[] = {&p->ms, &p->q1, &p->q3, &p->rmse, &p->pen, &p->shaded, &p->leak, &p->dark, &p->fetches};
    for (size_t i = 0; i < ARRAY_SIZE(arrays); i++)
        *arrays[i] = xcalloc(n, sizeof(double));
}

static void points_free(struct chart_points *p)
{
    free(p->items), free(p->ms), free(p->q1), free(p->q3), free(p->rmse), free(p->pen);
    free(p->shaded), free(p->leak), free(p->dark), free(p->fetches), free(p->count);
}

/* The subtitle of a chart: its device, and what the times mean there. */
static char *chart_subtitle(const char *device, const char *extra)
{
    bool cpu = device && strstr(device, "llvmpipe");
    return util_printf("timed on %s%s%s", device ? device : "an unknown device",
                       cpu ? " (CPU rasteriser: ranks techniques for this device only)" : "", extra);
}

/* Under the sun: each cell's error against the view depth of its pixels
 * (depth_metrics' distance bins, at their geometric centres), where
 * perspective aliasing and cascade splits show. */
static int distance_chart(const struct report *r, const char *scene, struct strbuf *html)
{
    struct chart_line *rmse = xcalloc((size_t)r->cell_count, sizeof *rmse);
    struct chart_line *pen = xcalloc((size_t)r->cell_count, sizeof *pen);
    double *x = xcalloc((size_t)r->cell_count * DEPTH_BINS * 3, sizeof(double));
    int n = 0;
    const cJSON *maps = NULL;
    for (int i = 0; i < r->cell_count; i++) {
        const struct cell *c = &r->cells[i];
        if (strcmp(c->scene, scene) != 0 || !cJSON_IsTrue(cJSON_GetObjectItem(c->cascades, "applied")) ||
            c->depth.bins == 0)
            continue;
        maps = cJSON_GetObjectItem(c->cascades, "maps");
        double *bx = &x[(size_t)n * DEPTH_BINS * 3], *by = bx + DEPTH_BINS, *bp = by + DEPTH_BINS;
        for (int b = 0; b < c->depth.bins; b++) {
            bx[b] = sqrt((double)c->depth.bin[b].lo * c->depth.bin[b].hi);
            by[b] = c->depth.bin[b].rmse, bp[b] = c->depth.bin[b].penumbra_rmse;
        }
        rmse[n] = (struct chart_line){item_of(c), c->depth.bins, bx, by, NULL};
        pen[n] = (struct chart_line){item_of(c), c->depth.bins, bx, bp, NULL};
        n++;
    }
    int rc = 0;
    if (n) {
        const struct chart_panel panels[] = {{"rmse", "visibility", rmse, n}, {"penumbra_rmse", "visibility", pen, n}};
        const int cascades = cJSON_GetArraySize(maps);
        char *title = util_printf("%s: error against distance from the camera", scene);
        char *sub = util_printf("%d shadow map%s over the view; each point a distance bin", cascades,
                                cascades == 1 ? "" : "s (cascades)");
        struct strbuf svg = {0};
        chart_lines_svg(&svg, title, sub, "view depth (scene units, log scale)", true, NAN, NULL, panels, 2);
        char *name = util_printf("%s_distance", scene);
        rc = emit_chart(r, name, &svg, html);
        free(title), free(sub), free(name);
    }
    free(rmse), free(pen), free(x);
    return rc;
}

/* Per scene: error against time, and the four failure metrics as bars. */
static int scene_charts(const struct report *r, const char *scene, const char *device,
                        struct strbuf *html)
{
    struct chart_points p;
    points_alloc(&p, r->cell_count);
    /* shadowbench's own cells first: the time charts hold only them, timed on
     * the run's device (an engine's times are its browser's: the summary's
     * engines_tradeoff charts them, over all scenes) */
    int own = 0;
    for (int engines = 0; engines <= 1; engines++) {
        if (engines)
            own = p.n;
        for (int i = 0; i < r->cell_count; i++) {
            const struct cell *c = &r->cells[i];
            if (strcmp(c->scene, scene) != 0 || technique_is_engine(c->technique) != engines)
                continue;
            p.items[p.n] = item_of(c);
            p.ms[p.n] = c->m.ms_total, p.q1[p.n] = c->m.ms_total_q1, p.q3[p.n] = c->m.ms_total_q3;
            p.rmse[p.n] = c->m.rmse, p.pen[p.n] = c->m.penumbra_rmse, p.shaded[p.n] = c->m.shaded_rmse;
            p.leak[p.n] = c->m.leak_fraction, p.dark[p.n] = c->m.dark_fraction;
            p.fetches[p.n] = c->m.fetches_per_pixel;
            p.n++;
        }
    }
    const struct chart_series time = {"ms_total", "ms", p.ms, p.q1, p.q3, NULL, NAN};
    const struct chart_series fetches = {"fetches_per_pixel", "shadow-map fetches per covered pixel", p.fetches,
                                         NULL, NULL, NULL, NAN};
    const struct chart_series bars[] = {{"rmse", "visibility", p.rmse, NULL, NULL, NULL, NAN},  /* the first two: errors */
                                        {"penumbra_rmse", "visibility", p.pen, NULL, NULL, NULL, NAN},
                                        {"shaded_rmse", "share of mean irradiance", p.shaded, NULL, NULL, NULL, NAN},
                                        {"leak_fraction", "share of scored pixels", p.leak, NULL, NULL, NULL, NAN},
                                        {"dark_fraction", "share of scored pixels", p.dark, NULL, NULL, NULL, NAN}};
    char *title = util_printf("%s: error against time per frame", scene), *sub = chart_subtitle(device, "");
    struct strbuf svg = {0};
    chart_tradeoff_svg(&svg, title, sub, p.items, own, &time, bars, 2);
    char *name = util_printf("%s_tradeoff", scene);
    int rc = emit_chart(r, name, &svg, html);
    free(title), free(name);
    /* the same against the counted cost, which holds on any device */
    title = util_printf("%s: error against fetches per pixel", scene);
    chart_tradeoff_svg(&svg, title, "shadow-map fetches counted on the device (receiver pass and mask): a cost "
                       "that holds on any GPU", p.items, own, &fetches, bars, 2);
    name = util_printf("%s_fetches", scene);
    rc |= emit_chart(r, name, &svg, html);
    free(title), free(name);
    title = util_printf("%s: error and failure metrics per technique", scene);
    chart_bars_svg(&svg, title, sub, p.items, p.n, bars, (int)ARRAY_SIZE(bars));
    name = util_printf("%s_metrics", scene);
    rc |= emit_chart(r, name, &svg, html);
    free(title), free(name), free(sub);
    points_free(&p);
    return rc || distance_chart(r, scene, html) ? -1 : 0;
}

/* A configuration (a cell label) over every scene of the run, among
 * shadowbench's own or among the engine cells (whose times are their
 * browser's device's, never compared with the run's): its mean
 * rmse and ms_total, and its mean penumbra_rmse over the scenes that have
 * a penumbra band (NAN with none); complete when every scene scored it. */
struct config_mean {
    const struct cell *first;
    double ms, q1, q3, pen, rmse, fetches, expensive, misclassified;
    int n, pen_n, misclassified_n;
    bool complete;
};

static int config_means(const struct report *r, bool engines, struct config_mean *out)
{
    int n = 0;
    for (int i = 0; i < r->cell_count; i++) {
        const struct cell *c = &r->cells[i];
        if (technique_is_engine(c->technique) != engines)
            continue;
        int k = 0;
        while (k < n && strcmp(out[k].first->label, c->label) != 0)
            k++;
        if (k == n)
            out[n++] = (struct config_mean){.first = c, .complete = true};
        struct config_mean *m = &out[k];
        m->complete &= metrics_scored(&c->m) && !c->m.nonfinite;
        m->ms += c->m.ms_total, m->q1 += c->m.ms_total_q1, m->q3 += c->m.ms_total_q3;
        if (isfinite(c->m.penumbra_rmse))  /* none: the scene has no penumbra band */
            m->pen += c->m.penumbra_rmse, m->pen_n++;
        m->rmse += c->m.rmse;
        m->fetches += c->m.fetches_per_pixel, m->expensive += c->m.expensive_fraction;
        if (isfinite(c->m.misclassified_fraction))  /* none: nothing decided early */
            m->misclassified += c->m.misclassified_fraction, m->misclassified_n++;
        m->n++;
    }
    for (int k = 0; k < n; k++) {
        struct config_mean *m = &out[k];
        m->complete &= m->n == r->scene_count;
        m->ms /= m->n, m->q1 /= m->n, m->q3 /= m->n, m->rmse /= m->n;
        m->fetches /= m->n, m->expensive /= m->n;
        m->pen = m->pen_n ? m->pen / m->pen_n : NAN;
        m->misclassified = m->misclassified_n ? m->misclassified / m->misclassified_n : NAN;
    }
    return n;
}

/* Over all scenes: each configuration's (by label, first-seen order) mean
 * error and mean time; a configuration with an unscored cell has no mean
 * error (NAN: left out of the chart). */
static int overall_chart(const struct report *r, const char *device, bool engines, struct strbuf *html)
{
    struct chart_points p;
    points_alloc(&p, r->cell_count);
    struct config_mean *m = xcalloc((size_t)r->cell_count + 1, sizeof *m);
    p.n = config_means(r, engines, m);
    if (engines && p.n == 0) {
        free(m);
        points_free(&p);
        return 0;
    }
    for (int k = 0; k < p.n; k++) {
        p.items[k] = item_of(m[k].first);
        p.ms[k] = m[k].ms, p.q1[k] = m[k].q1, p.q3[k] = m[k].q3, p.rmse[k] = m[k].rmse, p.pen[k] = m[k].pen;
    }
    const struct chart_series time = {"mean ms_total", "ms", p.ms, p.q1, p.q3, NULL, NAN};
    const struct chart_series errors[] = {{"mean rmse", "visibility", p.rmse, NULL, NULL, NULL, NAN},
                                          {"mean penumbra_rmse", "visibility", p.pen, NULL, NULL, NULL, NAN}};
    char *title = util_printf("All %d scenes: mean error against mean time per frame%s", r->scene_count,
                              engines ? ", engine cells" : "");
    const char *renderer = NULL;  /* a cell's that rendered (one that failed has none) */
    for (int i = 0; i < r->cell_count && engines && !renderer; i++)
        renderer = r->cells[i].engine_renderer;
    char *engine_device = engines ? util_printf("%s, in headless Chromium, timed by the page's clock",
                                                renderer ? renderer : "an engine's device") : NULL;
    char *sub = chart_subtitle(engines ? engine_device : device,
                               "; each point one technique configuration, its bar the mean quartiles");
    struct strbuf svg = {0};
    chart_tradeoff_svg(&svg, title, sub, p.items, p.n, &time, errors, 2);
    free(title), free(sub), free(engine_device), free(m);
    points_free(&p);
    return emit_chart(r, engines ? "engines_tradeoff" : "overall_tradeoff", &svg, html);
}

/* Whether label is one of t's levels: its defaults (its own name) or one
 * of its named settings, <t>@<preset> (docs/presets.md: an engine's
 * quality levels; pcss's seed-003 steps). */
static bool level_of(const struct technique *t, const char *label)
{
    const size_t n = strlen(t->name);
    if (strncmp(label, t->name, n) != 0)
        return false;
    return !label[n] || (label[n] == '@' && technique_preset_find(t, label + n + 1));
}

/* The quality curves: each technique with named settings, a line through
 * its defaults and those settings over every scene, ordered by cost, mean
 * error against counted fetches and against time (two charts); nothing
 * when no technique has two levels scored on every scene. */
static int quality_charts(const struct report *r, const char *device, struct strbuf *html)
{
    struct config_mean *m = xcalloc((size_t)r->cell_count + 1, sizeof *m);
    const int n = config_means(r, false, m);
    const int lines_max = TECHNIQUE_SELECTION_MAX;
    struct chart_line *pen[2], *rmse[2];
    double *arrays = xcalloc((size_t)n * 6 + 1, sizeof *arrays);
    bool *defaults = xcalloc((size_t)n * 2 + 1, sizeof *defaults);  /* per axis, per level */
    for (int a = 0; a < 2; a++)
        pen[a] = xcalloc(lines_max, sizeof **pen), rmse[a] = xcalloc(lines_max, sizeof **rmse);
    int count = 0, used = 0;
    for (const struct technique *const *t = technique_list; *t && count < lines_max; t++) {
        if (!(*t)->presets)
            continue;
        int idx[TECHNIQUE_CELLS_PER_SCENE * 4], k = 0;
        for (int i = 0; i < n && k < (int)ARRAY_SIZE(idx); i++)
            if (m[i].first->technique == *t && m[i].complete && level_of(*t, m[i].first->label))
                idx[k++] = i;
        if (k < 2)
            continue;
        for (int a = 0; a < 2; a++) {  /* a = 0: by fetches, 1: by time */
            for (int i = 1; i < k; i++)  /* insertion sort by the cost */
                for (int j = i; j > 0; j--) {
                    const double x0 = a ? m[idx[j - 1]].ms : m[idx[j - 1]].fetches;
                    const double x1 = a ? m[idx[j]].ms : m[idx[j]].fetches;
                    if (x1 < x0) {
                        int tmp = idx[j];
                        idx[j] = idx[j - 1], idx[j - 1] = tmp;
                    }
                }
            double *x = arrays + used, *yp = x + k, *yr = yp + k;
            bool *mark = defaults + used / 3;
            for (int i = 0; i < k; i++) {
                x[i] = a ? m[idx[i]].ms : m[idx[i]].fetches;
                yp[i] = m[idx[i]].pen, yr[i] = m[idx[i]].rmse;
                mark[i] = strcmp(m[idx[i]].first->label, (*t)->name) == 0;
            }
            used += 3 * k;
            const struct chart_item item = {(*t)->name, (*t)->name, technique_index(*t)};
            pen[a][count] = (struct chart_line){item, k, x, yp, mark};
            rmse[a][count] = (struct chart_line){item, k, x, yr, mark};
        }
        count++;
    }
    int rc = 0;
    if (count) {
        strbuf_printf(html, "<h2 id=\"quality\">Quality levels</h2>\n<p>Each line joins one technique's levels, "
                            "its defaults and its named settings (an engine's quality levels, "
                            "docs/presets.md; pcss's seed-003 steps), "
                            "in order of cost, each point a level's mean over every scene; the ringed point is "
                            "the defaults. Fetches are counted and hold on any GPU; times are this run's "
                            "device's only.</p>\n");
        for (int a = 0; a < 2; a++) {
            const struct chart_panel panels[] = {{"mean penumbra_rmse", "visibility", pen[a], count},
                                                 {"mean rmse", "visibility", rmse[a], count}};
            char *title = util_printf("All %d scenes: each level's mean error against its %s", r->scene_count,
                                      a ? "time per frame" : "counted fetches");
            char *sub = a ? chart_subtitle(device, "") : xstrdup("counted on the device: a cost that holds on any GPU");
            struct strbuf svg = {0};
            chart_lines_svg(&svg, title, sub,
                            a ? "mean ms per frame" : "shadow-map fetches per covered pixel (counted)",
                            true, NAN, "the defaults", panels, 2);
            rc |= emit_chart(r, a ? "quality_time" : "quality_fetches", &svg, html);
            free(title), free(sub);
        }
    }
    for (int a = 0; a < 2; a++)
        free(pen[a]), free(rmse[a]);
    free(arrays), free(defaults), free(m);
    return rc;
}

/* The frontiers of the tuned techniques, over every scene (scene NULL) or
 * one; nothing when there are none. */
static int frontier_chart(const struct report *r, const char *scene, const struct chart_curve *curves, int n,
                          struct strbuf *html)
{
    if (!n)
        return 0;
    char *title = util_printf("%s%sfrontier: the least error for a %s budget", scene ? scene : "",
                              scene ? ": " : "all scenes: ", r->frontier_fetches ? "fetch" : "time");
    struct strbuf svg = {0};
    char *y = util_printf("%s%s (lower is better)", scene ? "" : "mean ", r->frontier_objective);
    chart_frontier_svg(&svg, title, r->frontier_source, curves, n,
                       r->frontier_fetches ? "shadow-map fetches per covered pixel (counted, log scale)"
                                           : "ms per frame (median, log scale; bar: quartiles)",
                       y);
    free(y);
    char *name = scene ? util_printf("%s_frontier", scene) : xstrdup("frontier");
    int rc = emit_chart(r, name, &svg, html);
    free(name), free(title);
    return rc;
}

/* ---- report.html -------------------------------------------------------- */

const char report_style[] =
    "body{font:14px/1.45 system-ui,sans-serif;margin:1.5em 2em;color:#222;max-width:1400px}\n"
    "h2{margin-top:1.8em;border-bottom:1px solid #ccc}\n"
    "table{border-collapse:collapse;font-size:12.5px}td,th{border:1px solid #ccc;padding:2px 6px;"
    "text-align:right;white-space:nowrap}th{background:#eee;cursor:pointer;user-select:none}"
    "th.asc::after{content:' \\25B2'}th.desc::after{content:' \\25BC'}td.l{text-align:left}"
    "td.p{text-align:left;font-size:11px;color:#555}.scroll{overflow-x:auto}\n"
    "p.warn{background:#fdd;padding:4px 8px}tr.fail td,tr.unscored td{background:#fdd}"
    "tr.front td.c{font-weight:bold}td.none{color:#a00}\n"
    ".grid{display:flex;flex-wrap:wrap;gap:10px}.grid figure{margin:0;width:220px}"
    ".grid img{display:block;width:220px;image-rendering:pixelated}"
    ".grid figure>img,.crop{outline:1px solid #bbb;margin-bottom:4px}"
    ".crop{overflow:hidden}figcaption{font-size:12px}\n"
    "img.missing{outline:3px solid red;min-height:40px}\n"
    ".chart svg{max-width:100%;height:auto}figure.chart{margin:8px 0}\n"
    "pre{background:#f6f6f6;padding:8px;overflow:auto}\n";

/* Sorts the matrix by a clicked column (again: descending) and shows only
 * the rows of the scene and technique chosen; in the address, #sort=KEY (or
 * -KEY), &scene=S and &technique=T do the same on opening. */
static const char script[] =
    "(function(){\n"
    "const t=document.getElementById('matrix'),b=t.tBodies[0],hs=[...t.tHead.rows[0].cells];\n"
    "function sort(k,desc){const i=hs.findIndex(h=>h.dataset.k===k);if(i<0)return;\n"
    " const rows=[...b.rows],num=rows.every(r=>r.cells[i].dataset.v!==undefined);\n"
    " rows.sort((x,y)=>{const a=x.cells[i],c=y.cells[i];\n"
    "  const d=num?parseFloat(a.dataset.v)-parseFloat(c.dataset.v):a.textContent.localeCompare(c.textContent);\n"
    "  return desc?-d:d;});\n"
    " rows.forEach(r=>b.appendChild(r));hs.forEach(h=>h.classList.remove('asc','desc'));\n"
    " hs[i].classList.add(desc?'desc':'asc');t.dataset.sortedBy=(desc?'-':'')+k;}\n"
    "hs.forEach(h=>h.addEventListener('click',()=>sort(h.dataset.k,h.classList.contains('asc'))));\n"
    "const q=new URLSearchParams(location.hash.slice(1)),m=(q.get('sort')||'').match(/^(-?)([a-z_]+)$/);\n"
    "if(m)sort(m[2],m[1]==='-');\n"
    "const fs=document.getElementById('filter-scene'),ft=document.getElementById('filter-technique');\n"
    "function pick(sel,v){if(!v)return;\n"  /* a value no cell has stays asked for: no rows, said */
    " if(![...sel.options].some(o=>o.value===v))sel.add(new Option(v+' (no such cells)',v));sel.value=v;}\n"
    "pick(fs,q.get('scene'));pick(ft,q.get('technique'));\n"
    "function filter(){let n=0;for(const r of b.rows){\n"
    " const show=(!fs.value||r.dataset.scene===fs.value)&&(!ft.value||r.dataset.technique===ft.value);\n"
    " r.hidden=!show;n+=show;}\n"
    " document.getElementById('filter-count').textContent=n+' of '+b.rows.length+' cells';}\n"
    "fs.addEventListener('change',filter);ft.addEventListener('change',filter);filter();\n"
    "})();\n";

/* A path segment or fragment of a URL: anything but unreserved characters
 * and @ = , + percent-encoded (a scene file may be named anything). */
void report_url(struct strbuf *h, const char *s)
{
    for (; *s; s++) {
        unsigned char ch = (unsigned char)*s;
        if ((ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') ||
            strchr("-._~@=,+", ch))
            strbuf_append(h, s, 1);
        else
            strbuf_printf(h, "%%%02X", ch);
    }
}

/* id="scene-NAME" of a scene's section, and its link */
static void scene_anchor(struct strbuf *h, const char *scene)
{
    strbuf_printf(h, "scene-");
    report_url(h, scene);
}

/* <img src="SCENE[/CELL]/FILE"> that marks itself when it does not load */
static void picture(struct strbuf *h, const char *scene, const char *cell, const char *file,
                    const char *alt)
{
    strbuf_printf(h, "<img src=\"");
    report_url(h, scene);
    if (cell) {
        strbuf_printf(h, "/");
        report_url(h, cell);
    }
    strbuf_printf(h, "/%s\" alt=\"%s\" onerror=\"this.classList.add('missing')\">", file, alt);
}

/* front[i]: cell i is on its scene's Pareto front of rmse against ms_total. */
static void pareto_flags(const struct report *r, bool *front)
{
    int *index = xmalloc(sizeof(int) * (size_t)r->cell_count), *on = xmalloc(sizeof(int) * (size_t)r->cell_count);
    double *x = xmalloc(sizeof(double) * (size_t)r->cell_count), *y = xmalloc(sizeof(double) * (size_t)r->cell_count);
    for (int s = 0; s < r->scene_count; s++) {
        int n = 0;
        for (int i = 0; i < r->cell_count; i++)
            if (strcmp(r->cells[i].scene, r->scenes[s].name) == 0 && metrics_scored(&r->cells[i].m) &&
                !technique_is_engine(r->cells[i].technique)) {  /* timed on the run's device */
                index[n] = i, x[n] = r->cells[i].m.ms_total, y[n] = r->cells[i].m.rmse;
                n++;
            }
        int m = frontier_pareto(x, y, n, on);
        for (int k = 0; k < m; k++)
            front[index[on[k]]] = true;
    }
    free(index), free(on), free(x), free(y);
}

static void matrix_table(const struct report *r, struct strbuf *h)
{
    bool *front = xcalloc((size_t)r->cell_count, sizeof *front);
    pareto_flags(r, front);
    strbuf_printf(h, "<p>Show <select id=\"filter-scene\"><option value=\"\">every scene</option>");
    for (int s = 0; s < r->scene_count; s++) {
        strbuf_printf(h, "<option>");
        strbuf_xml(h, r->scenes[s].name);
        strbuf_printf(h, "</option>");
    }
    strbuf_printf(h, "</select> <select id=\"filter-technique\"><option value=\"\">every technique</option>");
    for (int i = 0; i < r->cell_count; i++) {  /* each technique once, in run order */
        int j = 0;
        while (j < i && r->cells[j].technique != r->cells[i].technique)
            j++;
        if (j == i)
            strbuf_printf(h, "<option>%s</option>", r->cells[i].technique->name);
    }
    strbuf_printf(h, "</select> <span id=\"filter-count\"></span></p>\n");
    strbuf_printf(h, "<div class=\"scroll\"><table id=\"matrix\"><thead><tr>"
                     "<th data-k=\"scene\">scene</th><th data-k=\"cell\">cell</th>");
    for (int k = 0; k < METRIC_COUNT; k++)
        if (metric_info[k].in_report) {
            strbuf_printf(h, "<th data-k=\"%s\" title=\"", metric_info[k].key);
            strbuf_xml(h, metric_info[k].help);
            strbuf_printf(h, "\">%s</th>", metric_info[k].key);
        }
    strbuf_printf(h, "<th data-k=\"params\">params</th></tr></thead>\n<tbody>\n");
    for (int i = 0; i < r->cell_count; i++) {
        const struct cell *c = &r->cells[i];
        strbuf_printf(h, "<tr class=\"%s%s%s\" data-scene=\"", c->m.nonfinite ? "fail" : "",
                      front[i] ? " front" : "", metrics_scored(&c->m) ? "" : " unscored");
        strbuf_xml(h, c->scene);
        strbuf_printf(h, "\" data-technique=\"%s\"><td class=\"l\">", c->technique->name);
        strbuf_xml(h, c->scene);
        strbuf_printf(h, "</td><td class=\"l c\"><a href=\"#");
        scene_anchor(h, c->scene);
        strbuf_printf(h, "\">");
        strbuf_xml(h, c->label);
        strbuf_printf(h, "</a></td>");
        for (int k = 0; k < METRIC_COUNT; k++) {
            if (!metric_info[k].in_report)
                continue;
            double v = metrics_value(&c->m, k);
            if (isnan(v)) {  /* nothing to score; sorts last */
                strbuf_printf(h, "<td data-v=\"Infinity\" class=\"none\">unscored</td>");
                continue;
            }
            strbuf_printf(h, "<td data-v=\"%.9g\">", v);
            strbuf_printf(h, metric_info[k].format, v);
            strbuf_printf(h, "</td>");
        }
        strbuf_printf(h, "<td class=\"p\">");
        strbuf_xml(h, c->params_text);
        strbuf_printf(h, "</td></tr>\n");
    }
    strbuf_printf(h, "</tbody></table></div>\n");
    free(front);
}

/* One legend for every heatmap of the report (they share one scale). */
static void heatmap_legend(struct strbuf *h, int id)
{
    strbuf_printf(h, "<svg width=\"220\" height=\"58\" font-size=\"11\" font-family=\"sans-serif\">"
                     "<defs><linearGradient id=\"diverging%d\">", id);
    for (int k = 0; k <= 10; k++) {
        uint8_t c[3];
        picture_diverging(-1.0f + 0.2f * (float)k, c);
        strbuf_printf(h, "<stop offset=\"%d%%\" stop-color=\"rgb(%d,%d,%d)\"/>", 10 * k, c[0], c[1], c[2]);
    }
    strbuf_printf(h, "</linearGradient></defs><rect x=\"10\" y=\"4\" width=\"200\" height=\"12\" "
                     "fill=\"url(#diverging%d)\"/>"
                     "<text x=\"10\" y=\"29\">-%.2g too dark</text><text x=\"110\" y=\"29\" "
                     "text-anchor=\"middle\">0</text><text x=\"210\" y=\"29\" text-anchor=\"end\">"
                     "+%.2g too bright</text><text x=\"10\" y=\"46\">e = V_tech &#8722; V_gt; grey: "
                     "not scored</text></svg>", id, (double)PICTURE_ERROR_SCALE, (double)PICTURE_ERROR_SCALE);
}

/* A cell's visibility, and its heatmap without its own legend strip (the
 * page shows one legend for all: they share a scale). */
static void cell_pictures(const struct report *r, const struct cell *c, struct strbuf *h)
{
    picture(h, c->scene, c->label, cell_files[CELL_VISIBILITY_PNG], "visibility");
    strbuf_printf(h, "<div class=\"crop\" style=\"aspect-ratio:%d/%d\">", r->width, r->height);
    picture(h, c->scene, c->label, cell_files[CELL_HEATMAP_PNG], "error heatmap");
    strbuf_printf(h, "</div>");
}

static void scene_grid(const struct report *r, const struct report_scene *sc, struct strbuf *h)
{
    strbuf_printf(h, "<div class=\"grid\">\n<figure>");
    picture(h, sc->name, NULL, cell_files[CELL_GROUNDTRUTH_PNG], "ground truth");
    strbuf_printf(h, "<figcaption>ground truth V<sub>gt</sub> (%s; hatched: not scored)</figcaption>",
                  sc->gt_cached ? "from the cache" : "ray traced for this run");
    heatmap_legend(h, (int)(sc - r->scenes));  /* each gradient needs an id of its own */
    strbuf_printf(h, "</figure>\n");
    for (int i = 0; i < r->cell_count; i++) {
        const struct cell *c = &r->cells[i];
        if (strcmp(c->scene, sc->name) != 0)
            continue;
        strbuf_printf(h, "<figure>");
        cell_pictures(r, c, h);
        strbuf_printf(h, "<figcaption><b>");
        strbuf_xml(h, c->label);
        if (metrics_scored(&c->m)) {
            char pen[16] = "&mdash;";  /* no penumbra band in this scene */
            if (isfinite(c->m.penumbra_rmse))
                snprintf(pen, sizeof pen, "%.4f", c->m.penumbra_rmse);
            strbuf_printf(h, "</b><br>rmse %.4f, penumbra %s<br>shaded %.4f, leak %.4f, dark %.4f"
                             "<br>%.2f ms (%.2f&ndash;%.2f)</figcaption></figure>\n", c->m.rmse, pen,
                          c->m.shaded_rmse, c->m.leak_fraction, c->m.dark_fraction, c->m.ms_total, c->m.ms_total_q1,
                          c->m.ms_total_q3);
        }
        else
            strbuf_printf(h, "</b><br>unscored: no pixel to score<br>%.2f ms</figcaption></figure>\n",
                          c->m.ms_total);
    }
    strbuf_printf(h, "</div>\n");
}

/* ---- the summary: what a reader takes in first ------------------------- */

/* A configuration the budget table can rank: scored on every scene, with
 * a finite mean time and a mean penumbra_rmse (no scene with a penumbra
 * band: none). */
static bool ranked(const struct config_mean *m) { return m->complete && isfinite(m->ms) && isfinite(m->pen); }

/* For each budget of a 1-2-5 series (ms per frame) from the fastest
 * configuration's mean time to the slowest's, the configuration with the
 * least mean penumbra_rmse among those within it; a row where the answer
 * changes. */
static void budget_table(const struct report *r, const char *device, struct strbuf *h)
{
    struct config_mean *m = xcalloc((size_t)r->cell_count + 1, sizeof *m);
    const int n = config_means(r, false, m);
    double lo = INFINITY, hi = 0;
    int left_out = 0;
    for (int k = 0; k < n; k++)
        if (ranked(&m[k]))
            lo = fmin(lo, m[k].ms), hi = fmax(hi, m[k].ms);
        else
            left_out++;
    strbuf_printf(h, "<table id=\"budgets\"><thead><tr><th>time budget per frame</th><th>least wrong</th>"
                     "<th>mean penumbra_rmse</th><th>mean rmse</th><th>mean ms_total (quartiles)</th>"
                     "</tr></thead><tbody>\n");
    int last = -1;
    for (double decade = pow(10, floor(log10(lo > 0 && isfinite(lo) ? lo : 1))); isfinite(lo) && decade <= 10 * hi;
         decade *= 10)
        for (int step = 0; step < 3; step++) {
            const double budget = decade * (double[]){1, 2, 5}[step];
            int best = -1;
            for (int k = 0; k < n; k++)
                if (ranked(&m[k]) && m[k].ms <= budget && (best < 0 || m[k].pen < m[best].pen))
                    best = k;
            if (best < 0 || best == last)
                continue;
            last = best;
            strbuf_printf(h, "<tr><td class=\"l\">&le; %g ms</td><td class=\"l\"><b>", budget);
            strbuf_xml(h, m[best].first->label);
            strbuf_printf(h, "</b></td><td>%.4f</td><td>%.4f</td><td>%.2f (%.2f&ndash;%.2f)</td></tr>\n", m[best].pen,
                          m[best].rmse, m[best].ms, m[best].q1, m[best].q3);
        }
    strbuf_printf(h, "</tbody></table>\n<p>Means over the %d scene(s) (penumbra_rmse over those with a penumbra "
                     "band); times on ", r->scene_count);
    strbuf_xml(h, device ? device : "an unknown device");
    strbuf_printf(h, "%s.", device && strstr(device, "llvmpipe") ? ", which rank techniques for this device only "
                                                                   "(fetches, not llvmpipe's milliseconds, carry "
                                                                   "to a GPU)"
                                                                 : "");
    if (left_out)
        strbuf_printf(h, " %d configuration(s) with an unscored or non-finite cell are left out (see the matrix).",
                      left_out);
    strbuf_printf(h, "</p>\n");
    free(m);
}

/* "What each shortcut buys": each technique's presets (seed 003's steps
 * for pcss) in their order, their mean cost and error over the scenes. */
static void shortcut_table(const struct report *r, struct strbuf *h)
{
    struct config_mean *m = xcalloc((size_t)r->cell_count + 1, sizeof *m);
    const int n = config_means(r, false, m);
    bool any = false;
    for (int k = 0; k < n; k++) {
        const struct cell *c = m[k].first;
        const char *at = strchr(c->label, '@');
        if (!at || !technique_preset_find(c->technique, at + 1))
            continue;
        if (!any)
            strbuf_printf(h, "<h2 id=\"shortcuts\">What each shortcut buys</h2>\n<p>The presets, in their "
                             "order (for <code>pcss</code>, seed 003's steps from a 7 &times; 7 grid to its "
                             "shipped pipeline), as means over the %d scene(s). Fetches are counted on the device "
                             "and carry to a GPU; the milliseconds are this device's.</p>\n<table id=\"shortcuts-table\">"
                             "<thead><tr><th>cell</th><th>what</th><th>mean ms_total</th><th>fetches_per_pixel</th>"
                             "<th>mean penumbra_rmse</th><th>mean rmse</th><th>expensive_fraction</th>"
                             "<th>misclassified_fraction</th></tr></thead><tbody>\n",
                          r->scene_count);
        any = true;
        strbuf_printf(h, "<tr><td class=\"l\">");
        strbuf_xml(h, c->label);
        strbuf_printf(h, "</td><td class=\"l\">");
        strbuf_xml(h, technique_preset_find(c->technique, at + 1)->summary);
        strbuf_printf(h, "</td><td>%.2f</td><td>%.1f</td><td>%.4f</td><td>%.4f</td><td>%.3f</td><td>", m[k].ms,
                      m[k].fetches, m[k].pen, m[k].rmse, m[k].expensive);
        if (isfinite(m[k].misclassified))
            strbuf_printf(h, "%.4f", m[k].misclassified);
        else
            strbuf_printf(h, "&mdash;");
        strbuf_printf(h, "</td></tr>\n");
    }
    if (any)
        strbuf_printf(h, "</tbody></table>\n");
    free(m);
}

/* The WORST_SHOWN cells with the largest value of a failure metric (above
 * 0), each its visibility and heatmap. */
#define WORST_SHOWN 3
static void worst_cells(const struct report *r, int metric, const char *what, struct strbuf *h)
{
    int shown[WORST_SHOWN], n = 0;
    for (; n < WORST_SHOWN; n++) {
        int best = -1;
        for (int i = 0; i < r->cell_count; i++) {
            const double v = metrics_value(&r->cells[i].m, metric);
            bool taken = false;
            for (int j = 0; j < n; j++)
                taken |= shown[j] == i;
            if (!taken && isfinite(v) && v > 0 && (best < 0 || v > metrics_value(&r->cells[best].m, metric)))
                best = i;
        }
        if (best < 0)
            break;
        shown[n] = best;
    }
    strbuf_printf(h, "<h3>Largest %s (%s)</h3>\n", metric_info[metric].key, what);
    if (!n) {
        strbuf_printf(h, "<p>None: no cell has a pixel of it.</p>\n");
        return;
    }
    strbuf_printf(h, "<div class=\"grid\">\n");
    for (int j = 0; j < n; j++) {
        const struct cell *c = &r->cells[shown[j]];
        strbuf_printf(h, "<figure class=\"failure\">");
        cell_pictures(r, c, h);
        strbuf_printf(h, "<figcaption><a href=\"#");
        scene_anchor(h, c->scene);
        strbuf_printf(h, "\">");
        strbuf_xml(h, c->scene);
        strbuf_printf(h, "</a> <b>");
        strbuf_xml(h, c->label);
        strbuf_printf(h, "</b><br>%s ", metric_info[metric].key);
        strbuf_printf(h, metric_info[metric].format, metrics_value(&c->m, metric));
        strbuf_printf(h, ", rmse %.4f</figcaption></figure>\n", c->m.rmse);
    }
    strbuf_printf(h, "</div>\n");
}

/* The cells that failed outright: non-finite output, or nothing scored. */
static void failed_cells(const struct report *r, struct strbuf *h)
{
    int n = 0;
    for (int i = 0; i < r->cell_count; i++)
        n += r->cells[i].m.nonfinite || !metrics_scored(&r->cells[i].m);
    if (!n)
        return;
    strbuf_printf(h, "<p class=\"warn\"><b>%d cell(s) failed</b> (NaN/Inf output, no pixel to score, or an "
                     "engine that failed: the matrix says why):", n);
    for (int i = 0; i < r->cell_count; i++)
        if (r->cells[i].m.nonfinite || !metrics_scored(&r->cells[i].m)) {
            strbuf_printf(h, " ");
            strbuf_xml(h, r->cells[i].scene);
            strbuf_printf(h, "/");
            strbuf_xml(h, r->cells[i].label);
        }
    strbuf_printf(h, ".</p>\n");
}

void report_html_end(struct strbuf *h, const char *heading, const cJSON *run, const char *script)
{
    char *env = cJSON_Print(run);
    strbuf_printf(h, "<h2 id=\"environment\">");
    strbuf_xml(h, heading);
    strbuf_printf(h, "</h2>\n<pre>");
    strbuf_xml(h, env);
    strbuf_printf(h, "</pre>\n<script>\n%s</script>\n</body></html>\n", script);
    cJSON_free(env);
}

/* The device the times come from, as run.json names it: "<GL_RENDERER>
 * (<GL_VENDOR>, <platform>), <timing method>"; NULL if unnamed. */
static char *timed_device(const cJSON *run)
{
    const char *renderer = cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_renderer"));
    const char *vendor = cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_vendor"));
    const char *platform = cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_platform"));
    const char *method = cJSON_GetStringValue(cJSON_GetObjectItem(run, "timing_method"));
    if (!renderer)
        return NULL;
    return util_printf("%s (%s, %s), %s", renderer, vendor ? vendor : "vendor unknown",
                       platform ? platform : "platform unknown", method ? method : "timing method unknown");
}

static int write_html(const struct report *r)
{
    char *device = timed_device(r->run);
    struct strbuf h = {0};
    strbuf_printf(&h, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
                      "<title>shadowbench report</title>\n<style>\n%s</style></head><body>\n"
                      "<h1>shadowbench report</h1>\n<p>%d scene(s) &times; %d technique configuration(s) "
                      "at %d&times;%d. The error is <i>e</i> = V<sub>tech</sub> &minus; V<sub>gt</sub> over "
                      "the scored pixels, V<sub>gt</sub> the ray-traced fraction of the area light above "
                      "each point's horizon that no other geometry hides (shadowing, not N&middot;L). "
                      "Times are medians per frame in milliseconds, the cells of a scene timed "
                      "interleaved, with their quartiles, on <b>",
                  report_style, r->scene_count, r->scene_count ? r->cell_count / r->scene_count : 0,
                  r->width, r->height);
    strbuf_xml(&h, device ? device : "unknown");
    strbuf_printf(&h, "</b>%s. Scenes:",
                  device && strstr(device, "llvmpipe")
                      ? ", a CPU rasteriser: there a full-map pass (a blur, mipmaps, a summed-area "
                        "table) costs far more against a texture fetch than on a GPU, so these times "
                        "rank techniques for this device only"
                      : "");
    for (int s = 0; s < r->scene_count; s++) {
        strbuf_printf(&h, " <a href=\"#");
        scene_anchor(&h, r->scenes[s].name);
        strbuf_printf(&h, "\">");
        strbuf_xml(&h, r->scenes[s].name);
        strbuf_printf(&h, "</a>");
    }
    strbuf_printf(&h, ". The full matrix follows the scenes (<a href=\"#matrix-title\">matrix</a>).</p>\n"
                      "<h2 id=\"summary\">Summary: for a time budget, the least wrong</h2>\n");
    failed_cells(r, &h);
    budget_table(r, device, &h);
    int rc = overall_chart(r, device, false, &h) || overall_chart(r, device, true, &h);
    shortcut_table(r, &h);
    rc = rc || quality_charts(r, device, &h);
    strbuf_printf(&h, "<h2 id=\"worst\">Worst failures</h2>\n<p>Heatmaps share one scale: blue too dark, red "
                      "too bright, grey not scored.</p>\n");
    heatmap_legend(&h, -1);
    worst_cells(r, METRIC_leak_fraction, "light through a true umbra", &h);
    worst_cells(r, METRIC_dark_fraction, "acne, over-darkening of lit surfaces", &h);
    if (r->frontier_count) {
        strbuf_printf(&h, "<h2 id=\"frontier\">Frontier: for a time budget, the least error</h2>\n<p>Each "
                          "technique's line joins the settings that <code>shadowbench tune</code> tried where "
                          "no other of its settings is both faster and better. The ring is its defaults, "
                          "the star its tuned setting: on each scene, the setting chosen on the other "
                          "scenes, scored on that scene. Measured by the tuning, not by this run: ");
        strbuf_xml(&h, r->frontier_source);
        strbuf_printf(&h, ".</p>\n");
        rc |= frontier_chart(r, NULL, r->frontier, r->frontier_count, &h);
    }
    for (int s = 0; s < r->scene_count; s++) {
        const struct report_scene *sc = &r->scenes[s];
        strbuf_printf(&h, "<h2 id=\"");
        scene_anchor(&h, sc->name);
        strbuf_printf(&h, "\">Scene ");
        strbuf_xml(&h, sc->name);
        strbuf_printf(&h, "</h2>\n<p>");
        text_capped(&h, sc->description);
        if (*sc->shows) {
            strbuf_printf(&h, " <b>Shows:</b> ");
            text_capped(&h, sc->shows);
        }
        strbuf_printf(&h, "</p>\n");
        scene_grid(r, sc, &h);
        rc |= scene_charts(r, sc->name, device, &h);
        rc |= frontier_chart(r, sc->name, sc->frontier, sc->frontier_count, &h);
    }
    strbuf_printf(&h, "<h2 id=\"matrix-title\">Matrix</h2>\n<p>Every cell. Click a column to sort it "
                      "(again: descending); choose a scene or a technique to show only its rows. Bold cells "
                      "are on their scene's Pareto front of rmse against ms_total. A red row is a failed "
                      "cell: NaN/Inf output, or <i>unscored</i> (no pixel to score: its metrics are null, not "
                      "0).</p>\n");
    matrix_table(r, &h);
    /* Stability (motion, sensitivity) is its own page: linked where it lies
     * beside this one in the default layout (results/runs/latest and
     * results/stability/latest). */
    char *stability = util_printf("%s/../../stability/latest/stability.html", r->out_dir);
    strbuf_printf(&h, "<h2 id=\"stability\">Stability</h2>\n<p>Flicker under motion and where each technique "
                      "breaks as the map, the light or a parameter varies: <code>shadowbench stability</code>%s</p>\n",
                  util_file_exists(stability)
                      ? ", whose last page is <a href=\"../../stability/latest/stability.html\">stability.html</a>."
                      : " writes its own page (results/stability/latest/stability.html by default).");
    free(stability);
    report_html_end(&h, "Environment (run.json)", r->run, script);

    char *path = util_printf("%s/report.html", r->out_dir);
    rc |= util_write_file_atomic(path, h.data, h.len);
    free(path);
    free(device);
    strbuf_free(&h);
    return rc ? -1 : 0;
}

int report_write(const struct report *r)
{
    char *run_path = util_printf("%s/run.json", r->out_dir), *charts = util_printf("%s/charts", r->out_dir);
    /* run.json last: it says "complete" only when the rest is written. */
    int rc = util_mkdirs_own(charts, 1) || write_matrix(r) || write_html(r) || report_write_json(run_path, r->run);
    free(run_path), free(charts);
    return rc ? -1 : 0;
}
