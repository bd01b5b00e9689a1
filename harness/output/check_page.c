#include "check_page.h"
#include "out_dir.h"
#include "picture.h"
#include "base/image.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>

int check_page_cell(const struct regression_cell *c, const char *out, struct strbuf *html)
{
    if (!c->base.picture || !c->v || !c->compared || (c->cmp.status == BASELINE_PASS && c->cmp.moved_fraction == 0.0))
        return 0;
    const size_t count = (size_t)c->setup.width * (size_t)c->setup.height;
    float *base = xmalloc(count * sizeof *base), *shown_px = xmalloc(count * sizeof *shown_px);
    double largest = 0.0;
    for (size_t p = 0; p < count; p++) {
        base[p] = (float)c->base.picture[p] / 65535.0f;
        shown_px[p] = 1.0f;
        if (isfinite(c->v[p]))
            largest = fmax(largest, fabs((double)c->v[p] - base[p]));
    }
    static const float steps[] = {0.01f, 0.02f, 0.05f, 0.1f, 0.2f, 0.5f, 1.0f};
    float scale = 1.0f;
    for (int s = 6; s >= 0; s--)
        if (steps[s] >= largest)
            scale = steps[s];
    struct picture pic;
    picture_difference(c->v, base, shown_px, c->setup.width, c->setup.height,
                       &(struct picture_legend){scale, "darker now", "brighter now", "V_now - V_baseline"},
                       &pic);
    char *name = util_printf("%s/%s/%s.png", out, c->scene->name, c->label);
    char *dir = util_printf("%s/%s", out, c->scene->name);
    int rc = util_mkdirs_own(dir, 1) || image_write_png(name, pic.width, pic.height, pic.rgb);
    picture_free(&pic);
    free(base), free(shown_px), free(name), free(dir);
    if (rc)
        return -1;
    strbuf_printf(html, "<h2>%s: ", baseline_status_names[c->cmp.status]);
    strbuf_xml(html, c->scene->name);
    strbuf_printf(html, " / ");
    strbuf_xml(html, c->label);
    strbuf_printf(html, "</h2>\n<p>%.2f %% of pixels moved by more than %g (allowed %.2f %%).</p>\n"
                         "<table><tr><th>metric</th><th>baseline</th><th>now</th><th>difference</th>"
                         "<th>tolerance</th></tr>\n",
                  100.0 * c->cmp.moved_fraction, c->base.pixel_threshold, 100.0 * c->base.max_moved);
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const int k = baseline_guards[g].metric;
        const double b = baseline_metric(&c->base, k), v = metrics_value(&c->now, k);
        strbuf_printf(html, "<tr><td>%s</td><td>%.5f</td><td>%.5f</td><td>%+.5f</td><td>%.5f</td></tr>\n",
                      metric_info[k].key, b, v, v - b, baseline_tolerance(&c->base, k));
    }
    strbuf_printf(html, "</table>\n<p><img src=\"");
    strbuf_xml(html, c->scene->name);
    strbuf_printf(html, "/");
    strbuf_xml(html, c->label);
    strbuf_printf(html, ".png\" alt=\"V_now - V_baseline\"></p>\n");
    return 1;
}

int check_page_write_sections(const char *sections, const char *out)
{
    struct strbuf html = {0};
    strbuf_printf(&html, "<!doctype html>\n<html><head><meta charset=\"utf-8\"><title>shadowbench check</title>\n"
                         "<style>body{font:14px sans-serif;margin:2em}td,th{padding:2px 8px;text-align:left}"
                         "img{image-rendering:pixelated;width:384px}</style></head><body>\n"
                         "<h1>shadowbench check: cells that moved</h1>\n%s",
                  sections && *sections ? sections : "<p>No cell moved.</p>\n");
    strbuf_printf(&html, "</body></html>\n");
    char *path = out_dir_path(out, OUTPUT_CHECK_PAGE);
    int rc = util_write_file_atomic(path, html.data, html.len);
    free(path);
    strbuf_free(&html);
    return rc ? -1 : 0;
}
