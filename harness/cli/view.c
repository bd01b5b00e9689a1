#include "view.h"
#include "base/image.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_window.h"
#include "gl/shader.h"
#include "output/picture.h"
#include "techniques/params.h"
#include "truth/gt_worker.h"

#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---- keys and the script ------------------------------------------------ */

/* The keys the viewer answers to, by the names --script uses. */
static const struct key_name {
    const char *name;
    int key;
} key_names[] = {
    {"TAB", GLFW_KEY_TAB},       {"SPACE", GLFW_KEY_SPACE},
    {"LEFT", GLFW_KEY_LEFT},     {"RIGHT", GLFW_KEY_RIGHT},
    {"UP", GLFW_KEY_UP},         {"DOWN", GLFW_KEY_DOWN},
    {"MINUS", GLFW_KEY_MINUS},   {"EQUAL", GLFW_KEY_EQUAL},
    {"LEFT_BRACKET", GLFW_KEY_LEFT_BRACKET}, {"RIGHT_BRACKET", GLFW_KEY_RIGHT_BRACKET},
    {"ESCAPE", GLFW_KEY_ESCAPE},
};

/* "A".."Z", "0".."9" or a name of key_names, optionally after "shift+". */
static int parse_key(const char *text, int *key, int *mods)
{
    *mods = 0;
    if (strncasecmp(text, "shift+", 6) == 0)
        *mods = GLFW_MOD_SHIFT, text += 6;
    if (text[0] && !text[1] && (isalpha((unsigned char)text[0]) || isdigit((unsigned char)text[0]))) {
        *key = isdigit((unsigned char)text[0]) ? GLFW_KEY_0 + (text[0] - '0')
                                               : GLFW_KEY_A + (toupper((unsigned char)text[0]) - 'A');
        return 0;
    }
    for (size_t i = 0; i < sizeof key_names / sizeof *key_names; i++)
        if (strcasecmp(text, key_names[i].name) == 0) {
            *key = key_names[i].key;
            return 0;
        }
    return -1;
}

struct script_event {
    int frame, key, mods;
};

/* Lines "FRAME KEY" (the key pressed before frame FRAME is drawn, frames
 * counted from 0, in order), blank lines and # comments. Returns the
 * number of events, or -1 (logged). */
static int script_load(const char *path, struct script_event *out, int max)
{
    struct stat st;
    if (stat(path, &st) == 0 && S_ISREG(st.st_mode) && st.st_size > VIEW_MAX_SCRIPT_BYTES) {
        log_error("--script %s: %lld bytes, more than a script of %d events needs (%d at most)", path,
                  (long long)st.st_size, max, VIEW_MAX_SCRIPT_BYTES);
        return -1;
    }
    char *text;
    size_t size;
    int err = util_read_file(path, &text, &size);
    if (err != 0) {
        log_error("--script %s: %s", path, util_read_error(err));
        return -1;
    }
    if (memchr(text, 0, size)) {
        log_error("--script %s: a NUL byte: not a text file", path);
        free(text);
        return -1;
    }
    int n = 0, line = 0, rc = 0;
    for (char *rest = text, *l; !rc && (l = strsep(&rest, "\n"));) {
        line++;
        char *hash = strchr(l, '#');
        if (hash)
            *hash = 0;
        char number[32], key[32], extra[2];
        const int fields = sscanf(l, "%31s %31s %1s", number, key, extra);
        if (fields <= 0)
            continue;  /* blank, or a comment */
        char *end;
        errno = 0;
        const long frame = strtol(number, &end, 10);
        if (fields != 2 || *end || errno || !isdigit((unsigned char)number[0]) || frame > VIEW_MAX_FRAMES) {
            log_error("--script %s:%d: not 'FRAME KEY' with FRAME a whole number in [0, %d] (e.g. '3 TAB')", path,
                      line, VIEW_MAX_FRAMES);
            rc = -1;
        } else if (n && frame < out[n - 1].frame) {
            log_error("--script %s:%d: frame %ld comes before the previous line's %d", path, line, frame,
                      out[n - 1].frame);
            rc = -1;
        } else if (n == max) {
            log_error("--script %s:%d: more than %d events", path, line, max);
            rc = -1;
        } else if (parse_key(key, &out[n].key, &out[n].mods) != 0) {
            struct strbuf names = {0};
            for (size_t i = 0; i < sizeof key_names / sizeof *key_names; i++)
                strbuf_printf(&names, ", %s", key_names[i].name);
            log_error("--script %s:%d: unknown key '%s' (A-Z, 0-9%s; shift+KEY)", path, line, key, names.data);
            strbuf_free(&names);
            rc = -1;
        } else {
            out[n++].frame = (int)frame;
        }
    }
    free(text);
    return rc ? -1 : n;
}

/* ---- the viewer --------------------------------------------------------- */

#define PITCH_MAX 1.4f  /* radians: the orbit stops short of the poles */

enum view_mode { MODE_SHADED, MODE_VTECH, MODE_VGT, MODE_ERROR, MODE_E, MODE_COUNT };
static const char *const mode_names[MODE_COUNT] = {"shaded", "V_tech", "V_gt", "error", "E"};

struct viewer {
    const struct run_options *o;
    const struct scene *base;
    struct scene posed;
    int w, h;
    float extent;  /* the scene's bounding-box diagonal: the unit of motion */
    struct scene_mesh mesh;
    struct shadowmap sm;
    struct receiver receiver;
    struct stage_timer timer;
    struct run_programs programs;

    int side[2];       /* o->techniques indices (what Tab and B step through) of the left (and
                          only) and the right technique */
    int param;         /* the left technique's parameter that - and = step */
    enum view_mode mode;
    bool split, overlay;

    struct view_pose {                 /* relative to the scene's */
        float light_dx, light_dy;      /* the light along its own x and y, world units */
        float yaw, pitch, dolly;       /* the camera's orbit (radians) and log distance */
    } pose, shown;                     /* asked for; in effect */
    unsigned pose_id;                  /* counts the poses put into effect: the ground truth's key */
    bool pose_dirty;

    float *v[2], *distance[2], *scored[2];
    float *irradiance;                 /* E of the pose in effect, -1 where no geometry */
    double mean_irradiance;            /* its mean over the geometry */
    float *shade;                      /* scratch for a view's values */
    struct stage_times times[2];       /* moving averages */
    bool timed[2];
    struct metrics m[2];
    struct gt_image gt;                /* of the current pose when gt_samples > 0 */
    int gt_samples;                    /* 0: none yet, -1: failed */
    struct gt_worker worker;

    GLuint shade_program, shade_fbo, shade_target, shade_depth;
    GLuint show_fbo, show_texture;
    int show_w, show_h;
    struct picture pic;

    double mouse_x, mouse_y;
    char message[200];                 /* the last refusal, shown until the next key */
    bool quit;
};

static const struct technique *side_technique(const struct viewer *v, int k)
{
    return v->o->techniques[v->side[k]];
}

static void *side_settings(const struct viewer *v, int k)
{
    return run_settings(v->o, side_technique(v, k));
}

/* Rodrigues: a turned by angle about the unit axis k. */
static struct vec3 turn(struct vec3 a, struct vec3 k, float angle)
{
    const float c = cosf(angle), s = sinf(angle);
    return v3_add(v3_add(v3_scale(a, c), v3_scale(v3_cross(k, a), s)), v3_scale(k, v3_dot(k, a) * (1 - c)));
}

/* The scene in the viewer's pose: the light moved in its plane, the camera
 * orbiting the point of its axis nearest the scene's centre (yaw, then
 * pitch) and dollied towards or away from it. */
static struct scene posed_scene(const struct viewer *v)
{
    const struct view_pose *p = &v->pose;
    struct scene s = *v->base;
    struct scene_light *L = &s.light;
    L->pos = v3_add(L->pos, v3_add(v3_scale(L->x, p->light_dx), v3_scale(L->y, p->light_dy)));
    if (p->yaw == 0 && p->pitch == 0 && p->dolly == 0)
        return s;  /* the scene's own camera, bit for bit */
    struct scene_camera *c = &s.camera;
    const struct vec3 centre = v3_scale(v3_add(s.bounds_min, s.bounds_max), 0.5f);
    const float along = fmaxf(v3_dot(v3_sub(c->pos, centre), c->z), 1e-3f * v->extent);
    /* yaw about the world's up (glTF's +y), or the camera's own up when it looks along it */
    const struct vec3 target = v3_sub(c->pos, v3_scale(c->z, along));
    const struct vec3 up = fabsf(c->z.y) < 0.99f ? v3(0, 1, 0) : c->y;
    struct vec3 arm = v3_sub(c->pos, target);
    arm = turn(arm, up, p->yaw), c->x = turn(c->x, up, p->yaw), c->y = turn(c->y, up, p->yaw), c->z = turn(c->z, up, p->yaw);
    arm = turn(arm, c->x, p->pitch), c->y = turn(c->y, c->x, p->pitch), c->z = turn(c->z, c->x, p->pitch);
    c->pos = v3_add(target, v3_scale(arm, expf(p->dolly)));
    return s;
}

static int shading_create(struct viewer *v)
{
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);  /* shadow_common.glsl's, for its facing normal */
    strbuf_printf(&defines, "#define SM_LIGHT_SHAPE %d\n", (int)v->base->light.shape);
    v->shade_program = shader_program("view: unshadowed shading", defines.data,
                                      (const struct shader_stage[]){{GL_VERTEX_SHADER, {"receiver.vert"}},
                                                                    {GL_FRAGMENT_SHADER, {"view_shading.frag"}}},
                                      2);
    strbuf_free(&defines);
    if (!v->shade_program)
        return -1;
    v->shade_target = gl_texture_2d(GL_R32F, v->w, v->h, "view: irradiance");
    v->shade_depth = gl_texture_2d(GL_DEPTH_COMPONENT32F, v->w, v->h, "view: irradiance depth");
    glGenFramebuffers(1, &v->shade_fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, v->shade_fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, v->shade_target, 0);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_DEPTH_ATTACHMENT, GL_TEXTURE_2D, v->shade_depth, 0);
    return gl_framebuffer_complete(v->shade_fbo, "view: shading") ? 0 : -1;
}

/* E, the unshadowed shading (shaders/view_shading.frag), of the pose in
 * effect into v->irradiance, and its mean over the geometry. */
static void shading_render(struct viewer *v)
{
    const struct scene_light *L = &v->posed.light;
    const GLuint p = v->shade_program;
    glBindFramebuffer(GL_FRAMEBUFFER, v->shade_fbo);
    glViewport(0, 0, v->w, v->h);
    glClearBufferfv(GL_COLOR, 0, (const float[4]){-1, 0, 0, 0});  /* no geometry */
    glClearBufferfv(GL_DEPTH, 0, (const float[]){0.0f});
    glUseProgram(p);
    glUniformMatrix4fv(glGetUniformLocation(p, "u_camera_view_proj"), 1, GL_FALSE, v->receiver.view_proj.m);
    const struct vec3 cam = v->receiver.camera_pos;
    glUniform3f(glGetUniformLocation(p, "u_camera_pos"), cam.x, cam.y, cam.z);
    glUniform3f(glGetUniformLocation(p, "u_light_pos"), L->pos.x, L->pos.y, L->pos.z);
    glUniform3f(glGetUniformLocation(p, "u_light_x"), L->x.x, L->x.y, L->x.z);
    glUniform3f(glGetUniformLocation(p, "u_light_y"), L->y.x, L->y.y, L->y.z);
    glUniform3f(glGetUniformLocation(p, "u_light_z"), L->z.x, L->z.y, L->z.z);
    glUniform1f(glGetUniformLocation(p, "u_light_half_width"), 0.5f * L->width);
    glUniform1f(glGetUniformLocation(p, "u_light_half_height"), 0.5f * L->height);
    glUniform1f(glGetUniformLocation(p, "u_light_radius"), L->radius);
    glUniform1i(glGetUniformLocation(p, "u_light_disk"), L->shape == LIGHT_DISK);
    scene_mesh_draw(&v->mesh);
    gl_read_red(GL_COLOR_ATTACHMENT0, v->w, v->h, v->irradiance);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);
    double sum = 0;
    long n = 0;
    for (size_t i = 0; i < (size_t)v->w * (size_t)v->h; i++)
        if (v->irradiance[i] >= 0)
            sum += v->irradiance[i], n++;
    v->mean_irradiance = n ? sum / (double)n : 0;
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
static void apply_pose(struct viewer *v)
{
    v->pose_dirty = false;
    /* how far a pose may go: past these, float precision and the ray
     * tracer's range give out */
    struct view_pose *p = &v->pose;
    const struct view_pose asked = *p;
    const float reach = VIEW_LIGHT_REACH * v->extent, dolly = logf(VIEW_DOLLY_REACH);
    p->light_dx = fminf(fmaxf(p->light_dx, -reach), reach), p->light_dy = fminf(fmaxf(p->light_dy, -reach), reach);
    p->dolly = fminf(fmaxf(p->dolly, -dolly), dolly);
    if (memcmp(&asked, p, sizeof asked) != 0)
        say(v, "no farther: the light stays within %g scene sizes, the camera within %gx its distance",
            (double)VIEW_LIGHT_REACH, (double)VIEW_DOLLY_REACH);
    struct scene s = posed_scene(v);
    if (shadowmap_refit(&v->sm, &s, NULL) != 0) {
        shadowmap_refit(&v->sm, &v->posed, NULL);
        v->pose = v->shown;
        snprintf(v->message, sizeof v->message, "the light's frustum cannot be fitted there: pose kept");
        return;
    }
    v->posed = s, v->shown = v->pose;
    receiver_set_camera(&v->receiver, &s);
    shading_render(v);
    v->pose_id++;
    v->gt_samples = 0;
    gt_worker_ask(&v->worker, v->pose_id, &s, &v->sm.frustum);
}


/* The next (dir > 0) or previous value of the selected parameter: its
 * table's tune values, or every choice; a parameter without a list steps
 * through its choices (bool, enum, taps), by one (int) or by a factor 1.25
 * (float) within its range. A value the technique's rules across
 * parameters refuse is not taken. */
static void step_param(struct viewer *v, int dir)
{
    const struct technique *t = side_technique(v, 0);
    if (!t->params[0].name) {
        say(v, "%s has no parameters", t->name);
        return;
    }
    const struct technique_param *p = &t->params[v->param];
    void *settings = side_settings(v, 0);
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

static void on_key(struct viewer *v, int key, int mods)
{
    struct view_pose *p = &v->pose;
    const int dir = mods & GLFW_MOD_SHIFT ? -1 : 1;
    const float light_step = 0.02f * v->extent, turn_step = 0.05f;
    v->message[0] = 0;
    switch (key) {
    case GLFW_KEY_TAB:
    case GLFW_KEY_B: {
        const int k = key == GLFW_KEY_B;
        const int n = v->o->technique_count;
        v->side[k] = (v->side[k] + dir + n) % n;
        if (k == 0)
            v->param = 0;
        say(v, "%s technique %s", k ? "right" : "left", side_technique(v, k)->name);
        break;
    }
    case GLFW_KEY_SPACE:
        v->split = !v->split;
        say(v, "split %s", v->split ? "on" : "off");
        break;
    case GLFW_KEY_1: case GLFW_KEY_2: case GLFW_KEY_3: case GLFW_KEY_4: case GLFW_KEY_5:
        v->mode = (enum view_mode)(key - GLFW_KEY_1);
        say(v, "view %s", mode_names[v->mode]);
        break;
    case GLFW_KEY_LEFT: p->light_dx -= light_step, v->pose_dirty = true; break;
    case GLFW_KEY_RIGHT: p->light_dx += light_step, v->pose_dirty = true; break;
    case GLFW_KEY_UP: p->light_dy += light_step, v->pose_dirty = true; break;
    case GLFW_KEY_DOWN: p->light_dy -= light_step, v->pose_dirty = true; break;
    case GLFW_KEY_A: p->yaw -= turn_step, v->pose_dirty = true; break;
    case GLFW_KEY_D: p->yaw += turn_step, v->pose_dirty = true; break;
    case GLFW_KEY_W: p->pitch = fminf(p->pitch + turn_step, PITCH_MAX), v->pose_dirty = true; break;
    case GLFW_KEY_S: p->pitch = fmaxf(p->pitch - turn_step, -PITCH_MAX), v->pose_dirty = true; break;
    case GLFW_KEY_Q: p->dolly -= 0.1f, v->pose_dirty = true; break;
    case GLFW_KEY_E: p->dolly += 0.1f, v->pose_dirty = true; break;
    case GLFW_KEY_R: *p = (struct view_pose){0}, v->pose_dirty = true; break;
    case GLFW_KEY_LEFT_BRACKET:
    case GLFW_KEY_RIGHT_BRACKET: {
        const struct technique *t = side_technique(v, 0);
        int n = 0;
        while (t->params[n].name)
            n++;
        if (n)
            v->param = (v->param + (key == GLFW_KEY_RIGHT_BRACKET ? 1 : n - 1)) % n;
        break;
    }
    case GLFW_KEY_MINUS: step_param(v, -1); break;
    case GLFW_KEY_EQUAL: step_param(v, 1); break;
    case GLFW_KEY_H: v->overlay = !v->overlay; break;
    case GLFW_KEY_ESCAPE: v->quit = true; break;
    }
}

static void key_callback(GLFWwindow *win, int key, int scancode, int action, int mods)
{
    (void)scancode;
    if (action == GLFW_PRESS || action == GLFW_REPEAT)
        on_key(glfwGetWindowUserPointer(win), key, mods);
}

/* Left drag orbits the camera, right drag moves the light, the wheel dollies. */
static void cursor_callback(GLFWwindow *win, double x, double y)
{
    struct viewer *v = glfwGetWindowUserPointer(win);
    const float dx = (float)(x - v->mouse_x), dy = (float)(y - v->mouse_y);
    v->mouse_x = x, v->mouse_y = y;
    struct view_pose *p = &v->pose;
    if (glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_LEFT) == GLFW_PRESS) {
        p->yaw -= 0.005f * dx, p->pitch = fminf(fmaxf(p->pitch - 0.005f * dy, -PITCH_MAX), PITCH_MAX);
        v->pose_dirty = true;
    } else if (glfwGetMouseButton(win, GLFW_MOUSE_BUTTON_RIGHT) == GLFW_PRESS) {
        int width, height;
        glfwGetWindowSize(win, &width, &height);
        const float per_pixel = v->extent / (float)(width > 0 ? width : 1);  /* across the window: the scene's size */
        p->light_dx += per_pixel * dx, p->light_dy -= per_pixel * dy;
        v->pose_dirty = true;
    }
}

static void scroll_callback(GLFWwindow *win, double xoff, double yoff)
{
    (void)xoff;
    struct viewer *v = glfwGetWindowUserPointer(win);
    v->pose.dolly -= 0.1f * (float)yoff;
    v->pose_dirty = true;
}

/* ---- a frame ------------------------------------------------------------ */

/* One frame of side k's technique, timed as the harness times a cell (its
 * products rendered afresh, then the receiver pass), read back. */
static int render_side(struct viewer *v, int k)
{
    const struct technique *t = side_technique(v, k);
    const void *settings = side_settings(v, k);
    GLuint program = run_program_get(&v->programs, t, settings, v->posed.light.shape);
    struct stage_times now;
    if (!program ||
        stage_timer_run(&v->timer, &(struct stage_timer_cell){t, settings, program}, 1, &now) != 0)
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
        const size_t count = (size_t)v->w * (size_t)v->h;
        v->m[k] = (struct metrics){0};
        v->m[k].mismatch_pixels = metrics_score_mask(v->gt.mask, v->gt.distance, v->distance[k], (int)count, v->scored[k]);
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
        const float exposure = mean > 0 ? (float)(1.0 / (VIEW_WHITE * mean)) : 1.0f;
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
    const struct technique *a = side_technique(v, 0), *b = side_technique(v, 1);
    strbuf_printf(&lines[n++], "%s%s%s   view %s (1-5)   %s", a->name, v->split ? " | " : "",
                  v->split ? b->name : "", mode_names[v->mode], v->split ? "split (Space)" : "Tab: technique");
    for (int i = 0; a->params[i].name && n < 40; i++) {
        char text[64];
        params_value_text(a, side_settings(v, 0), a->params[i].name, text, sizeof text);
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
                          v->gt_samples, v->o->gt_samples);
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

/* The picture to the window, scaled to fit and centred. */
static void present(struct viewer *v, GLFWwindow *win)
{
    const struct picture *p = &v->pic;
    if (p->width != v->show_w || p->height != v->show_h) {
        glDeleteTextures(1, &v->show_texture);
        glDeleteFramebuffers(1, &v->show_fbo);
        v->show_texture = gl_texture_2d(GL_RGB8, p->width, p->height, "view: the window's picture");
        glGenFramebuffers(1, &v->show_fbo);
        glBindFramebuffer(GL_FRAMEBUFFER, v->show_fbo);
        glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, v->show_texture, 0);
        glBindFramebuffer(GL_FRAMEBUFFER, 0);
        v->show_w = p->width, v->show_h = p->height;
    }
    glBindTexture(GL_TEXTURE_2D, v->show_texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexSubImage2D(GL_TEXTURE_2D, 0, 0, 0, p->width, p->height, GL_RGB, GL_UNSIGNED_BYTE, p->rgb);
    int fw, fh;
    glfwGetFramebufferSize(win, &fw, &fh);
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

/* The window's back buffer (what the next swap shows) as a PNG. */
static int screenshot(GLFWwindow *win, const char *path)
{
    int fw, fh;
    glfwGetFramebufferSize(win, &fw, &fh);
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

static void viewer_free(struct viewer *v)
{
    gt_worker_stop(&v->worker);
    gt_image_free(&v->gt);
    run_programs_free(&v->programs);
    glDeleteProgram(v->shade_program);
    glDeleteFramebuffers(1, &v->shade_fbo);
    glDeleteFramebuffers(1, &v->show_fbo);
    GLuint textures[] = {v->shade_target, v->shade_depth, v->show_texture};
    glDeleteTextures(3, textures);
    receiver_destroy(&v->receiver);
    shadowmap_destroy(&v->sm);
    scene_mesh_destroy(&v->mesh);
    for (int k = 0; k < 2; k++)
        free(v->v[k]), free(v->distance[k]), free(v->scored[k]);
    free(v->irradiance), free(v->shade);
    picture_free(&v->pic);
}

static int viewer_open(struct viewer *v, const struct run_options *o, const struct scene *s)
{
    v->o = o, v->base = s, v->posed = *s;
    v->w = o->width, v->h = o->height;
    v->extent = v3_length(v3_sub(s->bounds_max, s->bounds_min));
    v->overlay = true;
    v->side[1] = o->technique_count > 1 ? 1 : 0;
    const size_t count = (size_t)v->w * (size_t)v->h;
    for (int k = 0; k < 2; k++) {
        v->v[k] = xcalloc(count, sizeof(float));
        v->distance[k] = xcalloc(count, sizeof(float));
        v->scored[k] = xcalloc(count, sizeof(float));
    }
    v->irradiance = xcalloc(count, sizeof(float));
    v->shade = xcalloc(count, sizeof(float));
    if (gt_worker_start(&v->worker, v->w, v->h, o->gt_samples) != 0)
        return -1;
    scene_mesh_upload(s, &v->mesh);
    if (shadowmap_create(&v->sm, s, &(struct shadowmap_desc){.size_texels = o->shadow_map_size}) != 0 ||
        receiver_create(&v->receiver, s, v->w, v->h) != 0 || shading_create(v) != 0)
        return -1;
    v->timer = (struct stage_timer){.sm = &v->sm, .mesh = &v->mesh, .receiver = &v->receiver, .frames = 1,
                                    .timing = STAGE_TIMING_AUTO};
    v->pose_dirty = true;
    return 0;
}

/* A screenshot's path, checked before the window opens: a file name in a
 * writable folder, and nothing there yet but a regular file (the PNG
 * replaces what is there: a device, a FIFO or a link would be lost). */
static int check_screenshot_path(const char *path)
{
    struct stat st;
    const size_t len = strlen(path);
    const char *why = !len                                       ? "an empty file name"
                      : path[len - 1] == '/' || util_is_dir(path) ? "a folder, not a file"
                      : lstat(path, &st) == 0 && !S_ISREG(st.st_mode)
                          ? "not a regular file (a device, FIFO or link is not replaced)"
                          : NULL;
    if (why) {
        log_error("--screenshot %s: %s", path, why);
        return -1;
    }
    const char *slash = strrchr(path, '/');
    char *dir = slash ? util_printf("%.*s", slash == path ? 1 : (int)(slash - path), path) : xstrdup(".");
    const bool ok = util_is_dir(dir) && access(dir, W_OK) == 0;
    if (!ok)
        log_error("--screenshot %s: %s is not a writable folder", path, dir);
    free(dir);
    return ok ? 0 : -1;
}

int view_main(const struct run_options *o)
{
    static struct script_event script[VIEW_MAX_SCRIPT];
    int events = 0;
    if (o->script && (events = script_load(o->script, script, VIEW_MAX_SCRIPT)) < 0)
        return EXIT_USAGE;
    if (events && o->frames && script[events - 1].frame >= o->frames) {  /* it would never be pressed */
        log_error("--script %s: a key at frame %d, past the last of --frames %d (frames count from 0)", o->script,
                  script[events - 1].frame, o->frames);
        return EXIT_USAGE;
    }
    if (o->screenshot && check_screenshot_path(o->screenshot) != 0)
        return EXIT_USAGE;
    struct scene s;
    int scene_count = 0;
    if (run_load_scenes(o, &s, &scene_count) != 0)
        return EXIT_USAGE;
    if (shader_init(o->shader_dir) != 0) {
        scene_free(&s);
        return EXIT_USAGE;
    }
    char *title = util_printf("shadowbench view: %s", s.name);
    gl_window_request(o->width, o->height, title);
    if (gl_context_create(GL_BACKEND_GLFW) != 0) {
        free(title);
        scene_free(&s);
        return EXIT_USAGE;
    }
    GLFWwindow *win = gl_window();
    glfwSwapInterval(o->screenshot ? 0 : 1);
    log_info("view: %s, %d x %d, OpenGL %s; keys: shadowbench view --help", s.name, o->width, o->height,
             gl_context_renderer());

    static struct viewer v;  /* large; one per process */
    memset(&v, 0, sizeof v);
    int status = viewer_open(&v, o, &s) == 0 ? EXIT_OK : EXIT_CHECK_FAILED;
    glfwSetWindowUserPointer(win, &v);
    glfwSetKeyCallback(win, key_callback);
    glfwSetCursorPosCallback(win, cursor_callback);
    glfwSetScrollCallback(win, scroll_callback);
    glfwGetCursorPos(win, &v.mouse_x, &v.mouse_y);

    const int frames = o->frames;  /* 0: until the window closes */
    int next_event = 0;
    for (int frame = 0; status == EXIT_OK && (frames == 0 || frame < frames); frame++) {
        glfwPollEvents();
        for (; next_event < events && script[next_event].frame <= frame; next_event++)
            on_key(&v, script[next_event].key, script[next_event].mods);
        if (v.quit || glfwWindowShouldClose(win)) {
            if (o->screenshot) {
                log_error("view: closed before frame %d of %d: %s not written", frame + 1, frames, o->screenshot);
                status = EXIT_CHECK_FAILED;
            }
            break;
        }
        if (v.pose_dirty)
            apply_pose(&v);
        /* the screenshot's frame waits for the pose's finished ground truth,
         * so that what it shows does not depend on the machine's speed */
        const bool last = frames && frame == frames - 1;
        const int got = gt_worker_take(&v.worker, v.pose_id, last && o->screenshot, &v.gt);
        if (got)
            v.gt_samples = got;
        for (int k = 0; k <= (int)v.split && status == EXIT_OK; k++)
            if (render_side(&v, k) != 0)
                status = EXIT_CHECK_FAILED;
        if (status != EXIT_OK)
            break;
        compose(&v);
        present(&v, win);
        if (last && o->screenshot)
            status = screenshot(win, o->screenshot) == 0 ? EXIT_OK : EXIT_CHECK_FAILED;
        glfwSwapBuffers(win);
    }
    if (status == EXIT_OK) {
        char score[160];
        if (v.gt_samples <= 0)
            snprintf(score, sizeof score, "%s", v.gt_samples < 0 ? "the ground truth failed" : "no ground truth yet");
        else if (v.m[0].scored_pixels == 0)
            snprintf(score, sizeof score, "no pixel scored (V_gt %d spp)", v.gt_samples);
        else
            snprintf(score, sizeof score, "rmse %.6f, penumbra_rmse %.6f (V_gt %d spp)", v.m[0].rmse,
                     v.m[0].penumbra_rmse, v.gt_samples);
        log_info("view: %s, view %s%s%s: %s, mean E %.6g", side_technique(&v, 0)->name, mode_names[v.mode],
                 v.split ? ", right " : "", v.split ? side_technique(&v, 1)->name : "", score, v.mean_irradiance);
    }
    viewer_free(&v);
    gl_context_destroy();
    free(title);
    scene_free(&s);
    return status;
}
