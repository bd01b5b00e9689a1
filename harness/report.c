#include "report.h"
#include "util.h"

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
    cJSON *m = metrics_json(&c->m);
    for (cJSON *it = m->child; it; it = it->next)
        cJSON_AddNumberToObject(o, it->string, it->valuedouble);
    cJSON_Delete(m);
    cJSON_AddStringToObject(o, "gl_renderer", c->gl_renderer);
    return o;
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

static void csv_field(struct strbuf *sb, const char *s)
{
    strbuf_append(sb, "\"", 1);
    for (; *s; s++)
        strbuf_append(sb, *s == '"' ? "\"\"" : s, *s == '"' ? 2 : 1);
    strbuf_append(sb, "\"", 1);
}

static int write_matrix(const struct report *r)
{
    /* The metric columns are metrics_json()'s keys, in its order: one list. */
    struct strbuf csv = {0};
    strbuf_printf(&csv, "scene,technique,params");
    cJSON *names = metrics_json(&(struct metrics){0});
    for (const cJSON *it = names->child; it; it = it->next)
        strbuf_printf(&csv, ",%s", it->string);
    strbuf_printf(&csv, ",gl_renderer,cell\n");
    cJSON *matrix = cJSON_CreateObject();
    cJSON *cells = cJSON_AddArrayToObject(matrix, "cells");
    for (int i = 0; i < r->cell_count; i++) {
        cJSON *row = report_cell_json(&r->cells[i]);
        csv_field(&csv, r->cells[i].scene);
        strbuf_printf(&csv, ",");
        csv_field(&csv, r->cells[i].technique->name);
        strbuf_printf(&csv, ",");
        csv_field(&csv, r->cells[i].params_text);
        for (const cJSON *it = names->child; it; it = it->next)
            strbuf_printf(&csv, ",%.9g", cJSON_GetObjectItem(row, it->string)->valuedouble);
        strbuf_printf(&csv, ",");
        csv_field(&csv, r->cells[i].gl_renderer);
        strbuf_printf(&csv, ",");
        csv_field(&csv, r->cells[i].label);
        strbuf_printf(&csv, "\n");
        cJSON_AddItemToArray(cells, row);
    }
    cJSON_Delete(names);
    char *csv_path = util_printf("%s/matrix.csv", r->out_dir);
    char *json_path = util_printf("%s/matrix.json", r->out_dir);
    int rc = util_write_file_atomic(csv_path, csv.data, csv.len) ||
             report_write_json(json_path, matrix);
    free(csv_path);
    free(json_path);
    cJSON_Delete(matrix);
    strbuf_free(&csv);
    return rc ? -1 : 0;
}

static void html_text(struct strbuf *sb, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '<': strbuf_printf(sb, "&lt;"); break;
        case '>': strbuf_printf(sb, "&gt;"); break;
        case '&': strbuf_printf(sb, "&amp;"); break;
        case '"': strbuf_printf(sb, "&quot;"); break;
        default: strbuf_append(sb, s, 1);
        }
    }
}

static int write_html(const struct report *r)
{
    struct strbuf h = {0};
    strbuf_printf(&h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
        "<title>shadowbench report</title>\n<style>\n"
        "body{font:14px/1.4 system-ui,sans-serif;margin:2em;color:#222}\n"
        "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:3px 8px;"
        "text-align:right}th{background:#eee}td.l{text-align:left}\n"
        "tr.fail td{background:#fdd}figure{display:inline-block;vertical-align:top;margin:0 12px 12px 0}"
        "figure img{display:block;image-rendering:pixelated;width:256px}"
        "figcaption{font-size:12px;max-width:256px}\n"
        "pre{background:#f6f6f6;padding:8px;overflow:auto}\n</style></head><body>\n"
        "<h1>shadowbench report</h1>\n"
        "<p>Error is <i>e</i> = V<sub>tech</sub> &minus; V<sub>gt</sub> over the scored pixels; "
        "V<sub>gt</sub> is the ray-traced fraction of the area light each point sees. "
        "Times are medians per frame in milliseconds on the renderer named below.</p>\n"
        "<h2>Matrix</h2>\n<table id=\"matrix\"><tr><th>scene</th><th>technique</th>"
        "<th>params</th><th>rmse</th><th>penumbra_rmse</th><th>mae</th><th>bias</th>"
        "<th>p99_abs</th><th>leak_fraction</th><th>dark_fraction</th><th>nonfinite</th>"
        "<th>ms_total</th><th>gt noise rmse</th></tr>\n");
    for (int i = 0; i < r->cell_count; i++) {
        const struct cell *c = &r->cells[i];
        strbuf_printf(&h, "<tr%s><td class=\"l\">", c->m.nonfinite ? " class=\"fail\"" : "");
        html_text(&h, c->scene);
        strbuf_printf(&h, "</td><td class=\"l\">%s</td><td class=\"l\">", c->technique->name);
        html_text(&h, c->params_text);
        strbuf_printf(&h,
                      "</td><td>%.4f</td><td>%.4f</td><td>%.4f</td><td>%+.4f</td><td>%.4f</td>"
                      "<td>%.4f</td><td>%.4f</td><td>%ld</td><td>%.2f</td><td>%.4f</td></tr>\n",
                      c->m.rmse, c->m.penumbra_rmse, c->m.mae, c->m.bias, c->m.p99_abs,
                      c->m.leak_fraction, c->m.dark_fraction, c->m.nonfinite, c->m.ms_total,
                      c->m.gt_noise_rmse);
    }
    strbuf_printf(&h, "</table>\n");

    for (int s = 0; s < r->scene_count; s++) {
        const struct report_scene *sc = &r->scenes[s];
        strbuf_printf(&h, "<h2 id=\"scene-");
        html_text(&h, sc->name);
        strbuf_printf(&h, "\">Scene ");
        html_text(&h, sc->name);
        strbuf_printf(&h, "</h2>\n<p>");
        html_text(&h, sc->description);
        if (*sc->shows) {
            strbuf_printf(&h, " <b>Shows:</b> ");
            html_text(&h, sc->shows);
        }
        strbuf_printf(&h, "</p>\n<figure><img src=\"%s/groundtruth.png\" alt=\"ground truth\">"
                          "<figcaption>ground truth V<sub>gt</sub>%s</figcaption></figure>\n",
                      sc->name, sc->gt_cached ? " (cached)" : "");
        for (int i = 0; i < r->cell_count; i++) {
            const struct cell *c = &r->cells[i];
            if (strcmp(c->scene, sc->name) != 0)
                continue;
            const char *t = c->technique->name;
            strbuf_printf(&h,
                          "<figure><img src=\"%s/%s/visibility.png\" alt=\"%s visibility\">"
                          "<figcaption>%s: V<sub>tech</sub></figcaption></figure>\n"
                          "<figure><img src=\"%s/%s/heatmap.png\" alt=\"%s error heatmap\">"
                          "<figcaption>%s: error, rmse %.4f, penumbra rmse %.4f</figcaption>"
                          "</figure>\n",
                          sc->name, t, t, t, sc->name, t, t, t, c->m.rmse, c->m.penumbra_rmse);
        }
    }
    char *env = cJSON_Print(r->run);
    strbuf_printf(&h, "<h2>Environment (run.json)</h2>\n<pre>");
    html_text(&h, env);
    strbuf_printf(&h, "</pre>\n</body></html>\n");
    cJSON_free(env);

    char *path = util_printf("%s/report.html", r->out_dir);
    int rc = util_write_file_atomic(path, h.data, h.len);
    free(path);
    strbuf_free(&h);
    return rc ? -1 : 0;
}

int report_write(const struct report *r)
{
    char *run_path = util_printf("%s/run.json", r->out_dir);
    int rc = report_write_json(run_path, r->run);
    free(run_path);
    if (rc || write_matrix(r) || write_html(r))
        return -1;
    return 0;
}
