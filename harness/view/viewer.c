#include "viewer.h"
#include "base/log.h"
#include "base/util.h"
#include "techniques/params.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const view_mode_names[MODE_COUNT] = {"shaded", "V_tech", "V_gt", "error", "E"};

const struct technique *viewer_technique(const struct viewer *v, int k)
{
    return v->d.techniques[v->side[k]];
}

void *viewer_settings(const struct viewer *v, int k)
{
    return v->settings[v->side[k]];
}

static void say(struct viewer *v, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(struct viewer *v, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(v->message, sizeof v->message, fmt, ap);
    va_end(ap);
    log_info("view: %s", v->message);
}

/* Puts the pose asked for into effect: the shadow map refitted, the
 * camera moved, the ground truth asked for. A pose the light frustum cannot
 * be fitted to (logged) is refused: the last stays. */
void viewer_apply_pose(struct viewer *v)
{
    if (!v->pose_dirty)
        return;
    v->pose_dirty = false;
    /* how far a pose may go: past these, float precision and the ray
     * tracer's range give out */
    struct scene_orbit *p = &v->pose;
    const struct scene_orbit asked = *p;
    const float reach = VIEWER_LIGHT_REACH * v->extent, dolly = logf(VIEWER_DOLLY_REACH);
    p->light_dx = fminf(fmaxf(p->light_dx, -reach), reach), p->light_dy = fminf(fmaxf(p->light_dy, -reach), reach);
    p->dolly = fminf(fmaxf(p->dolly, -dolly), dolly);
    p->pitch = fminf(fmaxf(p->pitch, -VIEWER_PITCH_MAX), VIEWER_PITCH_MAX);
    if (memcmp(&asked, p, sizeof asked) != 0)
        say(v, "no farther: the light stays within %g scene sizes, the camera within %gx its distance and "
            "%.0f degrees of pitch", (double)VIEWER_LIGHT_REACH, (double)VIEWER_DOLLY_REACH,
            (double)VIEWER_PITCH_MAX * 180 / M_PI);
    struct scene s = scene_orbited(v->base, &v->pose, v->extent);
    if (shadow_cascades_refit(&v->cascades, &s, NULL) != 0) {
        shadow_cascades_refit(&v->cascades, &v->posed, NULL);
        v->pose = v->shown;
        snprintf(v->message, sizeof v->message, "the light's frustum cannot be fitted there: pose kept");
        return;
    }
    v->posed = s, v->shown = v->pose;
    receiver_set_camera(&v->receiver, &s);
    v->mean_irradiance = irradiance_render(&v->irradiance_pass, &s, &v->receiver, &v->mesh, v->irradiance);
    v->pose_id++;
    v->gt_samples = 0;
    gt_worker_ask(&v->worker, v->pose_id, &s, &v->cascades.view);
}


/* The next (dir > 0) or previous value of the selected parameter: its
 * table's tune values, or every choice; a parameter without a list steps
 * through its choices (bool, enum, taps), by one (int) or by a factor 1.25
 * (float) within its range. A value the technique's rules across
 * parameters refuse is not taken. */
static void step_param(struct viewer *v, int dir)
{
    const struct technique *t = viewer_technique(v, 0);
    if (!t->params[0].name) {
        say(v, "%s has no parameters", t->name);
        return;
    }
    const struct technique_param *p = &t->params[v->param];
    void *settings = viewer_settings(v, 0);
    const double now = params_get(p, settings);
    double values[64], next = now;
    int n = params_tune_values(p, values, 64);
    if (n == 0 && p->type != PARAM_FLOAT && p->type != PARAM_INT)  /* every choice */
        n = params_tune_values(&(struct technique_param){.type = p->type, .choices = p->choices, .tune = TUNE_CHOICES},
                               values, 64);
    for (int i = 0; i < n; i++)  /* as the member holds it: 1e-4 as a float is not 1e-4 */
        values[i] = p->type == PARAM_FLOAT ? (double)(float)values[i] : values[i];
    if (n > 0) {
        for (int i = 0; i < n; i++)  /* the nearest listed value beyond now, in dir */
            if ((dir > 0 ? values[i] > now : values[i] < now) &&
                (next == now || (dir > 0 ? values[i] < next : values[i] > next)))
                next = values[i];
    } else if (p->type == PARAM_FLOAT) {
        next = fmin(fmax(now == 0 ? (dir > 0 ? 0.01 : 0) : now * pow(1.25, dir), p->min), p->max);
    } else if (p->type == PARAM_INT) {
        next = fmin(fmax(now + dir, p->min), p->max);
    }
    if (next == now) {
        say(v, "%s.%s: no %s value", t->name, p->name, dir > 0 ? "larger" : "smaller");
        return;
    }
    void *before = memcpy(xmalloc(t->settings_size), settings, t->settings_size);
    params_put(p, settings, next);
    char why[200] = "", text[64];
    if (t->check && t->check(settings, why, sizeof why) != 0) {
        memcpy(settings, before, t->settings_size);
        say(v, "%s.%s: refused (%s)", t->name, p->name, why);
    } else {
        params_value_text(t, settings, p->name, text, sizeof text);
        say(v, "%s.%s = %s", t->name, p->name, text);
    }
    free(before);
}

/* The sun's cascades made again, fitted to the pose in effect, with settings
 * next (their count, or how the PCSS family's widths are taken); refused
 * (the old kept, said) where they cannot be. The ground truth stays: it
 * depends on the pose and the camera's view, not on the cascades. */
static void set_cascades(struct viewer *v, struct cascade_settings next)
{
    const struct cascade_settings *now = &v->cascades.settings;
    if (next.split == CASCADE_SPLIT_FRACTIONS && next.count != now->count) {
        say(v, "cascades: --cascade-split gives %d splits; the count stays %d", now->count - 1, now->count);
        return;
    }
    struct shadow_cascades made;
    if (shadow_cascades_create(&made, &v->posed, &v->cascades_desc, &next) != 0) {
        shadow_cascades_destroy(&made);
        say(v, "cascades: those settings cannot be fitted to this pose (logged): kept");
        return;
    }
    shadow_cascades_destroy(&v->cascades);
    v->cascades = made;
    say(v, "%d cascade%s, widths %s", made.count, made.count > 1 ? "s" : "",
        next.width == CASCADE_WIDTH_TEXEL ? "texel (cascade 0's ratio)" : "world");
}

void viewer_key(struct viewer *v, int key, int mods)
{
    struct scene_orbit *p = &v->pose;
    const int dir = mods & GLFW_MOD_SHIFT ? -1 : 1;
    const float light_step = 0.02f * v->extent, turn_step = 0.05f;
    v->message[0] = 0;
    switch (key) {
    case GLFW_KEY_TAB:
    case GLFW_KEY_B: {
        const int k = key == GLFW_KEY_B;
        const int n = v->d.technique_count;
        v->side[k] = (v->side[k] + dir + n) % n;
        if (k == 0)
            v->param = 0;
        say(v, "%s technique %s", k ? "right" : "left", viewer_technique(v, k)->name);
        break;
    }
    case GLFW_KEY_SPACE:
        v->split = !v->split;
        say(v, "split %s", v->split ? "on" : "off");
        break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4: case GLFW_KEY_5:
        v->mode = (enum view_mode)(key - GLFW_KEY_1);
        say(v, "view %s", view_mode_names[v->mode]);
        break;
    case GLFW_KEY_LEFT: p->light_dx -= light_step, v->pose_dirty = true; break;
    case GLFW_KEY_RIGHT: p->light_dx += light_step, v->pose_dirty = true; break;
    case GLFW_KEY_UP: p->light_dy += light_step, v->pose_dirty = true; break;
    case GLFW_KEY_DOWN: p->light_dy -= light_step, v->pose_dirty = true; break;
    case GLFW_KEY_A: p->yaw -= turn_step, v->pose_dirty = true; break;
    case GLFW_KEY_D: p->yaw += turn_step, v->pose_dirty = true; break;
    case GLFW_KEY_W: p->pitch += turn_step, v->pose_dirty = true; break;
    case GLFW_KEY_S: p->pitch -= turn_step, v->pose_dirty = true; break;
    case GLFW_KEY_Q: p->dolly -= 0.1f, v->pose_dirty = true; break;
    case GLFW_KEY_E: p->dolly += 0.1f, v->pose_dirty = true; break;
    case GLFW_KEY_R: *p = (struct scene_orbit){0}, v->pose_dirty = true; break;
    case GLFW_KEY_LEFT_BRACKET:
    case GLFW_KEY_RIGHT_BRACKET: {
        const struct technique *t = viewer_technique(v, 0);
        int n = 0;
        while (t->params[n].name)
            n++;
        if (n)
            v->param = (v->param + (key == GLFW_KEY_RIGHT_BRACKET ? 1 : n - 1)) % n;
        break;
    }
    case GLFW_KEY_MINUS: step_param(v, -1); break;
    case GLFW_KEY_EQUAL: step_param(v, 1); break;
    case GLFW_KEY_C:
    case GLFW_KEY_V: {
        struct cascade_settings next = v->cascades.settings;
        if (v->base->light.shape != LIGHT_SUN) {
            say(v, "cascades are the sun's: this scene's light has one map");
        } else if (key == GLFW_KEY_C && (next.count + dir < 1 || next.count + dir > CASCADES_MAX)) {
            say(v, "cascades: 1..%d", CASCADES_MAX);
        } else {
            if (key == GLFW_KEY_C)
                next.count += dir;
            else
                next.width = next.width == CASCADE_WIDTH_WORLD ? CASCADE_WIDTH_TEXEL : CASCADE_WIDTH_WORLD;
            set_cascades(v, next);
        }
        break;
    }
    case GLFW_KEY_H: v->overlay = !v->overlay; break;
    case GLFW_KEY_ESCAPE: v->quit = true; break;
    }
}

void viewer_drag(struct viewer *v, float dx, float dy, bool left, bool right, int window_width)
{
    struct scene_orbit *p = &v->pose;
    if (left) {
        p->yaw -= 0.005f * dx, p->pitch -= 0.005f * dy;
        v->pose_dirty = true;
    } else if (right) {
        const float per_pixel = v->extent / (float)(window_width > 0 ? window_width : 1);  /* across the window:
                                                                                            the scene's size */
        p->light_dx += per_pixel * dx, p->light_dy -= per_pixel * dy;
        v->pose_dirty = true;
    }
}

void viewer_scroll(struct viewer *v, double amount)
{
    v->pose.dolly -= 0.1f * (float)amount;
    v->pose_dirty = true;
}

void viewer_free(struct viewer *v)
{
    gt_worker_stop(&v->worker);
    gt_image_free(&v->gt);
    programs_free(&v->programs);
    irradiance_destroy(&v->irradiance_pass);
    glDeleteFramebuffers(1, &v->show_fbo);
    glDeleteTextures(1, &v->show_texture);
    receiver_destroy(&v->receiver);
    shadow_cascades_destroy(&v->cascades);
    scene_mesh_destroy(&v->mesh);
    for (int k = 0; k < 2; k++)
        free(v->v[k]), free(v->distance[k]), free(v->scored[k]);
    free(v->irradiance), free(v->shade);
    picture_free(&v->pic);
    for (int i = 0; i < v->d.technique_count; i++)
        free(v->settings[i]);
}

int viewer_open(struct viewer *v, const struct viewer_desc *d, const struct scene *s)
{
    memset(v, 0, sizeof *v);
    v->d = *d, v->base = s, v->posed = *s;
    v->w = d->width, v->h = d->height;
    for (int i = 0; i < d->technique_count; i++)
        v->settings[i] = memcpy(xmalloc(d->techniques[i]->settings_size), d->settings[i],
                                d->techniques[i]->settings_size);
    v->extent = v3_length(v3_sub(s->bounds_max, s->bounds_min));
    v->overlay = true;
    v->side[1] = d->technique_count > 1 ? 1 : 0;
    const size_t count = (size_t)v->w * (size_t)v->h;
    for (int k = 0; k < 2; k++) {
        v->v[k] = xcalloc(count, sizeof(float));
        v->distance[k] = xcalloc(count, sizeof(float));
        v->scored[k] = xcalloc(count, sizeof(float));
    }
    v->irradiance = xcalloc(count, sizeof(float));
    v->shade = xcalloc(count, sizeof(float));
    if (gt_worker_start(&v->worker, v->w, v->h, d->gt_samples) != 0)
        return -1;
    scene_mesh_upload(s, &v->mesh);
    v->cascades_desc = (struct shadowmap_desc){.size_texels = d->shadow_map_size, .aspect = (float)v->w / (float)v->h};
    if (shadow_cascades_create(&v->cascades, s, &v->cascades_desc, d->cascades) != 0 ||
        receiver_create(&v->receiver, s, v->w, v->h) != 0 ||
        irradiance_create(&v->irradiance_pass, s, v->w, v->h) != 0)
        return -1;
    v->timer = (struct stage_timer){.cascades = &v->cascades, .mesh = &v->mesh, .receiver = &v->receiver, .frames = 1,
                                    .timing = STAGE_TIMING_AUTO};
    v->pose_dirty = true;
    return 0;
}
