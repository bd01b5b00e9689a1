#include "stability_page.h"
#include "chart.h"
#include "out_dir.h"
#include "report.h"
#include "base/image.h"
#include "base/util.h"
#include "score/break_rule.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

const char *const stability_frame_files[2] = {"visibility_frames.png", "error_frames.png"};
#define frame_files stability_frame_files

static void csv_number(struct strbuf *csv, double v, bool last)
{
    if (isfinite(v))
        strbuf_printf(csv, "%.6g", v);
    strbuf_printf(csv, last ? "\n" : ",");
}

static const char csv_header[] =
    "scene,technique,mode,name,value,row,noise,accumulated,frames,flicker,flicker_p99,flicker_floor,"
    "flicker_meaningful,flicker_penumbra,flicker_floor_penumbra,rmse_mean,rmse_max,rmse_jump,mask_changes,rmse,penumbra_rmse,leak_fraction,dark_fraction,"
    "nonfinite,broken\n";

static int write_data(struct stability_output *so, const cJSON *run)
{
    const struct stability *st = so->st;
    struct strbuf csv = {0};
    strbuf_printf(&csv, "%s", csv_header);
    cJSON *doc = cJSON_CreateObject();
    cJSON_AddItemToObject(doc, "run", cJSON_Duplicate(run, true));
    cJSON *motions = cJSON_AddArrayToObject(doc, "motions");
    for (int i = 0; i < st->row_count; i++) {
        const struct motion_row *r = &st->rows[i];
        const struct motion *mo = &st->motions[r->motion];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "scene", st->scenes[r->scene].name);
        cJSON_AddStringToObject(j, "technique", r->t->name);
        cJSON_AddStringToObject(j, "motion", motion_kinds[mo->kind].name);
        if (*mo->node)
            cJSON_AddStringToObject(j, "node", mo->node);
        cJSON_AddNumberToObject(j, "step", mo->step);
        cJSON_AddStringToObject(j, "step_unit", motion_kinds[mo->kind].unit);
        cJSON_AddStringToObject(j, "row", r->label);
        if (!r->accumulated) {  /* its frames: the manifest the next run here removes */
            char *folder = util_printf("%s/%s/%s", st->scenes[r->scene].name, mo->label, r->label);
            cJSON_AddStringToObject(j, "frames_folder", folder);
            free(folder);
        }
        cJSON_AddStringToObject(j, "noise", r->animated ? "animated" : "still");
        cJSON_AddBoolToObject(j, "accumulated", r->accumulated);
        cJSON_AddNumberToObject(j, "frames", r->r.frames);
        cJSON_AddNumberToObject(j, "scored_frames", r->r.scored_frames);
        util_json_add_number(j, "flicker", r->r.flicker);
        util_json_add_number(j, "flicker_p99", r->r.flicker_p99);
        util_json_add_number(j, "flicker_floor", r->r.floor);
        util_json_add_number(j, "flicker_penumbra", r->r.flicker_penumbra);
        util_json_add_number(j, "flicker_floor_penumbra", r->r.floor_penumbra);
        cJSON_AddNumberToObject(j, "band_pixels", (double)r->r.band_pixels);
        cJSON_AddBoolToObject(j, "flicker_meaningful", r->r.meaningful);
        util_json_add_number(j, "rmse_mean", r->r.rmse_mean);
        util_json_add_number(j, "rmse_max", r->r.rmse_max);
        util_json_add_number(j, "rmse_jump", r->r.rmse_jump);
        cJSON *fr = cJSON_AddArrayToObject(j, "frame_rmse");
        for (int f = 0; r->frame_rmse && f < r->r.frames; f++)
            cJSON_AddItemToArray(fr, isfinite(r->frame_rmse[f]) ? cJSON_CreateNumber(r->frame_rmse[f]) : cJSON_CreateNull());
        cJSON_AddNumberToObject(j, "pairs_pixels", (double)r->r.pairs_pixels);
        cJSON_AddNumberToObject(j, "mask_changes", (double)r->r.mask_changes);
        cJSON_AddNumberToObject(j, "nonfinite", (double)r->nonfinite);
        cJSON_AddItemToArray(motions, j);
        report_csv_field(&csv, st->scenes[r->scene].name);
        strbuf_printf(&csv, ",%s,motion,", r->t->name);
        report_csv_field(&csv, mo->name);
        strbuf_printf(&csv, ",%g,%s,%s,%s,%d,", mo->step, r->label, r->animated ? "animated" : "still",
                      r->accumulated ? "true" : "false", r->r.frames);
        csv_number(&csv, r->r.flicker, false);
        csv_number(&csv, r->r.flicker_p99, false);
        csv_number(&csv, r->r.floor, false);
        strbuf_printf(&csv, "%s,", r->r.meaningful ? "true" : "false");
        csv_number(&csv, r->r.flicker_penumbra, false);
        csv_number(&csv, r->r.floor_penumbra, false);
        csv_number(&csv, r->r.rmse_mean, false);
        csv_number(&csv, r->r.rmse_max, false);
        csv_number(&csv, r->r.rmse_jump, false);
        strbuf_printf(&csv, "%ld,,,,,%ld,\n", r->r.mask_changes, r->nonfinite);
    }
    cJSON *vars = cJSON_AddArrayToObject(doc, "variations");
    for (int i = 0; i < st->point_count; i++) {
        const struct vary_point *p = &st->points[i];
        const struct variation *v = &st->vars[p->variation];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "scene", st->scenes[p->scene].name);
        cJSON_AddStringToObject(j, "technique", p->t->name);
        cJSON_AddStringToObject(j, "variable", v->name);
        cJSON_AddStringToObject(j, "value", v->texts[p->value]);
        cJSON_AddBoolToObject(j, "reference", p->value == v->reference);
        for (int k = 0; k < METRIC_COUNT; k++)
            if (strncmp(metric_info[k].key, "ms_", 3) != 0)  /* not timed here */
                util_json_add_number(j, metric_info[k].key, metrics_value(&p->m, k));
        cJSON_AddBoolToObject(j, "broken", p->broken);
        cJSON_AddItemToArray(vars, j);
        report_csv_field(&csv, st->scenes[p->scene].name);
        strbuf_printf(&csv, ",%s,vary,", p->t->name);
        report_csv_field(&csv, v->name);
        strbuf_printf(&csv, ",");
        report_csv_field(&csv, v->texts[p->value]);
        strbuf_printf(&csv, ",%s,still,false,1,,,,,,,,,,,", p->t->name);
        csv_number(&csv, p->m.rmse, false);
        csv_number(&csv, p->m.penumbra_rmse, false);
        csv_number(&csv, p->m.leak_fraction, false);
        csv_number(&csv, p->m.dark_fraction, false);
        strbuf_printf(&csv, "%ld,%s\n", p->m.nonfinite, p->broken ? "true" : "false");
    }
    cJSON *breaks = cJSON_AddArrayToObject(doc, "break_points");
    for (int s = 0; s < st->scene_count; s++)
        for (int var = 0; var < st->var_count; var++)
            for (int i = 0; i < st->technique_count; i++) {
                const struct technique *t = st->techniques[i];
                const struct variation *v = &st->vars[var];
                if (v->kind == VARY_PARAM && t != v->t)
                    continue;
                int below, above;
                stability_break_points(st, s, var, t, &below, &above);
                cJSON *j = cJSON_CreateObject();
                cJSON_AddStringToObject(j, "scene", st->scenes[s].name);
                cJSON_AddStringToObject(j, "technique", t->name);
                cJSON_AddStringToObject(j, "variable", v->name);
                cJSON_AddStringToObject(j, "reference", v->texts[v->reference]);
                if (below >= 0)
                    cJSON_AddStringToObject(j, "breaks_at_or_below", v->texts[below]);
                else
                    cJSON_AddNullToObject(j, "breaks_at_or_below");
                if (above >= 0)
                    cJSON_AddStringToObject(j, "breaks_at_or_above", v->texts[above]);
                else
                    cJSON_AddNullToObject(j, "breaks_at_or_above");
                struct strbuf all = {0};
                stability_broken_values(st, s, var, t, &all);
                cJSON_AddStringToObject(j, "broken_values", all.data ? all.data : "");
                strbuf_free(&all);
                cJSON_AddItemToArray(breaks, j);
            }
    cJSON_AddStringToObject(doc, "break_rule", break_rule_text);
    cJSON_AddItemToObject(doc, "charts", cJSON_Duplicate(so->charts, true));
    char *json_path = out_dir_path(so->out_dir, OUTPUT_STABILITY_JSON), *csv_path = out_dir_path(so->out_dir, OUTPUT_STABILITY_CSV);
    int rc = report_write_json(json_path, doc) || util_write_file_atomic(csv_path, csv.data, csv.len);
    free(json_path), free(csv_path);
    cJSON_Delete(doc);
    strbuf_free(&csv);
    return rc ? -1 : 0;
}

/* Writes <out>/charts/<name>.svg and an <img> of it into html. */
static int chart_file(struct stability_output *so, const char *name, struct strbuf *svg, struct strbuf *html)
{
    cJSON_AddItemToArray(so->charts, cJSON_CreateString(name));
    char *path = util_printf("%s/%s/%s.svg", so->out_dir, output_files[OUTPUT_CHARTS], name);
    int rc = util_write_file_atomic(path, svg->data, svg->len);
    free(path);
    strbuf_printf(html, "<figure class=\"chart\"><img src=\"charts/");
    report_url(html, name);
    strbuf_printf(html, ".svg\" alt=\"chart\" onerror=\"this.classList.add('missing')\"><figcaption><a href=\"charts/");
    report_url(html, name);
    strbuf_printf(html, ".svg\">charts/");
    strbuf_xml(html, name);
    strbuf_printf(html, ".svg</a></figcaption></figure>\n");
    strbuf_free(svg);
    return rc ? -1 : 0;
}

/* The row labels a flicker chart shows: per frame (still and animated) and
 * the animated rows accumulated (the still ones accumulated are in the
 * table and the files). */
static bool charted(const struct motion_row *r) { return !r->accumulated || r->animated; }

/* The flicker chart of one scene (s >= 0: the motions run on it) or the
 * mean over the scenes (s < 0: the motions run on every scene), if any. */
static int flicker_chart(struct stability_output *so, int s, const char *device, struct strbuf *html)
{
    const struct stability *st = so->st;
    /* items: the charted labels of the first motion row's (the same for each) */
    struct chart_item items[STABILITY_MAX_TECHNIQUES * 4];
    const struct motion_row *first[STABILITY_MAX_TECHNIQUES * 4];
    int n = 0;
    for (int i = 0; i < st->row_count && n < STABILITY_MAX_TECHNIQUES * 4; i++) {
        const struct motion_row *r = &st->rows[i];
        if (r->scene == st->rows[0].scene && r->motion == st->rows[0].motion && charted(r)) {
            first[n] = r;
            items[n++] = (struct chart_item){r->label, r->t->name, technique_index(r->t)};
        }
    }
    struct chart_series *series = xcalloc((size_t)st->motion_count + 1, sizeof *series);
    double *values = xcalloc((size_t)(n * st->motion_count) + 1, sizeof(double));
    int shown = 0;
    for (int m = 0; m < st->motion_count; m++) {
        if (s < 0 ? st->motions[m].scene >= 0 : !motion_on(&st->motions[m], s))
            continue;
        double floor_sum = 0;
        int floor_n = 0;
        for (int k = 0; k < n; k++) {
            double sum = 0;
            int count = 0;
            for (int i = 0; i < st->row_count; i++) {
                const struct motion_row *r = &st->rows[i];
                if (r->motion == m && (s < 0 || r->scene == s) && !strcmp(r->label, first[k]->label)) {
                    sum += r->r.flicker, count++;
                    if (k == 0)
                        floor_sum += r->r.floor, floor_n++;
                }
            }
            values[shown * n + k] = count ? sum / count : NAN;
        }
        series[shown] = (struct chart_series){st->motions[m].label, "mean |Δe| per pixel and frame",
                                              values + shown * n, NULL, NULL, "ground truth's own",
                                              floor_n ? floor_sum / floor_n : NAN};
        shown++;
    }
    if (!shown) {
        free(series), free(values);
        return 0;
    }
    char *title = s < 0 ? util_printf("Flicker under motion, mean over %d scene(s)", st->scene_count)
                        : util_printf("Flicker under motion: %s", st->scenes[s].name);
    char *subtitle = util_printf("%d frames at %dx%d, %d^2 map; ~anim: noise animated per frame; +ema: "
                                 "accumulated (alpha %g); on %s", st->frames, st->width, st->height,
                                 st->shadow_map_size, st->accumulate, device);
    struct strbuf svg = {0};
    chart_bars_svg(&svg, title, subtitle, items, n, series, shown);
    char *name = s < 0 ? xstrdup("flicker") : util_printf("flicker_%s", st->scenes[s].name);
    int rc = chart_file(so, name, &svg, html);
    free(series), free(values), free(title), free(subtitle), free(name);
    return rc;
}

static int vary_chart(struct stability_output *so, int s, int var, const char *device, struct strbuf *html)
{
    const struct stability *st = so->st;
    const struct variation *v = &st->vars[var];
    static const int keys[] = {METRIC_rmse, METRIC_penumbra_rmse, METRIC_leak_fraction, METRIC_dark_fraction};
    static const char *const units[] = {"visibility", "visibility", "share of scored pixels", "share of scored pixels"};
    struct chart_line lines[4][STABILITY_MAX_TECHNIQUES];
    double *data = xcalloc((size_t)(4 * st->technique_count * v->count) + 1, sizeof(double));
    bool *marks = xcalloc((size_t)(st->technique_count * v->count) + 1, sizeof(bool));
    int n = 0;
    for (int i = 0; i < st->technique_count; i++) {
        const struct technique *t = st->techniques[i];
        if (v->kind == VARY_PARAM && t != v->t)
            continue;
        const struct vary_point *ref = stability_point(st, s, var, v->reference, t);
        for (int k = 0; k < v->count; k++) {
            const struct vary_point *p = stability_point(st, s, var, k, t);
            marks[n * v->count + k] = p && ref && break_rule_broken(&p->m, &ref->m);
            for (int q = 0; q < 4; q++)
                data[(q * st->technique_count + n) * v->count + k] = p ? metrics_value(&p->m, keys[q]) : NAN;
        }
        for (int q = 0; q < 4; q++)
            lines[q][n] = (struct chart_line){{t->name, t->name, technique_index(t)}, v->count, v->values,
                                              data + (q * st->technique_count + n) * v->count, marks + n * v->count};
        n++;
    }
    struct chart_panel panels[4];
    for (int q = 0; q < 4; q++)
        panels[q] = (struct chart_panel){metric_info[keys[q]].key, units[q], lines[q], n};
    char *title = util_printf("%s: error against %s", st->scenes[s].name, v->name);
    char *subtitle = util_printf("%dx%d, %d GT samples, %d^2 map unless varied; on %s", st->width, st->height,
                                 st->gt_samples, st->shadow_map_size, device);
    char *x_label = v->kind == VARY_PARAM && (v->p->type == PARAM_ENUM || v->p->type == PARAM_BOOL)
                        ? util_printf("%s (choice index)", v->name)
                        : xstrdup(v->name);
    struct strbuf svg = {0};
    chart_lines_svg(&svg, title, subtitle, x_label, v->log_x, v->values[v->reference],
                    "broken (the break rule, against the reference value)", panels, 4);
    char *name = util_printf("vary_%s_%s", v->name, st->scenes[s].name);
    int rc = chart_file(so, name, &svg, html);
    free(data), free(marks), free(title), free(subtitle), free(x_label), free(name);
    return rc;
}

/* Frame sliders: each moves every strip of its group to its frame. */
static const char slider_script[] =
    "document.querySelectorAll('input.frame').forEach(function(s){\n"
    " s.addEventListener('input',function(){const g=s.dataset.group,t=+s.value;\n"
    "  document.querySelectorAll('img.strip[data-group=\"'+g+'\"]').forEach(function(i){\n"
    "   i.style.marginLeft=(-t*+i.dataset.w)+'px';});\n"
    "  document.getElementById('f-'+g).textContent=t;});});\n"
    "document.querySelectorAll('button.play').forEach(function(b){let timer=null;\n"
    " b.addEventListener('click',function(){const s=document.getElementById('s-'+b.dataset.group);\n"
    "  if(timer){clearInterval(timer);timer=null;b.textContent='play';return;}\n"
    "  b.textContent='stop';timer=setInterval(function(){s.value=(+s.value+1)%(+s.max+1);\n"
    "   s.dispatchEvent(new Event('input'));},125);});});\n";

static void flicker_cell(struct strbuf *h, const struct motion_row *r)
{
    if (!isfinite(r->r.flicker))
        strbuf_printf(h, "<td class=\"none\" colspan=\"2\">unscored</td>");
    else
        strbuf_printf(h, "<td%s title=\"p99 %.4f, rmse mean %.4f, max %.4f\">%.4f%s</td><td>%.4f</td>",
                      r->r.meaningful ? "" : " class=\"floor\"", r->r.flicker_p99, r->r.rmse_mean, r->r.rmse_max,
                      r->r.flicker, r->nonfinite ? " NaN!" : "", r->r.flicker_penumbra);
}

static void motion_section(const struct stability *st, int s, struct strbuf *h, int *group)
{
    const char *name = st->scenes[s].name;
    int m0 = 0;  /* the first motion run on s: the rows' labels */
    while (m0 < st->motion_count && !motion_on(&st->motions[m0], s))
        m0++;
    if (m0 == st->motion_count) {
        strbuf_printf(h, "<p>No motion runs on this scene.</p>\n");
        return;
    }
    strbuf_printf(h, "<table><thead><tr><th rowspan=\"2\">row</th>");
    for (int m = 0; m < st->motion_count; m++) {
        if (!motion_on(&st->motions[m], s))
            continue;
        strbuf_printf(h, "<th colspan=\"2\">");
        strbuf_xml(h, st->motions[m].label);
        strbuf_printf(h, "</th>");
    }
    strbuf_printf(h, "</tr><tr>");
    for (int m = 0; m < st->motion_count; m++)
        if (motion_on(&st->motions[m], s))
            strbuf_printf(h, "<th>flicker</th><th>in the band</th>");
    strbuf_printf(h, "</tr></thead><tbody>\n");
    for (int i = 0; i < st->row_count; i++) {
        const struct motion_row *r0 = &st->rows[i];
        if (r0->scene != s || r0->motion != m0)
            continue;
        strbuf_printf(h, "<tr><td class=\"l\">%s</td>", r0->label);
        for (int m = 0; m < st->motion_count; m++)
            for (int j = 0; j < st->row_count; j++)
                if (st->rows[j].scene == s && st->rows[j].motion == m && !strcmp(st->rows[j].label, r0->label))
                    flicker_cell(h, &st->rows[j]);
        strbuf_printf(h, "</tr>\n");
    }
    strbuf_printf(h, "<tr><td class=\"l\"><i>ground truth's floor</i></td>");
    for (int m = 0; m < st->motion_count; m++)
        for (int j = 0; j < st->row_count; j++)
            if (st->rows[j].scene == s && st->rows[j].motion == m) {
                strbuf_printf(h, "<td>%.4f</td><td>%.4f</td>", st->rows[j].r.floor, st->rows[j].r.floor_penumbra);
                break;
            }
    strbuf_printf(h, "</tr></tbody></table>\n");
    for (int m = 0; m < st->motion_count; m++) {
        const struct motion *mo = &st->motions[m];
        if (!motion_on(mo, s))
            continue;
        const int g = (*group)++;
        strbuf_printf(h, "<h4>");
        strbuf_xml(h, name);
        strbuf_printf(h, ", %s</h4>\n<p class=\"frames\"><button class=\"play\" data-group=\"%d\">play</button> "
                         "frame <input type=\"range\" class=\"frame\" id=\"s-%d\" data-group=\"%d\" min=\"0\" "
                         "max=\"%d\" value=\"0\"> <span id=\"f-%d\">0</span> of 0&ndash;%d</p>\n<div class=\"grid\">",
                      mo->label, g, g, g, st->frames - 1, g, st->frames - 1);
        for (int i = 0; i < st->row_count; i++) {
            const struct motion_row *r = &st->rows[i];
            if (r->scene != s || r->motion != m || r->accumulated)
                continue;
            for (int f = 0; f < 2; f++) {
                strbuf_printf(h, "<figure><div class=\"crop\" style=\"width:%dpx\"><img class=\"strip\" "
                                 "data-group=\"%d\" data-w=\"%d\" style=\"width:%dpx\" src=\"",
                              st->width, g, st->width, st->width * st->frames);
                report_url(h, name);
                strbuf_printf(h, "/");
                report_url(h, mo->label);
                strbuf_printf(h, "/");
                report_url(h, r->label);
                strbuf_printf(h, "/%s\" alt=\"%s\" onerror=\"this.classList.add('missing')\"></div>"
                                 "<figcaption>%s: %s</figcaption></figure>", frame_files[f], frame_files[f], r->label,
                              f ? "signed error" : "V<sub>tech</sub>");
            }
        }
        strbuf_printf(h, "</div>\n");
    }
}

static int write_html(struct stability_output *so, const cJSON *run)
{
    const struct stability *st = so->st;
    const char *device = cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_renderer"));
    struct strbuf h = {0};
    strbuf_printf(&h, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
                      "<title>shadowbench stability</title>\n<style>\n%s"
                      ".crop{overflow:hidden}.crop img{max-width:none;image-rendering:pixelated}"
                      ".grid figure{width:auto}td.floor{color:#999}h4{margin:1.2em 0 .3em}</style></head><body>\n"
                      "<h1>shadowbench stability</h1>\n", report_style);
    int rc = 0, group = 0;
    if (st->motion_count) {
        strbuf_printf(&h, "<h2 id=\"motion\">Motion: flicker</h2>\n<p>Each motion runs %d frames at %d&times;%d "
                          "with a %d&sup2; shadow map, every frame ray traced anew. <b>flicker</b> is the mean over "
                          "the pixels scored in both frames of a pair, and over the pairs, of |&Delta;V<sub>tech</sub> "
                          "&minus; &Delta;V<sub>gt</sub>| = |e<sub>t</sub> &minus; e<sub>t&minus;1</sub>|: how much "
                          "a pixel's error changes from one frame to the next (a pixel scored in one frame of a pair "
                          "only is left out and counted as mask_changes). The ground truth's own frame-to-frame noise "
                          "is the <b>floor</b>: a grey flicker is not above it, so not a meaningful number. <b>In the band</b>: "
                          "the same over the pixels whose V<sub>gt</sub> is in the penumbra band (0.02&ndash;0.98) in "
                          "either frame, where edges move (most pixels are lit or umbra and never flicker). Rows: "
                          "<i>T</i> per frame with its noise still (as <code>run</code> scores it); <i>T~anim</i> "
                          "with interleaved gradient noise moved each frame (Jimenez 2014), for techniques that use "
                          "noise; <i>+ema</i> the same frames accumulated by an exponential moving average "
                          "(weight %g for the new frame, reprojected where the camera moved), as TAA would. Hover a "
                          "number for its 99th percentile and the frames' rmse. The pictures are the frames: move "
                          "the slider or press play.</p>\n",
                      st->frames, st->width, st->height, st->shadow_map_size, st->accumulate);
        rc |= flicker_chart(so, -1, device ? device : "unknown", &h);
        for (int s = 0; s < st->scene_count; s++) {
            strbuf_printf(&h, "<h3>");
            strbuf_xml(&h, st->scenes[s].name);
            strbuf_printf(&h, "</h3>\n");
            motion_section(st, s, &h, &group);
            rc |= flicker_chart(so, s, device ? device : "unknown", &h);
        }
    }
    if (st->var_count) {
        strbuf_printf(&h, "<h2 id=\"vary\">Sensitivity: where each technique breaks</h2>\n<p>Break rule: %s. A "
                          "break point is the first value, walking away from the reference value (the dashed "
                          "line), that breaks the technique; a larger or smaller value may hold again, so the last column lists every "
                          "broken value, and the charts ring them.</p>\n",
                      break_rule_text);
        for (int var = 0; var < st->var_count; var++) {
            const struct variation *v = &st->vars[var];
            for (int s = 0; s < st->scene_count; s++) {
                strbuf_printf(&h, "<h3>");
                strbuf_xml(&h, v->name);
                strbuf_printf(&h, " on ");
                strbuf_xml(&h, st->scenes[s].name);
                strbuf_printf(&h, "</h3>\n<table><thead><tr><th>technique</th><th>breaks at or below</th><th>"
                                  "reference</th><th>breaks at or above</th><th>every broken value</th></tr>"
                                  "</thead><tbody>\n");
                for (int i = 0; i < st->technique_count; i++) {
                    const struct technique *t = st->techniques[i];
                    if (v->kind == VARY_PARAM && t != v->t)
                        continue;
                    int below, above;
                    stability_break_points(st, s, var, t, &below, &above);
                    strbuf_printf(&h, "<tr><td class=\"l\">%s</td><td>", t->name);
                    strbuf_xml(&h, below >= 0 ? v->texts[below] : "holds");
                    strbuf_printf(&h, "</td><td>");
                    strbuf_xml(&h, v->texts[v->reference]);
                    strbuf_printf(&h, "</td><td>");
                    strbuf_xml(&h, above >= 0 ? v->texts[above] : "holds");
                    struct strbuf all = {0};
                    stability_broken_values(st, s, var, t, &all);
                    strbuf_printf(&h, "</td><td>");
                    strbuf_xml(&h, all.data ? all.data : "none");
                    strbuf_free(&all);
                    strbuf_printf(&h, "</td></tr>\n");
                }
                strbuf_printf(&h, "</tbody></table>\n");
                rc |= vary_chart(so, s, var, device ? device : "unknown", &h);
            }
        }
    }
    report_html_end(&h, "Environment", run, slider_script);
    char *path = out_dir_path(so->out_dir, OUTPUT_STABILITY_PAGE);
    rc |= util_write_file_atomic(path, h.data, h.len);
    free(path);
    strbuf_free(&h);
    return rc ? -1 : 0;
}

/* Whether rel, a path below out of `parts` names, is one stability
 * writes: no empty, "." or ".." part, and every folder on the way a real
 * folder (not a link that would lead out of out). */
static bool own_path(const char *out, const char *rel, int parts)
{
    char *copy = xstrdup(rel), *rest = copy, *path = xstrdup(out);
    int n = 0;
    bool ok = true;
    for (char *part = strsep(&rest, "/"); part && ok; part = strsep(&rest, "/")) {
        ok = *part && strcmp(part, ".") && strcmp(part, "..") && ++n <= parts;
        char *next = util_printf("%s/%s", path, part);
        free(path), path = next;
        struct stat sb;
        ok = ok && lstat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
    }
    free(copy), free(path);
    return ok && n == parts;
}

/* Removes what the last run into out wrote and listed in its
 * stability.json (each motion row's frames, the charts), and the folders
 * that leaves empty: nothing else, so a folder shared with `run`, or
 * holding files of the user's, keeps them. */
static void remove_last_run(const char *out)
{
    char *path = out_dir_path(out, OUTPUT_STABILITY_JSON), *text = NULL;
    size_t size;
    cJSON *doc = util_read_file(path, &text, &size) == 0 ? cJSON_Parse(text) : NULL;
    free(text), free(path);
    const cJSON *row, *chart;
    cJSON_ArrayForEach(row, cJSON_GetObjectItemCaseSensitive(doc, "motions")) {
        const char *folder = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(row, "frames_folder"));
        if (!folder || !own_path(out, folder, 3))
            continue;
        for (int f = 0; f < 2; f++) {
            char *file = util_printf("%s/%s/%s", out, folder, frame_files[f]);
            unlink(file);
            free(file);
        }
        char *dir = util_printf("%s/%s", out, folder);
        for (int up = 0; up < 3 && rmdir(dir) == 0; up++)  /* stops at the first folder not empty */
            *strrchr(dir, '/') = '\0';
        free(dir);
    }
    cJSON_ArrayForEach(chart, cJSON_GetObjectItemCaseSensitive(doc, "charts")) {
        const char *name = cJSON_GetStringValue(chart);
        if (!name || strchr(name, '/') || !own_path(out, "charts", 1))
            continue;
        char *file = util_printf("%s/charts/%s.svg", out, name);
        unlink(file);
        free(file);
    }
    cJSON_Delete(doc);
}

void stability_output_begin(struct stability_output *so, const struct stability *st, const char *out_dir)
{
    *so = (struct stability_output){.st = st, .out_dir = out_dir, .charts = cJSON_CreateArray()};
    remove_last_run(out_dir);
    for (int f = OUTPUT_STABILITY_JSON; f <= OUTPUT_STABILITY_PAGE; f++) {  /* this run's, or none */
        char *path = out_dir_path(out_dir, (enum output_file)f);
        unlink(path);
        free(path);
    }
}

static void strip_put(struct frame_strip *s, const struct picture *p, int frame, int frames)
{
    if (!s->rgb) {
        s->w = p->width, s->ph = p->height, s->frames = frames;
        s->rgb = xcalloc((size_t)s->w * (size_t)frames * (size_t)s->ph * 3, 1);
    }
    for (int y = 0; y < s->ph; y++)
        memcpy(s->rgb + ((size_t)y * (size_t)(s->w * s->frames) + (size_t)frame * s->w) * 3,
               p->rgb + (size_t)y * s->w * 3, (size_t)s->w * 3);
}

int stability_output_frame(void *user, const struct motion_row *row, int frame, int frames,
                           const struct scene_setup *ss, const float *v)
{
    struct stability_output *so = user;
    const int index = (int)(row - so->st->rows);
    if (index >= so->strip_count) {
        so->strips = xrealloc(so->strips, sizeof *so->strips * (size_t)(index + 1));
        memset(so->strips + so->strip_count, 0, sizeof *so->strips * (size_t)(index + 1 - so->strip_count));
        so->strip_count = index + 1;
    }
    struct frame_strip *strips = so->strips[index];
    struct picture pic;
    picture_visibility(v, ss->distance, ss->scored, ss->width, ss->height, &pic);
    strip_put(&strips[0], &pic, frame, frames);
    picture_free(&pic);
    picture_error_heatmap(v, ss->gt.v, ss->scored, ss->width, ss->height, &pic);
    strip_put(&strips[1], &pic, frame, frames);
    picture_free(&pic);
    return 0;
}

int stability_output_frames(struct stability_output *so)
{
    const struct stability *st = so->st;
    int rc = 0;
    for (int i = 0; i < so->strip_count; i++) {
        struct frame_strip *strips = so->strips[i];
        if (!strips[0].rgb)
            continue;
        const struct motion_row *row = &st->rows[i];
        char *dir = util_printf("%s/%s/%s/%s", so->out_dir, st->scenes[row->scene].name,
                                st->motions[row->motion].label, row->label);
        rc = rc || util_mkdirs_own(dir, 3);  /* <scene>/<motion>/<row> */
        for (int f = 0; f < 2; f++) {
            char *path = util_printf("%s/%s", dir, frame_files[f]);
            rc = rc || image_write_png(path, strips[f].w * strips[f].frames, strips[f].ph, strips[f].rgb);
            free(path);
            free(strips[f].rgb);
            strips[f] = (struct frame_strip){0};
        }
        free(dir);
    }
    return rc ? -1 : 0;
}

int stability_output_write(struct stability_output *so, const cJSON *run)
{
    char *charts = util_printf("%s/%s", so->out_dir, output_files[OUTPUT_CHARTS]);
    int rc = util_mkdirs_own(charts, 1) || write_html(so, run) || write_data(so, run);
    free(charts);
    for (int f = OUTPUT_STABILITY_JSON; rc && f <= OUTPUT_STABILITY_PAGE; f++) {  /* none, rather than a mixed set */
        char *path = out_dir_path(so->out_dir, (enum output_file)f);
        unlink(path);
        free(path);
    }
    return rc ? -1 : 0;
}

void stability_output_free(struct stability_output *so)
{
    for (int i = 0; i < so->strip_count; i++)
        free(so->strips[i][0].rgb), free(so->strips[i][1].rgb);
    free(so->strips);
    cJSON_Delete(so->charts);
    memset(so, 0, sizeof *so);
}
