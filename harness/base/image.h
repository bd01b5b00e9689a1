/* Image files: float EXR through the OpenEXR C API, 8-bit PNG through
 * libpng's simplified API, as is 16-bit grey PNG. Rows are top row first
 * (docs/design.md §8). Every write is atomic: a temporary file renamed into
 * place. */
#ifndef SB_IMAGE_H
#define SB_IMAGE_H

#include <stdint.h>

struct exr_channel {
    const char *name;
    float *data;  /* width * height floats */
};

/* Writes float32 channels (ZIP compressed), and comments (may be NULL) as
 * the header's standard "comments" attribute. Returns 0 or -1 (logged). */
int image_write_exr(const char *path, int width, int height, const struct exr_channel *channels,
                    int channel_count, const char *comments);

/* Reads the named float channels into newly malloc'ed arrays (channels[i].data)
 * and, where comments is not NULL, the "comments" attribute into a newly
 * malloc'ed *comments (NULL when absent). Returns 0, -ENOENT if the file does
 * not exist (not logged), or -1 (logged) if it is unreadable, has another
 * size or lacks a channel. */
int image_read_exr(const char *path, int width, int height, struct exr_channel *channels,
                   int channel_count, char **comments);

/* 8-bit sRGB RGB PNG, top row first. Returns 0 or -1 (logged). */
int image_write_png(const char *path, int width, int height, const uint8_t *rgb);

/* 16-bit grey PNG, linear (no transfer curve), top row first. Returns 0 or
 * -1 (logged). */
int image_write_png16(const char *path, int width, int height, const uint16_t *pixels);

/* Reads a 16-bit grey PNG with linear samples (as image_write_png16 writes
 * it) of exactly width x height into a newly malloc'ed *pixels. Returns 0,
 * -ENOENT if the file does not exist (not logged), or -1 (logged) if it is
 * unreadable, of another format (8-bit, colour, sRGB: refused, not
 * converted) or another size. */
int image_read_png16(const char *path, int width, int height, uint16_t **pixels);

/* Linear [0,1] -> 8-bit sRGB. */
uint8_t image_srgb8(float linear);

#endif
