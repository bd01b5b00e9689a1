#include "cell.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "techniques/params.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

void cell_describe(struct cell *c, const char *scene, const struct technique *t, const void *settings,
                   const char *label)
{
    *c = (struct cell){.scene = scene, .technique = t, .label = label, .gl_renderer = gl_context_renderer()};
    c->params = params_json(t, settings);
    struct strbuf text = {0};
    params_summary(t, settings, &text);
    c->params_text = text.data ? text.data : xstrdup("");
}

void cell_set_times(struct cell *c, const struct stage_times *t)
{
    c->m.ms_shadowmap = t->shadowmap_ms, c->m.ms_filter_prep = t->filter_prep_ms;
    c->m.ms_mask = t->mask_ms, c->m.ms_receiver = t->receiver_ms, c->m.ms_denoise = t->denoise_ms;
    c->m.ms_total = t->total_ms;
    c->m.ms_total_q1 = t->total_q1_ms, c->m.ms_total_q3 = t->total_q3_ms;
}

void cell_note_search(struct cell *c, const void *settings, const struct shadow_cascades *cs)
{
    /* the search's light size scale: its own (pcss) when set, else light_size_scale */
    const struct technique_param *own = params_find(c->technique, "search_light_size_scale"),
                                 *both = params_find(c->technique, "light_size_scale");
    const double scale = own && params_get(own, settings) > 0 ? params_get(own, settings)
                         : both                               ? params_get(both, settings)
                                                              : -1;
    if (scale >= 0) {
        for (int k = 0; k < cs->count; k++) {
            const int map_size = cs->map[k].desc.size_texels;
            const float side = light_frustum_search_box_texels(&cs->map[k].frustum, (float)scale, map_size);
            if (side <= (float)map_size)
                continue;
            free(c->notice);
            c->notice = util_printf("the blocker search at light_size_scale %g spans %.0f texels at the farthest "
                                    "receiver%s, wider than the %d-texel map: past its edge it reads edge texels",
                                    scale, (double)side, cs->count > 1 ? " of a cascade" : "", map_size);
            log_warn("%s on %s: %s", c->label, c->scene, c->notice);
            break;
        }
    }
}

void cell_take_setup(struct cell *c, const struct scene_setup *ss)
{
    c->depth = ss->depth;
    cJSON_Delete(c->cascades);
    c->cascades = shadow_cascades_json(&ss->cascades, ss->scene->light.shape == LIGHT_SUN);
    if (technique_is_engine(c->technique)) {
        free(c->engine_version), free(c->engine_renderer);
        c->engine_version = xstrdup(ss->engine.version);
        c->engine_renderer = xstrdup(ss->engine.renderer);
        c->gl_renderer = c->engine_renderer;
        c->engine_texel_ratio[0] = ss->engine.texel_ratio[0], c->engine_texel_ratio[1] = ss->engine.texel_ratio[1];
        if (ss->engine.notice[0] && !c->notice) {
            c->notice = xstrdup(ss->engine.notice);
            log_warn("%s on %s: %s", c->label, c->scene, c->notice);
        }
    }
}

void cell_free(struct cell *c)
{
    cJSON_Delete(c->params);
    cJSON_Delete(c->cascades);
    c->cascades = NULL;
    free(c->params_text);
    free(c->notice);
    free(c->engine_version), free(c->engine_renderer), free(c->failed);
    c->failed = NULL;
    c->params = NULL, c->params_text = NULL, c->notice = NULL, c->engine_version = NULL, c->engine_renderer = NULL;
}

int scene_setup_open(struct scene_setup *ss, const struct scene *s, const struct scene_setup_desc *d)
{
    memset(ss, 0, sizeof *ss);
    ss->scene = s;
    ss->width = d->width, ss->height = d->height;
    ss->programs = d->programs;
    scene_mesh_upload(s, &ss->mesh);
    if (shadow_cascades_create(&ss->cascades, s,
                               &(struct shadowmap_desc){.size_texels = d->shadow_map_size,
                                                        .near_scale = d->near_scale,
                                                        .aspect = (float)d->width / (float)d->height},
                               d->cascades) ||
        receiver_create(&ss->receiver, s, d->width, d->height) ||
        gt_obtain(s, &ss->cascades.view,
                  &(struct gt_desc){.width = d->width, .height = d->height, .samples = d->gt_samples,
                                    .seed = d->gt_seed},
                  d->cache_dir, &ss->gt) != 0)
        return -1;
    const size_t count = (size_t)d->width * (size_t)d->height;
    ss->view_depth = xmalloc(sizeof(float) * count);
    scene_setup_truth_posed(ss);
    ss->v = xmalloc(sizeof(float) * count);
    ss->distance = xmalloc(sizeof(float) * count);
    ss->scored = xcalloc(count, sizeof(float));  /* written whole even before any cell is scored */
    ss->shortcut = xmalloc(sizeof(float) * count);
    ss->timer = (struct stage_timer){.cascades = &ss->cascades, .mesh = &ss->mesh, .receiver = &ss->receiver};
    return 0;
}

void scene_setup_truth_posed(struct scene_setup *ss)
{
    const struct scene_camera *c = &ss->scene->camera;
    const float ty = tanf(0.5f * c->yfov_rad), tx = ty * (float)ss->width / (float)ss->height;
    const float far = ss->cascades.z[ss->cascades.count];  /* INFINITY: no shadow distance */
    for (int y = 0; y < ss->height; y++)
        for (int x = 0; x < ss->width; x++) {
            const size_t i = (size_t)y * (size_t)ss->width + (size_t)x;
            const float px = (2.0f * ((float)x + 0.5f) / (float)ss->width - 1.0f) * tx;
            const float py = (1.0f - 2.0f * ((float)y + 0.5f) / (float)ss->height) * ty;
            const float d = ss->gt.distance[i];
            ss->view_depth[i] = d < 0 ? -1.0f : d / sqrtf(1.0f + px * px + py * py);
            if (d >= 0 && ss->view_depth[i] > far)
                ss->gt.mask[i] = 0;  /* past the shadow distance: unshadowed, unscored */
        }
}

struct stage_timer_cell scene_setup_timer_cell(struct scene_setup *ss, const struct technique *t,
                                               const void *settings)
{
    if (technique_is_engine(t))
        return (struct stage_timer_cell){t, settings, {0}};
    return (struct stage_timer_cell){t, settings,
                                     programs_get(ss->programs, t, settings, ss->scene->light.shape, false)};
}

/* An engine cell's frames on ss: its shadow factor and camera distance
 * into ss->v and ss->distance, its engine and times into ss->engine. */
static int engine_frames(struct scene_setup *ss, const struct technique *t, const void *settings, int warmup,
                         int frames)
{
    const struct technique_param *size = params_find(t, "map_size");
    const int own = size ? (int)params_get(size, settings) : 0;
    struct strbuf text = {0}, label = {0};
    params_summary(t, settings, &text);
    strbuf_printf(&label, "%s (%s)", t->name, text.data ? text.data + strspn(text.data, " ") : "");
    strbuf_free(&text);
    struct engine_result *e = &ss->engine;
    *e = (struct engine_result){0};
    e->image[ENGINE_OUT_SHADOW] = ss->v, e->image[ENGINE_OUT_DISTANCE] = ss->distance;
    const int rc = engine_render(&(struct engine_request){.t = t, .settings = settings, .scene = ss->scene,
                                                          .frustum = &ss->cascades.map[0].frustum,
                                                          .label = label.data, .width = ss->width,
                                                          .height = ss->height,
                                                          .map_size = own > 0 ? own
                                                                                : ss->cascades.map[0].desc.size_texels,
                                                          .warmup = warmup, .frames = frames,
                                                          .outputs = 1u << ENGINE_OUT_SHADOW |
                                                                     1u << ENGINE_OUT_DISTANCE},
                                 e);
    strbuf_free(&label);
    ss->engine_last = rc == 0;
    return rc;
}

int scene_setup_cell(struct scene_setup *ss, const struct technique *t, const void *settings, struct metrics *m)
{
    if (technique_is_engine(t)) {
        if (engine_frames(ss, t, settings, 0, 1) != 0)
            return -1;
        scene_setup_score(ss, t, m);
        m->fetches_per_pixel = m->prep_texels = m->expensive_fraction = m->misclassified_fraction = NAN;
        return 0;
    }
    const struct stage_timer_cell cell = {t, settings,
                                          programs_get(ss->programs, t, settings, ss->scene->light.shape, true)};
    ss->engine_last = false;
    if (!cell.programs.receiver || stage_timer_render(&ss->timer, &cell, true) != 0)
        return -1;
    scene_setup_score(ss, t, m);
    struct receiver_cost cost;
    receiver_read_cost(&ss->receiver, &cost, ss->shortcut);
    metrics_cost(cost.fetches, cost.covered, cost.expensive, ss->shortcut, &ss->gt, ss->scored, ss->width * ss->height, m);
    m->prep_texels = stage_timer_prep_texels(&ss->timer, &cell);
    return 0;
}

void scene_setup_score(struct scene_setup *ss, const struct technique *t, struct metrics *m)
{
    if (!ss->engine_last)  /* an engine's frame is in ss->v already */
        receiver_read(&ss->receiver, ss->v, ss->distance);
    m->mismatch_pixels = metrics_score_mask(ss->gt.mask, ss->gt.distance, ss->distance, ss->width, ss->height,
                                            metrics_depth_tolerance(t->depth_tolerance), ss->scored);
    metrics_compute(ss->v, &ss->gt, ss->scored, ss->distance, m);
    depth_metrics_compute(ss->v, &ss->gt, ss->scored, ss->view_depth, ss->cascades.z, ss->cascades.band,
                          ss->cascades.count, &ss->depth);
}

int scene_setup_time(struct scene_setup *ss, const struct scene_setup_timing *how, const struct stage_timer_cell *cells,
                     int n, struct stage_times *out)
{
    struct stage_timer timer = ss->timer;
    timer.warmup = how->warmup, timer.frames = how->frames, timer.timing = how->timing;
    timer.on_round = how->on_round, timer.user = how->user;
    /* shadowbench's own cells interleaved, then each engine cell by its engine */
    struct stage_timer_cell *own = xmalloc(sizeof *own * (size_t)(n > 0 ? n : 1));
    struct stage_times *own_times = xmalloc(sizeof *own_times * (size_t)(n > 0 ? n : 1));
    int count = 0;
    for (int i = 0; i < n; i++)
        if (!technique_is_engine(cells[i].technique))
            own[count++] = cells[i];
    int rc = count ? stage_timer_run(&timer, own, count, own_times) : 0;
    ss->engine_last = false;
    for (int i = 0, k = 0; i < n && !rc; i++) {
        if (!technique_is_engine(cells[i].technique)) {
            out[i] = own_times[k++];
            continue;
        }
        const bool failed = engine_frames(ss, cells[i].technique, cells[i].settings, how->warmup, how->frames) != 0;
        out[i] = failed ? (struct stage_times){NAN, NAN, NAN, NAN, NAN, NAN, NAN, NAN}
                        : (struct stage_times){NAN, NAN, NAN, NAN, NAN, ss->engine.ms, ss->engine.ms_q1,
                                               ss->engine.ms_q3};
        if (failed && how->engine_failed)
            how->engine_failed[i] = true;
        else
            rc = failed ? -1 : 0;
    }
    free(own), free(own_times);
    return rc;
}

void scene_setup_free(struct scene_setup *ss)
{
    gt_image_free(&ss->gt);
    receiver_destroy(&ss->receiver);
    shadow_cascades_destroy(&ss->cascades);
    scene_mesh_destroy(&ss->mesh);
    free(ss->v), free(ss->distance), free(ss->scored), free(ss->view_depth), free(ss->shortcut);
    memset(ss, 0, sizeof *ss);
}
