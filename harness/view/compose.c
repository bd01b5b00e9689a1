#include "viewer.h"
#include "base/image.h"
#include "base/log.h"
#include "base/util.h"
#include "techniques/params.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One frame of side k's technique, timed as the harness times a cell (its
 * products rendered afresh, then the receiver pass), read back. */
static int render_side(struct viewer *v, int k)
{
    const struct technique *t = viewer_technique(v, k);
    const void *settings = viewer_settings(v, k);
    const struct stage_timer_cell cell = {t, settings, programs_get(&v->programs, t, settings, v->posed.light.shape,
                                                                    false)};
    struct stage_times now;
    if (!cell.programs.receiver || stage_timer_run(&v->timer, &cell, 1, &now) != 0)
        return -1;
    receiver_read(&v->receiver, v->v[k], v->distance[k]);
    struct stage_times *avg = &v->times[k];
    const double a = v->timed[k] ? 0.2 : 1.0;  /* a moving average: steady digits */
    avg->shadowmap_ms += a * (now.shadowmap_ms - avg->shadowmap_ms);
    avg->filter_prep_ms += a * (now.filter_prep_ms - avg->filter_prep_ms);
    avg->receiver_ms += a * (now.receiver_ms - avg->receiver_ms);
    avg->total_ms += a * (now.total_ms - avg->total_ms);
    v->timed[k] = true;
    if (v->gt_samples > 0) {
        v->m[k] = (struct metrics){0};
        v->m[k].mismatch_pixels = metrics_score_mask(v->gt.mask, v->gt.distance, v->distance[k], v->w, v->h,
                                                     metrics_depth_tolerance(t->depth_tolerance), v->scored[k]);
        metrics_compute(v->v[k], &v->gt, v->scored[k], v->distance[k], &v->m[k]);
    }
    return 0;
}

/* Side k's picture in the current view. */
static void side_picture(struct viewer *v, int k, struct picture *out)
{
    const size_t count = (size_t)v->w * (size_t)v->h;
    const bool gt = v->gt_samples > 0;
    switch (v->mode) {
    case MODE_SHADED:
    case MODE_E: {
        const double mean = v->mean_irradiance;
        const float exposure = mean > 0 ? (float)(1.0 / (VIEWER_WHITE * mean)) : 1.0f;
        for (size_t i = 0; i < count; i++)
            v->shade[i] = fminf(v->irradiance[i] * (v->mode == MODE_E ? 1.0f : v->v[k][i]) * exposure, 1.0f);
        picture_visibility(v->shade, v->distance[k], NULL, v->w, v->h, out);
        return;
    }
    case MODE_VTECH: picture_visibility(v->v[k], v->distance[k], NULL, v->w, v->h, out); return;
    case MODE_VGT:
        if (gt) {
            picture_visibility(v->gt.v, v->gt.distance, v->gt.mask, v->w, v->h, out);
            return;
        }
        break;
    case MODE_ERROR:
        if (gt) {
            picture_error_heatmap(v->v[k], v->gt.v, v->scored[k], v->w, v->h, out);
            return;
        }
        break;
    case MODE_COUNT: break;
    }
    for (size_t i = 0; i < count; i++)  /* no ground truth of this pose yet */
        v->shade[i] = 0.05f;
    picture_visibility(v->shade, v->distance[k], NULL, v->w, v->h, out);
    const uint8_t ink[3] = {230, 230, 230};
    picture_text(out, 8, v->h / 2, 1, v->gt_samples < 0 ? "the ground truth failed (see the log)"
                                                         : "tracing the ground truth of this pose ...", ink);
}

/* Lines of text on a darkened band at the top left. */
static void overlay(struct viewer *v, struct picture *p)
{
    struct strbuf lines[48] = {{0}};
    int n = 0;
    const struct technique *a = viewer_technique(v, 0), *b = viewer_technique(v, 1);
    strbuf_printf(&lines[n++], "%s%s%s   view %s (1-5)   %s", a->name, v->split ? " | " : "",
                  v->split ? b->name : "", view_mode_names[v->mode], v->split ? "split (Space)" : "Tab: technique");
    for (int i = 0; a->params[i].name && n < 40; i++) {
        char text[64];
        params_value_text(a, viewer_settings(v, 0), a->params[i].name, text, sizeof text);
        strbuf_printf(&lines[n++], "%s %s = %s", i == v->param ? ">" : " ", a->params[i].name, text);
    }
    const char *how = stage_timing_resolve(STAGE_TIMING_AUTO) == STAGE_TIMING_WALL ? "wall clock" : "GL queries";
    for (int k = 0; k <= (int)v->split; k++) {
        const struct stage_times *t = &v->times[k];
        strbuf_printf(&lines[n++], "%s ms: map %.2f  filter %.2f  receiver %.2f  total %.2f (%s)",
                      v->split ? (k ? "right" : "left") : "", t->shadowmap_ms, t->filter_prep_ms, t->receiver_ms,
                      t->total_ms, how);
    }
    if (v->gt_samples > 0) {
        for (int k = 0; k <= (int)v->split; k++)
            strbuf_printf(&lines[n++], "%s rmse %.4f  penumbra_rmse %.4f  (V_gt %d of %d spp)",
                          v->split ? (k ? "right" : "left") : "", v->m[k].rmse, v->m[k].penumbra_rmse,
                          v->gt_samples, v->d.gt_samples);
    } else {
        strbuf_printf(&lines[n++], "%s", v->gt_samples < 0 ? "V_gt failed" : "V_gt: tracing ...");
    }
    if (v->message[0])
        strbuf_printf(&lines[n++], "%s", v->message);
    const int scale = v->w >= 1024 ? 2 : 1, step = 11 * scale;
    int width = 0;
    for (int i = 0; i < n; i++)
        width = width > picture_text_width(lines[i].data, scale) ? width : picture_text_width(lines[i].data, scale);
    for (int y = 0; y < 4 + n * step && y < p->height; y++)
        for (int x = 0; x < width + 8 && x < p->width; x++) {
            uint8_t *c = &p->rgb[((size_t)y * p->width + x) * 3];
            c[0] /= 3, c[1] /= 3, c[2] /= 3;
        }
    const uint8_t ink[3] = {255, 255, 255};
    for (int i = 0; i < n; i++) {
        picture_text(p, 4, 4 + i * step, scale, lines[i].data, ink);
        strbuf_free(&lines[i]);
    }
}

/* The window's picture: one side, or the left half of one and the right of
 * the other with a line between; the overlay on top. */
static void compose(struct viewer *v)
{
    picture_free(&v->pic);
    side_picture(v, 0, &v->pic);
    if (v->split) {
        struct picture right = {0};
        side_picture(v, 1, &right);
        for (int y = 0; y < v->pic.height && y < right.height; y++) {
            const size_t row = (size_t)y * v->pic.width * 3, half = (size_t)(v->pic.width / 2) * 3;
            memcpy(&v->pic.rgb[row + half], &right.rgb[row + half], (size_t)v->pic.width * 3 - half);
            memset(&v->pic.rgb[row + half - 3], 255, 3);
        }
        picture_free(&right);
    }
    if (v->overlay)
        overlay(v, &v->pic);
}

void viewer_present(struct viewer *v, int fw, int fh)
{
    const struct picture *p = &v->pic;
    if (p->width != v->show_w || p->height != v->show_h) {
        glDeleteTextures(1, &v->show_texture);
        glDeleteFramebuffers(1, &v->show_fbo);
        v->show_texture = gl_texture_2d(GL_RGB8, p->width, p->height, "view: the window's picture");
        v->show_fbo = gl_framebuffer(&v->show_texture, 1, 0, "view: the window's picture");
        v->show_w = p->width, v->show_h = p->height;
    }
    glBindTexture(GL_TEXTURE_2D, v->show_texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, p->width, p->height, GL_RGB, GL_UNSIGNED_BYTE, p->rgb);
    const float s = fminf((float)fw / (float)p->width, (float)fh / (float)p->height);
    const int dw = (int)lrintf(s * (float)p->width), dh = (int)lrintf(s * (float)p->height);
    const int x0 = (fw - dw) / 2, y0 = (fh - dh) / 2;
    glBindFramebuffer(GL_DRAW_FRAMEBUFFER, 0);
    glViewport(0, 0, fw, fh);
    glClearBufferfv(GL_COLOR, 0, (const float[4]){0.08f, 0.08f, 0.1f, 1});
    glBindFramebuffer(GL_READ_FRAMEBUFFER, v->show_fbo);
    /* the picture's top row first: read upside down */
    glBlitFramebuffer(0, p->height, p->width, 0, x0, y0, x0 + dw, y0 + dh, GL_COLOR_BUFFER_BIT,
                      s == 1.0f ? GL_NEAREST : GL_LINEAR);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
}

int viewer_screenshot(int fw, int fh, const char *path)
{
    uint8_t *rgb = xmalloc((size_t)fw * fh * 3), *flipped = xmalloc((size_t)fw * fh * 3);
    glBindFramebuffer(GL_READ_FRAMEBUFFER, 0);
    glReadBuffer(GL_BACK);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, fw, fh, GL_RGB, GL_UNSIGNED_BYTE, rgb);
    for (int y = 0; y < fh; y++)
        memcpy(flipped + (size_t)y * fw * 3, rgb + (size_t)(fh - 1 - y) * fw * 3, (size_t)fw * 3);
    int rc = image_write_png(path, fw, fh, flipped);
    free(rgb), free(flipped);
    if (rc == 0)
        log_info("view: wrote %s (%d x %d)", path, fw, fh);
    return rc;
}

int viewer_frame(struct viewer *v, bool wait_for_truth)
{
    const double start = util_now_ms();
    for (int level = 0; wait_for_truth && !gt_worker_wait(&v->worker, v->pose_id, 250, &level);)
        log_progress("view: the screenshot waits for its ground truth: %d of %d samples per pixel done, %.0f s",
                     level, v->d.gt_samples, (util_now_ms() - start) * 1e-3);
    log_progress_done();
    const int got = gt_worker_take(&v->worker, v->pose_id, &v->gt);
    if (got)
        v->gt_samples = got;
    for (int k = 0; k <= (int)v->split; k++)
        if (render_side(v, k) != 0)
            return -1;
    compose(v);
    return 0;
}

void viewer_summary(const struct viewer *v, char *out, size_t size)
{
    char score[160];
    if (v->gt_samples <= 0)
        snprintf(score, sizeof score, "%s", v->gt_samples < 0 ? "the ground truth failed" : "no ground truth yet");
    else if (v->m[0].scored_pixels == 0)
        snprintf(score, sizeof score, "no pixel scored (V_gt %d spp)", v->gt_samples);
    else
        snprintf(score, sizeof score, "rmse %.6f, penumbra_rmse %.6f (V_gt %d spp)", v->m[0].rmse,
                 v->m[0].penumbra_rmse, v->gt_samples);
    snprintf(out, size, "%s, view %s%s%s: %s, mean E %.6g", viewer_technique(v, 0)->name, view_mode_names[v->mode],
             v->split ? ", right " : "", v->split ? viewer_technique(v, 1)->name : "", score, v->mean_irradiance);
}
