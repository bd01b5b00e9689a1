/* SVG charts for the report: error against time with its Pareto front, and
 * bars of several metrics per technique configuration. Every chart has a
 * title, a subtitle (the device the timings come from), labelled axes with
 * units and a legend; styles (colour, dash, marker) follow the technique, so a
 * technique looks the same in every chart. */
#ifndef SB_CHART_H
#define SB_CHART_H

#include "base/util.h"

#include <stdbool.h>

/* How a technique's series is drawn in every chart: colour, line dash
 * (SVG stroke-dasharray, "none": solid) and marker. The first
 * CHART_DISTINCT_STYLES techniques each get a style no other has. */
struct chart_style {
    const char *colour, *dash, *marker_name;
    int marker;  /* 0 circle, 1 square, 2 triangle, 3 diamond, 4 cross */
};
#define CHART_DISTINCT_STYLES 40
struct chart_style chart_style(int group);

/* One point or bar: a technique configuration. */
struct chart_item {
    const char *label;       /* the configuration, e.g. "pcss@blocker_samples=16" */
    const char *group_name;  /* its technique, named in the legend */
    int group;               /* its technique's index in technique_list: its colour */
};

/* One axis quantity of a scatter panel, or one bar panel. */
struct chart_series {
    const char *name;      /* e.g. "rmse" */
    const char *unit;      /* e.g. "visibility", "ms", "share of scored pixels" */
    const double *values;  /* one per item; NAN: nothing to show (unscored) */
    const double *lo, *hi; /* the spread behind each value (may be NULL): drawn as an error
                              bar along the time axis */
    const char *floor_name;  /* bars: a dashed line across the panel at floor, so named (NULL:
                                none), e.g. the ground truth's own noise */
    double floor;
};

/* Scatter panels side by side, one per error series, each against the same
 * cost series (x): a time, each item's point with its spread, or without a
 * spread (lo NULL) a counted cost (fetches per pixel); the Pareto front (no
 * other item both cheaper and more accurate) drawn as a staircase and its
 * items named. Items with a NAN
 * coordinate are left out. */
void chart_tradeoff_svg(struct strbuf *out, const char *title, const char *subtitle,
                        const struct chart_item *items, int n, const struct chart_series *time,
                        const struct chart_series *errors, int error_count);

/* Bar panels in a grid of two columns, one per series, a bar per item; a
 * NAN value (unscored, or no pixel the metric measures) is written "none"
 * instead of a bar. */
void chart_bars_svg(struct strbuf *out, const char *title, const char *subtitle,
                    const struct chart_item *items, int n, const struct chart_series *series,
                    int series_count);

/* One technique's frontier: its Pareto front over its own settings (points
 * in increasing time, with the time's quartiles), and two marked points. */
struct chart_curve {
    struct chart_item item;       /* label: the technique */
    int n;
    const double *x, *y, *lo, *hi;
    double default_x, default_y;  /* its defaults (NAN: none) */
    double tuned_x, tuned_y;      /* its tuned setting (NAN: none) */
};

/* Error (y, linear from 0) against time (x, logarithmic: times span
 * decades): each curve a staircase through its points, each point with its
 * time's quartiles, the default a ring and the tuned setting a
 * filled star (shapes no marker has). */
void chart_frontier_svg(struct strbuf *out, const char *title, const char *subtitle,
                        const struct chart_curve *curves, int n, const char *x_label, const char *y_label);

/* One line of a line chart: a technique's metric against a varied value. */
struct chart_line {
    struct chart_item item;  /* label: the technique */
    int n;
    const double *x, *y;     /* in increasing x; a NAN y: no point there (unscored) */
    const bool *marked;      /* may be NULL: points drawn with a ring (e.g. "broken") */
};

/* One panel of a line chart: a metric. */
struct chart_panel {
    const char *name, *unit;
    const struct chart_line *lines;
    int n;
};

/* Panels in a grid of two columns sharing one x axis (logarithmic with
 * log_x: values that span decades), each a line per technique through its
 * points, marked points ringed (what the ring means: marked_text, NULL:
 * no note, for charts without marks or reference), a dashed vertical line
 * at reference_x (NAN: none). */
void chart_lines_svg(struct strbuf *out, const char *title, const char *subtitle, const char *x_label, bool log_x,
                     double reference_x, const char *marked_text, const struct chart_panel *panels,
                     int panel_count);

#endif
