#include "chart.h"
#include "score/frontier.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A series' style, by technique index: Okabe & Ito's colour-blind-safe
 * palette (8 colours), with a dash for each round of it (solid, dashed,
 * dotted, dash-dot, sparse dots) and a marker that changes with the
 * index, so the first CHART_DISTINCT_STYLES techniques differ in colour or
 * dash, and techniques a palette apart (pcf and vssm) also in their
 * marker. */
static const char *const palette[] = {"#0072B2", "#E69F00", "#009E73", "#CC79A7",
                                      "#56B4E9", "#D55E00", "#000000", "#F0E442"};
static const char *const dashes[] = {"none", "7 3", "2 2", "8 2 2 2", "1 4"};
static const char *const marker_names[] = {"circle", "square", "triangle", "diamond", "cross"};
#define COUNT(a) (int)(sizeof (a) / sizeof (a)[0])
static const char font[] = "font-family=\"sans-serif\"";

struct chart_style chart_style(int group)
{
    const int g = group < 0 ? 0 : group, rounds = g / COUNT(palette);
    return (struct chart_style){palette[g % COUNT(palette)], dashes[rounds % COUNT(dashes)],
                                marker_names[g % COUNT(marker_names)], g % COUNT(marker_names)};
}

static const char *colour(int group) { return chart_style(group).colour; }

/* Opens the group's marker at (x, y), radius r, filled with fill (NULL:
 * its colour), outlined in stroke, of SVG class class_name; the element is
 * left open for a <title>, closed by marker_end. */
static void marker_begin(struct strbuf *o, int group, double x, double y, double r, const char *fill,
                         const char *stroke, const char *class_name)
{
    const struct chart_style st = chart_style(group);
    fill = fill ? fill : st.colour;
    strbuf_printf(o, "<path class=\"%s\" data-marker=\"%s\" d=\"", class_name, st.marker_name);
    switch (st.marker) {
    case 0:  /* circle, as two arcs */
        strbuf_printf(o, "M%.1f %.1f a%.1f %.1f 0 1 0 %.1f 0 a%.1f %.1f 0 1 0 %.1f 0Z", x - r, y, r, r, 2 * r, r,
                      r, -2 * r);
        break;
    case 1:
        r *= 0.9;
        strbuf_printf(o, "M%.1f %.1f h%.1f v%.1f h%.1f Z", x - r, y - r, 2 * r, 2 * r, -2 * r);
        break;
    case 2:
        r *= 1.15;
        strbuf_printf(o, "M%.1f %.1f L%.1f %.1f L%.1f %.1f Z", x, y - r, x + 0.87 * r, y + 0.5 * r, x - 0.87 * r,
                      y + 0.5 * r);
        break;
    case 3:
        r *= 1.2;
        strbuf_printf(o, "M%.1f %.1f L%.1f %.1f L%.1f %.1f L%.1f %.1f Z", x, y - r, x + r, y, x, y + r, x - r, y);
        break;
    default: {  /* a plus of bars r/2.5 wide */
        const double t = r / 2.5;
        strbuf_printf(o, "M%.1f %.1f h%.1f v%.1f h%.1f v%.1f h%.1f v%.1f h%.1f v%.1f h%.1f v%.1f h%.1f Z", x - t,
                      y - r, 2 * t, r - t, r - t, 2 * t, t - r, r - t, -2 * t, t - r, t - r, -2 * t, r - t);
    }
    }
    strbuf_printf(o, "\" fill=\"%s\" stroke=\"%s\">", fill, stroke);
}

static void marker_end(struct strbuf *o) { strbuf_printf(o, "</path>\n"); }

/* One legend entry at (x, y): the group's line sample (its dash) and
 * marker, then its name; the entry carries the style it shows, so a test
 * can tell that no two entries of a chart share one. Returns the next x. */
static int legend_entry(struct strbuf *o, int group, const char *name, int x, int y)
{
    const struct chart_style st = chart_style(group);
    strbuf_printf(o, "<g class=\"legend-entry\" data-style=\"%s %s %s\"><line x1=\"%d\" x2=\"%d\" y1=\"%d\" "
                     "y2=\"%d\" stroke=\"%s\" stroke-width=\"2\" stroke-dasharray=\"%s\"/>",
                  st.colour, st.dash, st.marker_name, x, x + 22, y - 4, y - 4, st.colour, st.dash);
    marker_begin(o, group, x + 11, y - 4, 4.5, NULL, "white", "legend-marker");
    marker_end(o);
    strbuf_printf(o, "<text x=\"%d\" y=\"%d\">", x + 27, y);
    strbuf_xml(o, name);
    strbuf_printf(o, "</text></g>\n");
    return x + 40 + 7 * (int)strlen(name);
}

/* 0 for what cannot be drawn (NaN, Inf, negative). */
static double drawable(double v) { return isfinite(v) && v > 0 ? v : 0; }

/* A round tick step giving about five ticks up to max, and the axis end. */
static double nice_axis(double max, double *step)
{
    if (!(max > 0) || !isfinite(max) || max > 1e30)  /* an axis it can tick */
        max = 1;
    double raw = max / 5, mag = pow(10, floor(log10(raw))), f = raw / mag;
    *step = (f <= 1 ? 1 : f <= 2 ? 2 : f <= 5 ? 5 : 10) * mag;
    return ceil(max / *step - 1e-9) * *step;
}

static void begin(struct strbuf *o, int w, int h, const char *title, const char *subtitle)
{
    strbuf_printf(o, "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" "
                     "viewBox=\"0 0 %d %d\" %s font-size=\"12\">\n"
                     "<rect width=\"%d\" height=\"%d\" fill=\"white\"/>\n",
                  w, h, w, h, font, w, h);
    strbuf_printf(o, "<text x=\"%d\" y=\"20\" text-anchor=\"middle\" font-size=\"15\" "
                     "font-weight=\"bold\">", w / 2);
    strbuf_xml(o, title);
    strbuf_printf(o, "</text>\n<text x=\"%d\" y=\"38\" text-anchor=\"middle\" fill=\"#555\">", w / 2);
    strbuf_xml(o, subtitle);
    strbuf_printf(o, "</text>\n");
}

/* A legend row of the techniques present, at y. */
static void legend(struct strbuf *o, const struct chart_item *items, int n, int x, int y)
{
    bool seen[64] = {false};
    for (int i = 0; i < n; i++) {
        int g = items[i].group;
        if (g < 0 || g >= 64 || seen[g])
            continue;
        seen[g] = true;
        x = legend_entry(o, g, items[i].group_name, x, y);
    }
}

/* A panel's bold title, centred over the plot from x0 to x0 + w. */
static void panel_title(struct strbuf *o, int x0, int w, int y, const char *name, const char *suffix)
{
    strbuf_printf(o, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\" font-weight=\"bold\">",
                  x0 + w / 2, y);
    strbuf_xml(o, name);
    strbuf_printf(o, "%s</text>\n", suffix);
}

/* A plot frame at (x0, y0) of size w x h with y ticks to y_max; the x axis
 * is drawn by the caller (ticks or category labels). */
static void y_axis(struct strbuf *o, int x0, int y0, int w, int h, double y_max, double y_step,
                   const char *y_label)
{
    for (double v = 0; v <= y_max + 1e-12; v += y_step) {
        double y = y0 + h - v / y_max * h;
        strbuf_printf(o, "<line x1=\"%d\" x2=\"%d\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#e4e4e4\"/>"
                         "<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%g</text>\n",
                      x0, x0 + w, y, y, x0 - 5, y + 4, v);
    }
    strbuf_printf(o, "<text transform=\"translate(%d %d) rotate(-90)\" text-anchor=\"middle\">",
                  x0 - 48, y0 + h / 2);
    strbuf_xml(o, y_label);
    strbuf_printf(o, "</text>\n<path d=\"M%d %d V%d H%d\" fill=\"none\" stroke=\"#333\"/>\n", x0, y0,
                  y0 + h, x0 + w);
}

enum { PANEL_W = 470, PANEL_H = 380, PAD_L = 70, PAD_R = 24, PAD_T = 30, PAD_B = 50, TOP = 50 };

static void tradeoff_panel(struct strbuf *o, int left, const struct chart_item *all_items, int all_n,
                           const struct chart_series *time, const struct chart_series *err)
{
    const int x0 = left + PAD_L, y0 = TOP + PAD_T, w = PANEL_W - PAD_L - PAD_R,
              h = PANEL_H - PAD_T - PAD_B;
    /* The items with both coordinates, compacted; i indexes them, src[i] the caller's. */
    int *src = xmalloc(sizeof(int) * (size_t)(all_n ? all_n : 1)), n = 0;
    double *x = xmalloc(sizeof(double) * (size_t)(all_n ? all_n : 1)),
           *y = xmalloc(sizeof(double) * (size_t)(all_n ? all_n : 1));
    double x_max = 0, y_max = 0, x_step, y_step;
    for (int k = 0; k < all_n; k++) {
        if (!isfinite(time->values[k]) || !isfinite(err->values[k]))
            continue;
        src[n] = k, x[n] = drawable(time->values[k]), y[n] = drawable(err->values[k]);
        x_max = fmax(x_max, time->hi ? drawable(time->hi[k]) : x[n]), y_max = fmax(y_max, y[n]);
        n++;
    }
    x_max = nice_axis(x_max, &x_step);
    y_max = nice_axis(y_max, &y_step);

    /* a cost without a spread is counted (fetches), not timed */
    panel_title(o, x0, w, TOP + 16, err->name, time->lo ? " against time" : " against its counted cost");
    char y_label[128], x_label[160];
    snprintf(y_label, sizeof y_label, "%s (%s, lower is better)", err->name, err->unit);
    if (time->lo)
        snprintf(x_label, sizeof x_label, "%s (%s per frame, median; bar: quartiles)", time->name, time->unit);
    else
        snprintf(x_label, sizeof x_label, "%s (%s)", time->name, time->unit);
    y_axis(o, x0, y0, w, h, y_max, y_step, y_label);
    for (double v = 0; v <= x_max + 1e-12; v += x_step) {
        double px = x0 + v / x_max * w;
        strbuf_printf(o, "<line x1=\"%.1f\" x2=\"%.1f\" y1=\"%d\" y2=\"%d\" stroke=\"#333\"/>"
                         "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>\n",
                      px, px, y0 + h, y0 + h + 5, px, y0 + h + 18, v);
    }
    strbuf_printf(o, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">", x0 + w / 2, y0 + h + 38);
    strbuf_xml(o, x_label);
    strbuf_printf(o, "</text>\n");

#define SX(v) (x0 + (v) / x_max * w)
#define PX(i) SX(x[i])
#define PY(i) (y0 + h - y[i] / y_max * h)
    int *front = xmalloc(sizeof(int) * (size_t)(n ? n : 1));
    int m = frontier_pareto(x, y, n, front);
    strbuf_printf(o, "<path class=\"pareto\" d=\"");
    for (int k = 0; k < m; k++)
        strbuf_printf(o, k ? " H%.1f V%.1f" : "M%.1f %.1f", PX(front[k]), PY(front[k]));
    strbuf_printf(o, "\" fill=\"none\" stroke=\"#888\" stroke-width=\"1.5\" stroke-dasharray=\"5 3\"/>\n");
    for (int i = 0; i < n; i++) {
        const int k = src[i];
        const char *c = colour(all_items[k].group);
        if (time->lo && time->hi)  /* the time's spread: q1 to q3, with end caps */
            strbuf_printf(o, "<path class=\"spread\" d=\"M%.1f %.1f H%.1f M%.1f %.1f V%.1f M%.1f %.1f "
                             "V%.1f\" stroke=\"%s\" stroke-width=\"1.5\"/>\n",
                          SX(drawable(time->lo[k])), PY(i), SX(drawable(time->hi[k])),
                          SX(drawable(time->lo[k])), PY(i) - 4, PY(i) + 4, SX(drawable(time->hi[k])),
                          PY(i) - 4, PY(i) + 4, c);
        marker_begin(o, all_items[k].group, PX(i), PY(i), 5, NULL, "white", "point");
        strbuf_printf(o, "<title>");
        strbuf_xml(o, all_items[k].label);
        strbuf_printf(o, ": %s %.4g, %.3g %s", err->name, err->values[k], time->values[k], time->unit);
        if (time->lo && time->hi)
            strbuf_printf(o, " (quartiles %.3g-%.3g)", time->lo[k], time->hi[k]);
        strbuf_printf(o, "</title>");
        marker_end(o);
    }
    for (int j = 0; j < m; j++) {  /* name the front, alternately above and below */
        int i = front[j];
        strbuf_printf(o, "<text class=\"front-label\" x=\"%.1f\" y=\"%.1f\" font-size=\"11\">",
                      PX(i) + 7, PY(i) + (j % 2 ? 14 : -7));
        strbuf_xml(o, all_items[src[i]].label);
        strbuf_printf(o, "</text>\n");
    }
#undef SX
#undef PX
#undef PY
    free(front), free(x), free(y), free(src);
}

void chart_tradeoff_svg(struct strbuf *out, const char *title, const char *subtitle,
                        const struct chart_item *items, int n, const struct chart_series *time,
                        const struct chart_series *errors, int error_count)
{
    const int width = PANEL_W * error_count, height = TOP + PANEL_H + 30;
    begin(out, width, height, title, subtitle);
    for (int k = 0; k < error_count; k++)
        tradeoff_panel(out, k * PANEL_W, items, n, time, &errors[k]);
    legend(out, items, n, 20, height - 12);
    strbuf_printf(out, "<text x=\"%d\" y=\"%d\" text-anchor=\"end\" fill=\"#555\">dashed: Pareto "
                       "front (named)</text>\n</svg>\n", width - 10, height - 12);
}

enum { BAR_W = 470, BAR_PLOT_H = 190 };

void chart_bars_svg(struct strbuf *out, const char *title, const char *subtitle,
                    const struct chart_item *items, int n, const struct chart_series *series,
                    int series_count)
{
    /* Room under each plot for the longest label, written at -40 degrees
     * (about 6 px a character at 11 px). */
    size_t longest = 0;
    for (int i = 0; i < n; i++)
        longest = strlen(items[i].label) > longest ? strlen(items[i].label) : longest;
    const int pad_b = 24 + (int)(6.0 * sin(40 * M_PI / 180) * (double)longest);
    const int panel_h = PAD_T + BAR_PLOT_H + pad_b, rows = (series_count + 1) / 2;
    const int width = 2 * BAR_W, height = TOP + rows * panel_h + 30;
    begin(out, width, height, title, subtitle);
    for (int k = 0; k < series_count; k++) {
        const struct chart_series *s = &series[k];
        const int x0 = (k % 2) * BAR_W + PAD_L, y0 = TOP + (k / 2) * panel_h + PAD_T,
                  w = BAR_W - PAD_L - PAD_R, h = BAR_PLOT_H;
        const bool has_floor = s->floor_name && isfinite(s->floor) && s->floor > 0;
        double max = has_floor ? s->floor : 0, step;  /* the floor stays on the axis */
        for (int i = 0; i < n; i++)
            max = fmax(max, drawable(s->values[i]));
        max = nice_axis(max, &step);
        panel_title(out, x0, w, y0 - 12, s->name, "");
        char label[128];
        snprintf(label, sizeof label, "%s (%s)", s->name, s->unit);
        y_axis(out, x0, y0, w, h, max, step, label);
        const double slot = (double)w / n, bw = fmin(0.7 * slot, 40);
        for (int i = 0; i < n; i++) {
            double v = drawable(s->values[i]), bh = v / max * h, cx = x0 + (i + 0.5) * slot;
            if (isnan(s->values[i]))  /* no value (unscored, or no pixel of its kind): said, never a bar of 0 */
                strbuf_printf(out, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\" font-size=\"10\" "
                                   "fill=\"#a00\">none</text>\n", cx, y0 + h - 3);
            strbuf_printf(out, "<rect class=\"bar\" x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" "
                               "fill=\"%s\"><title>", cx - bw / 2, y0 + h - bh, bw, bh,
                          colour(items[i].group));
            strbuf_xml(out, items[i].label);
            if (isnan(s->values[i]))
                strbuf_printf(out, ": no %s (unscored, or no pixel it measures)</title></rect>\n", s->name);
            else
                strbuf_printf(out, ": %s %.4g</title></rect>\n", s->name, s->values[i]);
            if (!isnan(s->values[i])) {  /* its technique's marker at the bar's foot: colours repeat */
                marker_begin(out, items[i].group, cx, y0 + h - 6, 3.5, "white", colour(items[i].group), "bar-marker");
                marker_end(out);
            }
            if (slot >= 48 && !isnan(s->values[i]))  /* values over the bars while they fit */
                strbuf_printf(out, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\" "
                                   "font-size=\"10\">%.3g</text>\n", cx, y0 + h - bh - 3, s->values[i]);
            strbuf_printf(out, "<text transform=\"translate(%.1f %d) rotate(-40)\" "
                               "text-anchor=\"end\" font-size=\"11\">", cx + 3, y0 + h + 12);
            strbuf_xml(out, items[i].label);
            strbuf_printf(out, "</text>\n");
        }
        if (has_floor) {
            const double fy = y0 + h - s->floor / max * h;
            strbuf_printf(out, "<line class=\"floor\" x1=\"%d\" x2=\"%d\" y1=\"%.1f\" y2=\"%.1f\" stroke=\"#a00\" "
                               "stroke-dasharray=\"5 3\"/><text x=\"%d\" y=\"%.1f\" text-anchor=\"end\" "
                               "font-size=\"10\" fill=\"#a00\">", x0, x0 + w, fy, fy, x0 + w, fy - 3);
            strbuf_xml(out, s->floor_name);
            strbuf_printf(out, " %.3g</text>\n", s->floor);
        }
    }
    legend(out, items, n, 20, height - 12);
    strbuf_printf(out, "</svg>\n");
}

enum { LINE_W = 470, LINE_PLOT_H = 220, LINE_PAD_B = 56 };

void chart_lines_svg(struct strbuf *out, const char *title, const char *subtitle, const char *x_label, bool log_x,
                     double reference_x, const char *marked_text, const struct chart_panel *panels,
                     int panel_count)
{
    double x_lo = INFINITY, x_hi = -INFINITY;
    for (int k = 0; k < panel_count; k++)
        for (int c = 0; c < panels[k].n; c++)
            for (int i = 0; i < panels[k].lines[c].n; i++) {
                const double x = panels[k].lines[c].x[i];
                if (isfinite(x) && (!log_x || x > 0))
                    x_lo = fmin(x_lo, x), x_hi = fmax(x_hi, x);
            }
    if (!(x_hi > x_lo))  /* one value (or none): an axis around it */
        x_lo = isfinite(x_lo) ? (log_x ? x_lo / 2 : x_lo - 1) : (log_x ? 1 : 0),
        x_hi = isfinite(x_hi) ? (log_x ? x_hi * 2 : x_hi + 1) : (log_x ? 10 : 1);
    const double a = log_x ? log10(x_lo) : x_lo, b = log_x ? log10(x_hi) : x_hi;
    const int panel_h = PAD_T + LINE_PLOT_H + LINE_PAD_B, rows = (panel_count + 1) / 2;
    const int width = 2 * LINE_W, height = TOP + rows * panel_h + 30;
    begin(out, width, height, title, subtitle);
    for (int k = 0; k < panel_count; k++) {
        const struct chart_panel *p = &panels[k];
        const int x0 = (k % 2) * LINE_W + PAD_L, y0 = TOP + (k / 2) * panel_h + PAD_T,
                  w = LINE_W - PAD_L - PAD_R, h = LINE_PLOT_H;
        double y_max = 0, y_step;
        for (int c = 0; c < p->n; c++)
            for (int i = 0; i < p->lines[c].n; i++)
                y_max = fmax(y_max, drawable(p->lines[c].y[i]));
        y_max = nice_axis(y_max, &y_step);
        panel_title(out, x0, w, y0 - 12, p->name, "");
        char label[128];
        snprintf(label, sizeof label, "%s (%s)", p->name, p->unit);
        y_axis(out, x0, y0, w, h, y_max, y_step, label);
#define LX(v) (x0 + ((log_x ? log10(v) : (v)) - a) / (b - a) * w)
#define LY(v) (y0 + h - fmin(drawable(v), y_max) / y_max * h)
        /* x ticks: the values the lines have (the varied values) when they
         * share them; else, on a log axis, 1, 2 and 5 times the powers of
         * ten in range */
        const struct chart_line *first = p->n ? &p->lines[0] : NULL;
        bool shared = true;
        for (int c = 1; c < p->n && shared; c++) {
            shared = p->lines[c].n == first->n;
            for (int i = 0; i < first->n && shared; i++)
                shared = p->lines[c].x[i] == first->x[i];
        }
        double ticks[64];
        int tick_count = 0;
        for (int i = 0; first && shared && i < first->n && tick_count < 64; i++)
            if (isfinite(first->x[i]) && (!log_x || first->x[i] > 0))
                ticks[tick_count++] = first->x[i];
        for (double e = floor(a); !shared && log_x && e <= b && tick_count < 60; e++)
            for (int k = 0; k < 3; k++) {
                const double v = (k == 0 ? 1 : k == 1 ? 2 : 5) * pow(10, e);
                if (v >= x_lo && v <= x_hi)
                    ticks[tick_count++] = v;
            }
        for (int i = 0; i < tick_count; i++)
            strbuf_printf(out, "<line x1=\"%.1f\" x2=\"%.1f\" y1=\"%d\" y2=\"%d\" stroke=\"#333\"/>"
                               "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>\n",
                          LX(ticks[i]), LX(ticks[i]), y0 + h, y0 + h + 5, LX(ticks[i]), y0 + h + 18, ticks[i]);
        strbuf_printf(out, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">", x0 + w / 2, y0 + h + 38);
        strbuf_xml(out, x_label);
        strbuf_printf(out, "%s</text>\n", log_x ? " (log scale)" : "");
        if (isfinite(reference_x) && (!log_x || reference_x > 0))
            strbuf_printf(out, "<line class=\"reference\" x1=\"%.1f\" x2=\"%.1f\" y1=\"%d\" y2=\"%d\" "
                               "stroke=\"#777\" stroke-dasharray=\"4 3\"/>\n",
                          LX(reference_x), LX(reference_x), y0, y0 + h);
        for (int c = 0; c < p->n; c++) {
            const struct chart_line *l = &p->lines[c];
            const char *col = colour(l->item.group);
            strbuf_printf(out, "<path class=\"line\" d=\"");
            bool pen = false;
            for (int i = 0; i < l->n; i++) {
                if (!isfinite(l->y[i]) || !isfinite(l->x[i]) || (log_x && !(l->x[i] > 0))) {
                    pen = false;
                    continue;
                }
                strbuf_printf(out, "%s%.1f %.1f ", pen ? "L" : "M", LX(l->x[i]), LY(l->y[i]));
                pen = true;
            }
            strbuf_printf(out, "\" fill=\"none\" stroke=\"%s\" stroke-width=\"2\" stroke-dasharray=\"%s\"/>\n",
                          col, chart_style(l->item.group).dash);
            for (int i = 0; i < l->n; i++) {
                if (!isfinite(l->y[i]) || !isfinite(l->x[i]) || (log_x && !(l->x[i] > 0)))
                    continue;
                const bool ring = l->marked && l->marked[i];
                if (ring)
                    strbuf_printf(out, "<circle class=\"marked\" cx=\"%.1f\" cy=\"%.1f\" r=\"8\" fill=\"none\" "
                                       "stroke=\"%s\" stroke-width=\"2\"/>", LX(l->x[i]), LY(l->y[i]), col);
                marker_begin(out, l->item.group, LX(l->x[i]), LY(l->y[i]), 4, ring ? "white" : NULL, col, "point");
                strbuf_printf(out, "<title>");
                strbuf_xml(out, l->item.label);
                strbuf_printf(out, " at %g: %s %.4g%s%s</title>", l->x[i], p->name, l->y[i], ring ? ", " : "",
                              ring ? marked_text : "");
                marker_end(out);
            }
        }
#undef LX
#undef LY
    }
    int lx = 20;
    const struct chart_panel *p0 = panel_count ? &panels[0] : NULL;
    for (int c = 0; p0 && c < p0->n; c++)
        lx = legend_entry(out, p0->lines[c].item.group, p0->lines[c].item.label, lx, height - 12);
    if (marked_text) {
        strbuf_printf(out, "<text x=\"%d\" y=\"%d\" text-anchor=\"end\" fill=\"#555\">ringed: ", width - 10,
                      height - 12);
        strbuf_xml(out, marked_text);
        strbuf_printf(out, "%s</text>\n", isfinite(reference_x) ? "; dashed: the reference value" : "");
    }
    strbuf_printf(out, "</svg>\n");
}

enum { FRONT_W = 900, FRONT_H = 550, FRONT_L = 80, FRONT_R = 30, FRONT_T = 60, FRONT_B = 100 };

void chart_frontier_svg(struct strbuf *out, const char *title, const char *subtitle,
                        const struct chart_curve *curves, int n, const char *x_label, const char *y_label)
{
    const int x0 = FRONT_L, y0 = FRONT_T, w = FRONT_W - FRONT_L - FRONT_R, h = FRONT_H - FRONT_T - FRONT_B;
    double x_min = INFINITY, x_max = 0, y_max = 0, y_step;
    for (int c = 0; c < n; c++) {
        const struct chart_curve *k = &curves[c];
        for (int i = 0; i < k->n; i++) {
            x_min = fmin(x_min, k->lo ? k->lo[i] : k->x[i]), x_max = fmax(x_max, k->hi ? k->hi[i] : k->x[i]);
            y_max = fmax(y_max, k->y[i]);
        }
        const double px[] = {k->default_x, k->tuned_x}, py[] = {k->default_y, k->tuned_y};
        for (int i = 0; i < 2; i++)
            if (isfinite(px[i]) && px[i] > 0 && isfinite(py[i]))
                x_min = fmin(x_min, px[i]), x_max = fmax(x_max, px[i]), y_max = fmax(y_max, py[i]);
    }
    if (!(x_min > 0) || !(x_max >= x_min))
        x_min = 1, x_max = 10;
    /* Decades from below x_min to above x_max. */
    const double lx0 = floor(log10(x_min)), lx1 = fmax(ceil(log10(x_max)), lx0 + 1);
    y_max = nice_axis(y_max, &y_step);
    begin(out, FRONT_W, FRONT_H, title, subtitle);
    y_axis(out, x0, y0, w, h, y_max, y_step, y_label);
#define FX(v) (x0 + (log10(v) - lx0) / (lx1 - lx0) * w)
#define FY(v) (y0 + h - (v) / y_max * h)
    for (double d = lx0; d <= lx1 + 1e-9; d++)
        for (int m = 1; m < 10; m++) {
            const double v = pow(10, d) * m;
            if (log10(v) > lx1 + 1e-9)
                break;
            const bool label = m == 1 || m == 2 || m == 5;
            strbuf_printf(out, "<line x1=\"%.1f\" x2=\"%.1f\" y1=\"%d\" y2=\"%d\" stroke=\"%s\"/>",
                          FX(v), FX(v), y0 + h, label ? y0 + h + 5 : y0 + h + 3, "#333");
            if (label)
                strbuf_printf(out, "<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%g</text>", FX(v),
                              y0 + h + 18, v);
            strbuf_printf(out, "\n");
        }
    strbuf_printf(out, "<text x=\"%d\" y=\"%d\" text-anchor=\"middle\">", x0 + w / 2, y0 + h + 38);
    strbuf_xml(out, x_label);
    strbuf_printf(out, "</text>\n");
    for (int c = 0; c < n; c++) {
        const struct chart_curve *k = &curves[c];
        const char *col = colour(k->item.group);
        strbuf_printf(out, "<path class=\"frontier\" d=\"");
        for (int i = 0; i < k->n; i++)
            strbuf_printf(out, i ? " H%.1f V%.1f" : "M%.1f %.1f", FX(k->x[i]), FY(k->y[i]));
        strbuf_printf(out, "\" fill=\"none\" stroke=\"%s\" stroke-width=\"2\" stroke-dasharray=\"%s\"/>\n", col,
                      chart_style(k->item.group).dash);
        for (int i = 0; i < k->n; i++) {
            if (k->lo && k->hi)
                strbuf_printf(out, "<path class=\"spread\" d=\"M%.1f %.1f H%.1f\" stroke=\"%s\" "
                                   "stroke-width=\"1\"/>", FX(k->lo[i]), FY(k->y[i]), FX(k->hi[i]), col);
            marker_begin(out, k->item.group, FX(k->x[i]), FY(k->y[i]), 3.5, NULL, col, "point");
            strbuf_printf(out, "<title>");
            strbuf_xml(out, k->item.label);
            strbuf_printf(out, ": %.4g at %.3g ms</title>", k->y[i], k->x[i]);
            marker_end(out);
        }
        if (isfinite(k->default_x) && k->default_x > 0 && isfinite(k->default_y)) {  /* a ring, larger than any marker and hollow */
            strbuf_printf(out, "<circle class=\"default\" cx=\"%.1f\" cy=\"%.1f\" r=\"8\" fill=\"none\" "
                               "stroke=\"%s\" stroke-width=\"2\"><title>", FX(k->default_x), FY(k->default_y), col);
            strbuf_xml(out, k->item.label);
            strbuf_printf(out, " at its defaults: %.4g at %.3g ms</title></circle>\n", k->default_y, k->default_x);
        }
        if (isfinite(k->tuned_x) && k->tuned_x > 0 && isfinite(k->tuned_y)) {  /* a five-point star */
            const double cx = FX(k->tuned_x), cy = FY(k->tuned_y);
            strbuf_printf(out, "<path class=\"tuned\" d=\"");
            for (int p = 0; p < 10; p++) {
                const double r = p % 2 ? 4 : 10, a = M_PI * p / 5;
                strbuf_printf(out, "%c%.1f %.1f ", p ? 'L' : 'M', cx + r * sin(a), cy - r * cos(a));
            }
            strbuf_printf(out, "Z\" fill=\"%s\" stroke=\"black\"><title>", col);
            strbuf_xml(out, k->item.label);
            strbuf_printf(out, " tuned: %.4g at %.3g ms</title></path>\n", k->tuned_y, k->tuned_x);
        }
    }
#undef FX
#undef FY
    int lx = 20;
    for (int c = 0; c < n; c++)
        lx = legend_entry(out, curves[c].item.group, curves[c].item.label, lx, FRONT_H - 35);
    strbuf_printf(out, "<text x=\"%d\" y=\"%d\" text-anchor=\"end\" fill=\"#555\">line: frontier (no "
                       "setting tried is faster and better); &#9711; defaults; &#9733; tuned</text>\n</svg>\n",
                  FRONT_W - 10, FRONT_H - 12);
}
