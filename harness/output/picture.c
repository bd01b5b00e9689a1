#include "picture.h"
#include "base/image.h"
#include "base/util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <stb_easy_font.h>

static const uint8_t no_geometry[3] = {52, 58, 74};
static const uint8_t not_scored[3] = {96, 96, 96};
static const uint8_t not_scored_hatch[3] = {128, 128, 128};

void picture_free(struct picture *p)
{
    free(p->rgb);
    memset(p, 0, sizeof *p);
}

static void put(struct picture *p, int x, int y, const uint8_t c[3])
{
    if (x >= 0 && y >= 0 && x < p->width && y < p->height)
        memcpy(&p->rgb[((size_t)y * p->width + x) * 3], c, 3);
}

void picture_visibility(const float *v, const float *distance, const float *scored, int width,
                        int height, struct picture *out)
{
    out->width = width;
    out->height = height;
    out->rgb = xmalloc((size_t)width * height * 3);
    for (int y = 0; y < height; y++)
        for (int x = 0; x < width; x++) {
            int i = y * width + x;
            uint8_t g = image_srgb8(v[i]);
            const uint8_t grey[3] = {g, g, g};
            const uint8_t *c = grey;
            if (distance[i] < 0.0f)
                c = no_geometry;
            else if (scored && scored[i] < 0.5f)
                c = (x + y) % 8 < 4 ? not_scored : not_scored_hatch;
            memcpy(&out->rgb[(size_t)i * 3], c, 3);
        }
}

/* ColorBrewer RdBu (11 classes), from blue (-1) through white to red (+1). */
void picture_diverging(float t, uint8_t rgb[3])
{
    static const uint8_t stops[11][3] = {
        {5, 48, 97},    {33, 102, 172}, {67, 147, 195}, {146, 197, 222}, {209, 229, 240},
        {247, 247, 247}, {253, 219, 199}, {244, 165, 130}, {214, 96, 77},  {178, 24, 43},
        {103, 0, 31},
    };
    float s = (fminf(fmaxf(t, -1.0f), 1.0f) + 1.0f) * 5.0f;  /* [0, 10] */
    int i = (int)fminf(s, 9.0f);
    float f = s - (float)i;
    for (int c = 0; c < 3; c++)
        rgb[c] = (uint8_t)lrintf((1.0f - f) * stops[i][c] + f * stops[i + 1][c]);
}

void picture_text(struct picture *p, int x, int y, int scale, const char *s, const uint8_t c[3])
{
    static char quads[64 * 1024];
    int n = stb_easy_font_print(0, 0, (char *)s, NULL, quads, sizeof quads);
    for (int q = 0; q < n; q++) {
        const float *v = (const float *)(quads + q * 4 * 16);  /* 4 vertices of 16 bytes */
        int x0 = (int)v[0], y0 = (int)v[1], x1 = (int)v[2 * 4], y1 = (int)v[2 * 4 + 1];
        for (int yy = y0 * scale; yy < y1 * scale; yy++)
            for (int xx = x0 * scale; xx < x1 * scale; xx++)
                put(p, x + xx, y + yy, c);
    }
}

int picture_text_width(const char *s, int scale) { return stb_easy_font_width((char *)s) * scale; }

void picture_error_heatmap(const float *v_tech, const float *v_gt, const float *scored, int width,
                           int height, struct picture *out)
{
    picture_difference(v_tech, v_gt, scored, width, height,
                       &(struct picture_legend){PICTURE_ERROR_SCALE, "too dark", "too bright",
                                                "V_tech - V_gt   grey: not scored"},
                       out);
}

void picture_difference(const float *a, const float *b, const float *shown, int width, int height,
                        const struct picture_legend *legend, struct picture *out)
{
    const int scale = width >= 360 ? 2 : 1;
    const int legend_h = 26 * scale + 8;
    out->width = width;
    out->height = height + legend_h;
    out->rgb = xmalloc((size_t)out->width * out->height * 3);
    memset(out->rgb, 255, (size_t)out->width * out->height * 3);
    for (int i = 0; i < width * height; i++) {
        uint8_t c[3];
        if (shown[i] > 0.5f && isfinite(a[i]))
            picture_diverging((a[i] - b[i]) / legend->scale, c);
        else
            memcpy(c, shown[i] > 0.5f ? (const uint8_t[3]){0, 255, 0} : not_scored, 3);
        memcpy(&out->rgb[(size_t)i * 3], c, 3);
    }

    /* Legend: a colour bar with its scale, what each end means, and the
     * colour of pixels not shown. */
    const uint8_t ink[3] = {20, 20, 20};
    int bar_x0 = width / 5, bar_x1 = width - width / 5, bar_y = height + 4, bar_h = 8 * scale;
    for (int x = bar_x0; x < bar_x1; x++) {
        uint8_t c[3];
        picture_diverging(2.0f * (float)(x - bar_x0) / (float)(bar_x1 - bar_x0 - 1) - 1.0f, c);
        for (int y = bar_y; y < bar_y + bar_h; y++)
            put(out, x, y, c);
    }
    char lo[32], hi[32], words[2][32];
    snprintf(lo, sizeof lo, "-%.2g", (double)legend->scale);
    snprintf(hi, sizeof hi, "+%.2g", (double)legend->scale);
    int ty = bar_y + bar_h + 2;
    picture_text(out, bar_x0, ty, scale, lo, ink);
    picture_text(out, (bar_x0 + bar_x1) / 2 - picture_text_width("0", scale) / 2, ty, scale, "0", ink);
    picture_text(out, bar_x1 - picture_text_width(hi, scale), ty, scale, hi, ink);
    /* Each end's words on two lines: "too" / "dark". */
    const char *ends[2] = {legend->negative, legend->positive};
    for (int e = 0; e < 2; e++) {
        const char *space = strchr(ends[e], ' ');
        snprintf(words[0], sizeof words[0], "%.*s", space ? (int)(space - ends[e]) : (int)strlen(ends[e]), ends[e]);
        snprintf(words[1], sizeof words[1], "%s", space ? space + 1 : "");
        int x = e ? bar_x1 + 4 : 2;
        picture_text(out, x, bar_y, scale, words[0], ink);
        picture_text(out, x, bar_y + 8 * scale, scale, words[1], ink);
    }
    picture_text(out, (width - picture_text_width(legend->caption, scale)) / 2, ty + 9 * scale, scale, legend->caption, ink);
}
