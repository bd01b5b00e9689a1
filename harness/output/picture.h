/* The pictures a person looks at: visibility in grey, and the signed error
 * as a diverging heatmap with its legend (value scale) drawn on the image. */
#ifndef SB_PICTURE_H
#define SB_PICTURE_H

#include <stdint.h>

/* Heatmap range: errors beyond +-PICTURE_ERROR_SCALE saturate. Fixed, so
 * heatmaps of different cells compare by eye. */
#define PICTURE_ERROR_SCALE 0.5f

struct picture {
    int width, height;
    uint8_t *rgb;  /* width * height * 3, top row first */
};

/* V in grey (sRGB); pixels with no geometry (distance < 0) in slate blue;
 * where scored is given, unscored pixels hatched in grey (the ground truth
 * there is not computed or not compared). */
void picture_visibility(const float *v, const float *distance, const float *scored, int width,
                        int height, struct picture *out);

/* e = v_tech - v_gt on scored pixels (blue: too dark, red: too bright),
 * grey where not scored, with a legend strip added below the image. */
void picture_error_heatmap(const float *v_tech, const float *v_gt, const float *scored, int width,
                           int height, struct picture *out);

/* A difference heatmap's legend: the colour bar spans -scale..+scale;
 * the words at its ends (up to two words each, e.g. "too dark"); the
 * caption under it. */
struct picture_legend {
    float scale;
    const char *negative, *positive, *caption;
};

/* a - b where shown[i] is set (a diverging map, saturating beyond the
 * legend's scale), grey elsewhere, green where a is not finite; the legend
 * drawn below the image. */
void picture_difference(const float *a, const float *b, const float *shown, int width, int height,
                        const struct picture_legend *legend, struct picture *out);

/* Text at (x, y) (its top left), in stb_easy_font's glyphs, each glyph
 * pixel a scale x scale block of colour c; clipped to the picture. */
void picture_text(struct picture *p, int x, int y, int scale, const char *s, const uint8_t c[3]);

/* The width in pixels picture_text gives s. */
int picture_text_width(const char *s, int scale);

/* Diverging colormap: t in [-1, 1] -> RGB. */
void picture_diverging(float t, uint8_t rgb[3]);

void picture_free(struct picture *p);

#endif
