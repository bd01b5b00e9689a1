#include "image.h"
#include "log.h"
#include "util.h"

#include <OpenEXR/openexr.h>
#include <png.h>

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static int exr_failed(exr_context_t ctx, const char *path, const char *what, exr_result_t rc)
{
    /* the library's write error hides the system's reason: errno keeps it
     * (write_exr_to clears it first) */
    const int err = rc == EXR_ERR_WRITE_IO ? errno : 0;
    log_error("%s: %s: %s%s%s", path, what, exr_get_default_error_message(rc), err ? ": " : "",
              err ? strerror(err) : "");
    if (ctx)
        exr_finish(&ctx);
    return -1;
}

/* The library's own messages would make a second line: ours name the file. */
static void exr_quiet(exr_const_context_t ctx, exr_result_t code, const char *msg)
{
    (void)ctx, (void)code, (void)msg;
}

/* The library's writes, into our descriptor (user data): it opens no file. */
static int64_t exr_pwrite(exr_const_context_t ctx, void *user, const void *buffer, uint64_t size, uint64_t offset,
                          exr_stream_error_func_ptr_t error_cb)
{
    const int fd = *(const int *)user;
    for (uint64_t done = 0; done < size;) {
        const ssize_t n = pwrite(fd, (const char *)buffer + done, size - done, (off_t)(offset + done));
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0) {
            error_cb(ctx, EXR_ERR_WRITE_IO, "write failed");
            return -1;
        }
        done += (uint64_t)n;
    }
    return (int64_t)size;
}

/* Writes the EXR into descriptor fd; messages name path. */
static int write_exr_to(const char *path, int fd, int width, int height, const struct exr_channel *channels,
                        int channel_count, const char *comments)
{
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_quiet;
    init.user_data = &fd;
    init.write_fn = exr_pwrite;
    int part = 0;
    errno = 0;
    exr_result_t rc = exr_start_write(&ctx, path, EXR_WRITE_FILE_DIRECTLY, &init);
    if (rc != EXR_ERR_SUCCESS)
        return exr_failed(NULL, path, "cannot write", rc);
    if ((rc = exr_add_part(ctx, "visibility", EXR_STORAGE_SCANLINE, &part)) ||
        (rc = exr_initialize_required_attr_simple(ctx, part, width, height, EXR_COMPRESSION_ZIP)) ||
        (rc = exr_set_zip_compression_level(ctx, part, 1)))
        return exr_failed(ctx, path, "cannot write header", rc);
    for (int c = 0; c < channel_count; c++)
        if ((rc = exr_add_channel(ctx, part, channels[c].name, EXR_PIXEL_FLOAT,
                                  EXR_PERCEPTUALLY_LINEAR, 1, 1)))
            return exr_failed(ctx, path, "cannot add channel", rc);
    if (comments && (rc = exr_attr_set_string(ctx, part, "comments", comments)))
        return exr_failed(ctx, path, "cannot write header", rc);
    if ((rc = exr_write_header(ctx)))
        return exr_failed(ctx, path, "cannot write header", rc);

    int32_t lines_per_chunk = 1;
    exr_get_scanlines_per_chunk(ctx, part, &lines_per_chunk);
    exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
    bool first = true;
    for (int y = 0; y < height; y += lines_per_chunk) {
        exr_chunk_info_t chunk;
        if ((rc = exr_write_scanline_chunk_info(ctx, part, y, &chunk)))
            break;
        rc = first ? exr_encoding_initialize(ctx, part, &chunk, &enc)
                   : exr_encoding_update(ctx, part, &chunk, &enc);
        if (rc)
            break;
        /* The file orders channels by name: match each by name. */
        for (int i = 0; i < enc.channel_count; i++) {
            const struct exr_channel *src = NULL;
            for (int c = 0; c < channel_count; c++)
                if (strcmp(channels[c].name, enc.channels[i].channel_name) == 0)
                    src = &channels[c];
            enc.channels[i].encode_from_ptr = (const uint8_t *)(src->data + (size_t)y * width);
            enc.channels[i].user_pixel_stride = sizeof(float);
            enc.channels[i].user_line_stride = (int32_t)(sizeof(float) * (size_t)width);
            enc.channels[i].user_data_type = EXR_PIXEL_FLOAT;
            enc.channels[i].user_bytes_per_element = sizeof(float);
        }
        if (first && (rc = exr_encoding_choose_default_routines(ctx, part, &enc)))
            break;
        first = false;
        if ((rc = exr_encoding_run(ctx, part, &enc)))
            break;
    }
    if (!first)
        exr_encoding_destroy(ctx, &enc);
    if (rc)
        return exr_failed(ctx, path, "cannot write pixels", rc);
    if ((rc = exr_finish(&ctx)))
        return exr_failed(NULL, path, "cannot finish", rc);
    return 0;
}

int image_write_exr(const char *path, int width, int height, const struct exr_channel *channels,
                    int channel_count, const char *comments)
{
    /* Our own temporary and rename (not the library's), so that a signal
     * removes it and a later run knows its name (util.h). */
    char *tmp;
    const int fd = util_temp_create(path, &tmp);
    if (fd < 0)
        return -1;
    int rc = write_exr_to(path, fd, width, height, channels, channel_count, comments);
    if (close(fd) != 0 && rc == 0) {
        log_error("%s: cannot write: %s", path, strerror(errno));
        rc = -1;
    }
    if (rc == 0 && rename(tmp, path) != 0) {
        log_error("%s: cannot write: %s", path, strerror(errno));
        rc = -1;
    }
    if (rc)
        unlink(tmp);
    util_temp_end();
    free(tmp);
    return rc;
}

int image_read_exr(const char *path, int width, int height, struct exr_channel *channels,
                   int channel_count, char **comments)
{
    if (!util_file_exists(path))
        return -ENOENT;
    exr_context_t ctx = NULL;
    exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
    init.error_handler_fn = exr_quiet;
    exr_result_t rc = exr_start_read(&ctx, path, &init);
    if (rc)
        return exr_failed(NULL, path, "cannot read", rc);
    exr_attr_box2i_t dw;
    if ((rc = exr_get_data_window(ctx, 0, &dw)))
        return exr_failed(ctx, path, "cannot read header", rc);
    if (dw.max.x - dw.min.x + 1 != width || dw.max.y - dw.min.y + 1 != height) {
        log_error("%s: is %dx%d, expected %dx%d", path, dw.max.x - dw.min.x + 1,
                  dw.max.y - dw.min.y + 1, width, height);
        exr_finish(&ctx);
        return -1;
    }
    if (comments) {
        const char *text = NULL;
        int32_t length = 0;
        *comments = exr_attr_get_string(ctx, 0, "comments", &length, &text) == EXR_ERR_SUCCESS
                        ? util_printf("%.*s", (int)length, text)
                        : NULL;
    }
    for (int c = 0; c < channel_count; c++)
        channels[c].data = xcalloc((size_t)width * (size_t)height, sizeof(float));

    int32_t lines_per_chunk = 1;
    exr_get_scanlines_per_chunk(ctx, 0, &lines_per_chunk);
    exr_decode_pipeline_t dec = EXR_DECODE_PIPELINE_INITIALIZER;
    bool first = true;
    int found = 0;
    for (int y = dw.min.y; y <= dw.max.y && !rc; y += lines_per_chunk) {
        exr_chunk_info_t chunk;
        if ((rc = exr_read_scanline_chunk_info(ctx, 0, y, &chunk)))
            break;
        rc = first ? exr_decoding_initialize(ctx, 0, &chunk, &dec)
                   : exr_decoding_update(ctx, 0, &chunk, &dec);
        if (rc)
            break;
        found = 0;
        for (int i = 0; i < dec.channel_count; i++) {
            dec.channels[i].decode_to_ptr = NULL;  /* channels we don't want are skipped */
            for (int c = 0; c < channel_count; c++)
                if (strcmp(channels[c].name, dec.channels[i].channel_name) == 0) {
                    dec.channels[i].decode_to_ptr =
                        (uint8_t *)(channels[c].data + (size_t)(y - dw.min.y) * width);
                    dec.channels[i].user_pixel_stride = sizeof(float);
                    dec.channels[i].user_line_stride = (int32_t)(sizeof(float) * (size_t)width);
                    dec.channels[i].user_data_type = EXR_PIXEL_FLOAT;
                    dec.channels[i].user_bytes_per_element = sizeof(float);
                    found++;
                }
        }
        if (found != channel_count)
            break;
        if (first && (rc = exr_decoding_choose_default_routines(ctx, 0, &dec)))
            break;
        first = false;
        rc = exr_decoding_run(ctx, 0, &dec);
    }
    if (!first)
        exr_decoding_destroy(ctx, &dec);
    if (rc || found != channel_count) {
        for (int c = 0; c < channel_count; c++) {
            free(channels[c].data);
            channels[c].data = NULL;
        }
        if (comments)
            free(*comments), *comments = NULL;
        if (rc)
            return exr_failed(ctx, path, "cannot read pixels", rc);
        log_error("%s: lacks a channel this version needs", path);
        exr_finish(&ctx);
        return -1;
    }
    exr_finish(&ctx);
    return 0;
}

/* Encodes pixels (rows top first, packed) as format into a buffer of the
 * largest size the encoding can take, so the image is encoded once, and
 * writes it to path atomically. PNG_IMAGE_FLAG_FAST: libpng's setting for
 * speed over size; a run writes two pictures a cell, and stb_image_write's
 * encoder took most of a cell's output time (measured in Speed). */
static int write_png(const char *path, int width, int height, png_uint_32 format, const void *pixels)
{
    png_image im = {.version = PNG_IMAGE_VERSION, .width = (png_uint_32)width,
                    .height = (png_uint_32)height, .format = format, .flags = PNG_IMAGE_FLAG_FAST};
    png_alloc_size_t size = PNG_IMAGE_PNG_SIZE_MAX(im);
    void *png = xmalloc(size);
    int rc = png_image_write_to_memory(&im, png, &size, 0, pixels, 0, NULL)
                 ? util_write_file_atomic(path, png, size)
                 : (log_error("%s: PNG encoding failed: %s", path, im.message), -1);
    free(png);
    return rc ? -1 : 0;
}

int image_write_png(const char *path, int width, int height, const uint8_t *rgb)
{
    return write_png(path, width, height, PNG_FORMAT_RGB, rgb);
}

int image_write_png16(const char *path, int width, int height, const uint16_t *pixels)
{
    return write_png(path, width, height, PNG_FORMAT_LINEAR_Y, pixels);
}

static uint32_t be32(const unsigned char *p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

/* Whether the PNG in bytes is 16-bit grey with linear samples (no sRGB or
 * ICC profile, gamma absent or 1.0), so that its samples are read as
 * written; else why not. */
static const char *png16_problem(const unsigned char *bytes, size_t size)
{
    static const unsigned char signature[8] = {137, 80, 78, 71, 13, 10, 26, 10};
    if (size < 33 || memcmp(bytes, signature, 8) != 0 || memcmp(bytes + 12, "IHDR", 4) != 0)
        return "not a PNG";
    if (bytes[24] != 16 || bytes[25] != 0)
        return "not a 16-bit grey PNG";
    for (size_t at = 8; at + 12 <= size;) {
        const uint32_t length = be32(bytes + at);
        const unsigned char *type = bytes + at + 4, *data = bytes + at + 8;
        if (length > size - at - 12)
            return "a chunk runs past the end of the file";
        if (memcmp(type, "sRGB", 4) == 0 || memcmp(type, "iCCP", 4) == 0)
            return "its samples are not linear (an sRGB or ICC chunk)";
        if (memcmp(type, "gAMA", 4) == 0 && (length != 4 || be32(data) != 100000))
            return "its samples are not linear (a gamma other than 1.0)";
        if (memcmp(type, "IEND", 4) == 0)
            return NULL;
        at += 12 + (size_t)length;
    }
    return "no IEND chunk: the file is cut short";
}

int image_read_png16(const char *path, int width, int height, uint16_t **pixels)
{
    *pixels = NULL;
    char *bytes;
    size_t size;
    int err = util_read_file(path, &bytes, &size);
    if (err == -ENOENT)
        return -ENOENT;
    if (err) {
        log_error("%s: cannot read: %s", path, util_read_error(err));
        return -1;
    }
    const char *problem = png16_problem((const unsigned char *)bytes, size);
    png_image im = {.version = PNG_IMAGE_VERSION};
    if (problem || !png_image_begin_read_from_memory(&im, bytes, size)) {
        log_error("%s: %s", path, problem ? problem : im.message);
        free(bytes);
        return -1;
    }
    if ((int)im.width != width || (int)im.height != height) {
        log_error("%s: %ux%u pixels, expected %dx%d", path, im.width, im.height, width, height);
        png_image_free(&im);
        free(bytes);
        return -1;
    }
    im.format = PNG_FORMAT_LINEAR_Y;
    *pixels = xmalloc((size_t)width * (size_t)height * sizeof **pixels);
    if (!png_image_finish_read(&im, NULL, *pixels, 0, NULL)) {
        log_error("%s: not a readable PNG: %s", path, im.message);
        free(*pixels);
        *pixels = NULL;
        free(bytes);
        return -1;
    }
    free(bytes);
    return 0;
}

uint8_t image_srgb8(float v)
{
    v = v > 0.0f ? (v < 1.0f ? v : 1.0f) : 0.0f;  /* also maps NaN to 0 */
    float s = v <= 0.0031308f ? 12.92f * v : 1.055f * powf(v, 1.0f / 2.4f) - 0.055f;
    return (uint8_t)lrintf(s * 255.0f);
}
