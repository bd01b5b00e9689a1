#include "check_page.h"
#include "out_dir.h"
#include "picture.h"
#include "base/image.h"
#include "base/util.h"

#include <math.h>
#include <stdlib.h>

void check_page_section(struct strbuf *html, const struct check_section *s)
{
    strbuf_printf(html, "<h2>%s: ", baseline_status_names[s->status]);
    strbuf_xml(html, s->scene);
    strbuf_printf(html, " / ");
    strbuf_xml(html, s->label);
    strbuf_printf(html, "</h2>\n<p>%.2f %% of pixels moved by more than %g (allowed %.2f %%).</p>\n"
                        "<table><tr><th>metric</th><th>baseline</th><th>now</th><th>difference</th>"
                        "<th>tolerance</th></tr>\n",
                  100.0 * s->moved_fraction, s->pixel_threshold, 100.0 * s->max_moved);
    for (int g = 0; g < BASELINE_GUARDS; g++)
        strbuf_printf(html, "<tr><td>%s</td><td>%.5f</td><td>%.5f</td><td>%+.5f</td><td>%.5f</td></tr>\n",
                      metric_info[baseline_guards[g].metric].key, s->base[g], s->now[g], s->now[g] - s->base[g],
                      s->tolerance[g]);
    strbuf_printf(html, "</table>\n<p><img src=\"");
    strbuf_xml(html, s->scene);
    strbuf_printf(html, "/");
    strbuf_xml(html, s->label);
    strbuf_printf(html, ".png\" alt=\"V_now - V_baseline\"></p>\n");
}

bool check_section_of(const struct regression_cell *c, struct check_section *s)
{
    if (!c->base.picture || !c->v || !c->compared || (c->cmp.status == BASELINE_PASS && c->cmp.moved_fraction == 0.0))
        return false;
    *s = (struct check_section){.status = c->cmp.status, .scene = c->scene->name, .label = c->label,
                                .moved_fraction = c->cmp.moved_fraction, .pixel_threshold = c->base.pixel_threshold,
                                .max_moved = c->base.max_moved};
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const int k = baseline_guards[g].metric;
        s->base[g] = baseline_metric(&c->base, k), s->now[g] = metrics_value(&c->now, k);
        s->tolerance[g] = baseline_tolerance(&c->base, k);
    }
    return true;
}

int check_page_heatmap(const struct regression_cell *c, const char *out)
{
    struct check_section sec;
    if (!check_section_of(c, &sec))
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
    return rc ? -1 : 1;
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
