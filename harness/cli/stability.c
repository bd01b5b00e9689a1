/* shadowbench stability: motions (flicker) and variations (break points).
 * See stability.h for what it measures; README.md, "Stability", for how to
 * read it. */
#include "stability.h"
#include "base/log.h"
#include "base/image.h"
#include "base/util.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "output/chart.h"
#include "output/picture.h"
#include "output/report.h"
#include "render/receiver.h"
#include "scene/pose.h"
#include "score/flicker.h"
#include "score/metrics.h"
#include "techniques/params.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_VALUES 32

enum motion_kind {
#define X(id, name, unit, def, max, help) MOTION_##id,
    STABILITY_MOTIONS(X)
#undef X
    MOTION_KIND_COUNT
};

static const struct {
    const char *name, *unit;
    double def, max;
} motion_kinds[] = {
#define X(id, name, unit, def, max, help) {name, unit, def, max},
    STABILITY_MOTIONS(X)
#undef X
};

enum variable_kind {
#define X(id, name, ref, lo, hi, help) VARY_##id,
    STABILITY_VARIABLES(X)
#undef X
    VARY_PARAM,  /* a technique parameter: T.P */
};

static const struct {
    const char *name;
    double reference, lo, hi;
} variables[] = {
#define X(id, name, ref, lo, hi, help) {name, ref, lo, hi},
    STABILITY_VARIABLES(X)
#undef X
};

struct motion {
    enum motion_kind kind;
    double step;      /* in the kind's unit */
    char node[65];    /* caster_shift: the name of the node it moves */
    int scene, entry; /* the scene whose extras.shadowbench.motions[entry] it is, or -1: --motion */
    char name[80];    /* "light_shift", "caster_shift:sphere" */
    char label[128];  /* "light_shift=0.125", "caster_shift:sphere=0.25": its folder, each
                         character outside [A-Za-z0-9_.:=+-] as '_' */
};

struct variation {
    enum variable_kind kind;
    const struct technique *t;       /* VARY_PARAM: the technique and its parameter */
    const struct technique_param *p;
    char name[96];                   /* "shadow_map_size", "pcf.radius_texels" */
    int count;
    double values[MAX_VALUES];       /* increasing; VARY_PARAM enum/bool: the index */
    char *texts[MAX_VALUES];         /* as given (VARY_PARAM: for params_set) */
    int reference;                   /* the index of the reference value */
    bool log_x;                      /* the values span decades: a log axis */
};

/* One line of the motion results: a technique with its noise still or
 * animated, per frame or accumulated, on one scene and motion. */
struct motion_row {
    int scene, motion;
    const struct technique *t;
    bool animated, accumulated;
    char label[64];  /* "pcf", "pcf+ema", "pcf~anim", "pcf~anim+ema": its folder */
    struct flicker_result r;
    long nonfinite;  /* NaN/Inf values over the frames */
};

/* One point of a variation: a technique at one value on one scene. */
struct vary_point {
    int scene, variation, value;
    const struct technique *t;
    struct metrics m;
    bool broken;
};

struct stab {
    const struct run_options *o;
    struct scene *scenes;
    int scene_count;
    struct motion *motions;
    int motion_count;
    struct variation vars[RUN_MAX_VARIES];
    int var_count;
    struct run_programs programs;
    struct motion_row *rows;
    int row_count;
    struct vary_point *points;
    int point_count;
    cJSON *charts;  /* the names of the charts written, for stability.json */
};

static int technique_group(const struct technique *t)
{
    int i = 0;
    while (technique_list[i] != t)
        i++;
    return i;
}

/* ---- the command line --------------------------------------------------- */

static int parse_number(const char *what, const char *text, double *out)
{
    char *end;
    errno = 0;
    *out = strtod(text, &end);
    if (!*text || *end || errno == ERANGE || !isfinite(*out)) {
        log_error("%s: '%s' is not a finite number", what, text);
        return -1;
    }
    return 0;
}

/* Parses spec, NAME[:NODE][=STEP], into m: a --motion (scene -1) or scene
 * `scene`'s extras.shadowbench.motions[entry]; what names it in errors. */
static int parse_motion(const char *what, const char *spec, int scene, int entry, struct motion *m)
{
    memset(m, 0, sizeof *m);
    m->scene = scene, m->entry = entry;
    const char *colon = strchr(spec, ':'), *eq = strrchr(spec, '=');
    if (eq && colon && eq < colon)  /* NAME=...:... : the ':' is the step's */
        colon = NULL;
    const size_t len = colon ? (size_t)(colon - spec) : eq ? (size_t)(eq - spec) : strlen(spec);
    int k = 0;
    while (k < MOTION_KIND_COUNT && !(strlen(motion_kinds[k].name) == len && !strncmp(spec, motion_kinds[k].name, len)))
        k++;
    if (k == MOTION_KIND_COUNT) {
        struct strbuf known = {0};
        for (int i = 0; i < MOTION_KIND_COUNT; i++)
            strbuf_list_printf(&known, ", ", "%s", motion_kinds[i].name);
        log_error("%s: '%s' is not a motion (motions: %s; see --help)", what, spec, known.data);
        strbuf_free(&known);
        return -1;
    }
    m->kind = (enum motion_kind)k;
    m->step = motion_kinds[k].def;
    if ((k == MOTION_CASTER_SHIFT) != (colon != NULL)) {
        log_error("%s: '%s': %s", what, spec, colon ? "only caster_shift names a node (NAME:NODE)"
                                                    : "caster_shift names the node it moves: caster_shift:NODE[=STEP]");
        return -1;
    }
    if (colon) {
        const size_t n = (eq ? (size_t)(eq - colon) : strlen(colon)) - 1;
        if (n == 0 || n >= sizeof m->node) {
            log_error("%s: '%s': a node's name is 1 to %zu bytes", what, spec, sizeof m->node - 1);
            return -1;
        }
        memcpy(m->node, colon + 1, n);
    }
    if (eq && k == MOTION_STATIC) {
        log_error("%s: '%s': static takes no step", what, spec);
        return -1;
    }
    if (eq && parse_number(what, eq + 1, &m->step) != 0)
        return -1;
    if (k != MOTION_STATIC && !(m->step != 0 && fabs(m->step) <= motion_kinds[k].max)) {
        log_error("%s: '%s': the step must be non-zero and at most %g %s in size", what, spec, motion_kinds[k].max,
                  motion_kinds[k].unit);
        return -1;
    }
    snprintf(m->name, sizeof m->name, "%s%s%s", motion_kinds[k].name, colon ? ":" : "", m->node);
    if (k == MOTION_STATIC)
        snprintf(m->label, sizeof m->label, "static");
    else
        snprintf(m->label, sizeof m->label, "%s=%g", m->name, m->step);
    for (char *c = m->label; *c; c++)  /* the label is a folder's name */
        if (!(isalnum((unsigned char)*c) || strchr("_.:=+-", *c)))
            *c = '_';
    return 0;
}

/* Whether motion m runs on scene s. */
static bool motion_on(const struct motion *m, int s) { return m->scene < 0 || m->scene == s; }

/* Adds m to st's motions unless an equal one already runs on the scenes m
 * runs on: a motion given twice on the command line or in one scene's
 * list is an error; a scene's motion that the command line (or the
 * default) gives already runs once. Two different motions whose folder
 * names (labels) agree are an error. Returns 0 or -1 (logged). */
static int add_motion(struct stab *st, const struct motion *m)
{
    for (int j = 0; j < st->motion_count; j++) {
        const struct motion *o = &st->motions[j];
        if (m->scene >= 0 && !motion_on(o, m->scene))
            continue;
        const bool same = o->kind == m->kind && o->step == m->step && !strcmp(o->node, m->node);
        if (same && o->scene < 0 && m->scene >= 0)
            return 0;  /* run already */
        if (same || !strcmp(o->label, m->label)) {
            if (m->scene < 0)
                log_error("--motion: %s %s", m->label, same ? "is given twice" : "names the same folder as another");
            else
                log_error("%s: extras.shadowbench.motions[%d]: %s %s", st->scenes[m->scene].path, m->entry, m->label,
                          same ? "is listed twice" : "names the same folder as another motion");
            return -1;
        }
    }
    st->motions[st->motion_count++] = *m;
    return 0;
}

/* The node each caster motion moves, found in every scene it runs on.
 * Returns 0 or -1 (logged). */
static int check_motion_nodes(const struct stab *st)
{
    for (int m = 0; m < st->motion_count; m++)
        for (int s = 0; s < st->scene_count; s++) {
            const struct motion *mo = &st->motions[m];
            const struct scene *sc = &st->scenes[s];
            int count;
            if (mo->kind != MOTION_CASTER_SHIFT || !motion_on(mo, s))
                continue;
            const int node = pose_find_node(sc, mo->node, &count);
            if (node >= 0 && !(pose_light_depth_of_node(sc, node) > 0)) {
                log_error("%s: %s: %s's node '%s' has its centre behind the light's plane, where a texel has no size "
                          "to step by", mo->scene < 0 ? "--motion" : sc->path, mo->label, sc->name, mo->node);
                return -1;
            }
            if (node >= 0)
                continue;
            struct strbuf names = {0};
            int listed = 0;
            for (size_t i = 0; i < sc->node_count; i++)
                if (*sc->nodes[i].name && listed++ < 16)
                    strbuf_list_printf(&names, ", ", "%s", sc->nodes[i].name);
            if (listed > 16)
                strbuf_printf(&names, " and %d more", listed - 16);
            char *source = mo->scene < 0 ? xstrdup("--motion")
                                         : util_printf("%s: extras.shadowbench.motions[%d]", sc->path, mo->entry);
            log_error("%s: %s: %s %s named '%s' (its nodes with geometry: %s)", source, mo->label, sc->name,
                      count ? "has more than one node" : "has no node with geometry", mo->node,
                      names.len ? names.data : "none named");
            free(source);
            strbuf_free(&names);
            return -1;
        }
    return 0;
}

static void sort_values(struct variation *v)
{
    for (int i = 1; i < v->count; i++)  /* insertion sort: a handful of values */
        for (int j = i; j > 0 && v->values[j - 1] > v->values[j]; j--) {
            double d = v->values[j];
            v->values[j] = v->values[j - 1], v->values[j - 1] = d;
            char *t = v->texts[j];
            v->texts[j] = v->texts[j - 1], v->texts[j - 1] = t;
        }
}

static void variation_free(struct variation *v);

static int parse_vary(const struct run_options *o, const char *spec, struct variation *v)
{
    memset(v, 0, sizeof *v);
    const char *eq = strchr(spec, '=');
    if (!eq || eq == spec || !eq[1]) {
        log_error("--vary: '%s' is not NAME=V1,V2,... (see --help)", spec);
        return -1;
    }
    snprintf(v->name, sizeof v->name, "%.*s", (int)(eq - spec), spec);
    void *work = NULL;  /* VARY_PARAM: the technique's settings, for checking each value */
    double reference = NAN;
    const char *dot = strchr(v->name, '.');
    if (dot) {
        char tech[64];
        snprintf(tech, sizeof tech, "%.*s", (int)(dot - v->name), v->name);
        v->kind = VARY_PARAM;
        v->t = technique_find(tech);
        if (!v->t) {
            log_error("--vary: unknown technique '%s' (see 'shadowbench list')", tech);
            return -1;
        }
        bool selected = false;
        for (int i = 0; i < o->technique_count; i++)
            selected |= o->techniques[i] == v->t;
        if (!selected) {
            log_error("--vary: %s is not among the techniques selected with --technique", v->t->name);
            return -1;
        }
        for (const struct technique_param *p = v->t->params; p->name && !v->p; p++)
            if (strcmp(p->name, dot + 1) == 0)
                v->p = p;
        if (!v->p) {
            log_error("--vary: %s has no parameter '%s' (see 'shadowbench list')", v->t->name, dot + 1);
            return -1;
        }
        const void *base = run_settings(o, v->t);
        work = memcpy(xmalloc(v->t->settings_size), base, v->t->settings_size);
        reference = params_get(v->p, base);
    } else {
        int k = 0;
        while (k < VARY_PARAM && strcmp(variables[k].name, v->name) != 0)
            k++;
        if (k == VARY_PARAM) {
            struct strbuf known = {0};
            for (int i = 0; i < VARY_PARAM; i++)
                strbuf_list_printf(&known, ", ", "%s", variables[i].name);
            log_error("--vary: '%s' is neither %s nor a technique parameter T.P", v->name, known.data);
            strbuf_free(&known);
            return -1;
        }
        v->kind = (enum variable_kind)k;
        reference = k == VARY_MAP_SIZE ? o->shadow_map_size : variables[k].reference;
    }
    char *copy = xstrdup(eq + 1), *rest = copy;
    int rc = 0;
    for (char *text = strsep(&rest, ","); text && !rc; text = strsep(&rest, ",")) {
        double value = 0;
        if (!*text) {
            log_error("--vary %s: an empty value in '%s'", v->name, eq + 1);
            rc = -1;
        } else if (v->count == MAX_VALUES - 1) {  /* room for the reference */
            log_error("--vary %s: at most %d values", v->name, MAX_VALUES - 1);
            rc = -1;
        } else if (v->kind == VARY_PARAM) {
            rc = params_set(v->t, work, v->p->name, text);
            value = rc ? 0 : params_get(v->p, work);
        } else if ((rc = parse_number(v->name, text, &value)) == 0) {
            const bool whole = v->kind != VARY_MAP_SIZE || value == floor(value);
            if (!whole || value < variables[v->kind].lo || value > variables[v->kind].hi) {
                log_error("--vary %s: %s is out of range [%g, %g]%s", v->name, text, variables[v->kind].lo,
                          variables[v->kind].hi, whole ? "" : " or not a whole number");
                rc = -1;
            }
        }
        for (int i = 0; i < v->count && !rc; i++)
            if (v->values[i] == value) {
                log_error("--vary %s: %s is listed twice", v->name, text);
                rc = -1;
            }
        if (!rc) {
            v->texts[v->count] = xstrdup(text);
            v->values[v->count++] = value;
        }
    }
    free(copy);
    /* The reference value is always measured: breaks are counted from it. */
    bool has_reference = false;
    for (int i = 0; i < v->count; i++)
        has_reference |= v->values[i] == reference;
    if (!rc && !has_reference) {
        if (v->kind == VARY_PARAM)
            v->texts[v->count] = xmalloc(64), params_value_text(v->t, run_settings(o, v->t), v->p->name,
                                                                v->texts[v->count], 64);
        else
            v->texts[v->count] = util_printf("%g", reference);
        v->values[v->count++] = reference;
    }
    free(work);
    if (rc) {
        variation_free(v);
        return -1;
    }
    sort_values(v);
    for (int i = 0; i < v->count; i++)
        if (v->values[i] == reference)
            v->reference = i;
    const bool numeric = v->kind != VARY_PARAM || v->p->type == PARAM_FLOAT || v->p->type == PARAM_INT ||
                         v->p->type == PARAM_TAPS;
    v->log_x = numeric && v->values[0] > 0 && v->values[v->count - 1] / v->values[0] >= 8;
    return 0;
}

static void variation_free(struct variation *v)
{
    for (int i = 0; i < v->count; i++)
        free(v->texts[i]);
    v->count = 0;
}

/* ---- motion ------------------------------------------------------------- */

/* The pose of frame `frame` of motion m on scene s, whose map is map_size
 * texels and whose image is height pixels high; node: the node a caster
 * motion moves. */
static struct scene_pose motion_pose(const struct motion *m, const struct scene *s, const struct light_frustum *f,
                                     int map_size, int height, int node, int frame)
{
    struct scene_pose p = {0};
    const double amount = m->step * frame;
    switch (m->kind) {
    case MOTION_STATIC: break;
    case MOTION_LIGHT_SHIFT:
        p.light_shift = (float)amount * pose_texel_world(f->r - f->l, f->near_world, map_size,
                                                         pose_light_depth_of_centre(s));
        break;
    case MOTION_LIGHT_ROTATE: p.light_turn_rad = (float)(amount * M_PI / 180); break;
    case MOTION_CAMERA_SHIFT: p.camera_shift = (float)amount * pose_pixel_world(s, height); break;
    case MOTION_CASTER_SHIFT:
        p.caster = node + 1;
        p.caster_shift = (float)amount * pose_texel_world(f->r - f->l, f->near_world, map_size,
                                                          pose_light_depth_of_node(s, node));
        break;
    case MOTION_KIND_COUNT: break;
    }
    return p;
}

/* from[i]: the pixel of the last frame (camera prev) that pixel i of this
 * frame (camera now) sees, or -1: the accumulation's reprojection, from
 * the GL camera distances (-1 where no geometry). A pixel whose point the
 * last frame saw at another distance (it was hidden, or is new) has none. */
static void reproject(const struct scene_camera *now, const struct scene_camera *prev, const float *dist_now,
                      const float *dist_prev, int w, int h, int *from)
{
    const float ty = tanf(0.5f * now->yfov_rad), tx = ty * (float)w / (float)h;
    const float py_ = tanf(0.5f * prev->yfov_rad), px_ = py_ * (float)w / (float)h;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const int i = y * w + x;
            from[i] = -1;
            if (dist_now[i] < 0)
                continue;
            const float sx = (2 * (x + 0.5f) / (float)w - 1) * tx, sy = (1 - 2 * (y + 0.5f) / (float)h) * ty;
            const struct vec3 dir = v3_normalize(
                v3_add(v3_scale(now->z, -1), v3_add(v3_scale(now->x, sx), v3_scale(now->y, sy))));
            const struct vec3 q = v3_sub(v3_add(now->pos, v3_scale(dir, dist_now[i])), prev->pos);
            const float qz = -v3_dot(q, prev->z);
            if (!(qz > 0))
                continue;
            const float fx = (v3_dot(q, prev->x) / qz / px_ + 1) * 0.5f * (float)w;
            const float fy = (1 - v3_dot(q, prev->y) / qz / py_) * 0.5f * (float)h;
            if (!(fx >= 0 && fx < (float)w && fy >= 0 && fy < (float)h))
                continue;
            const int j = (int)fy * w + (int)fx;
            const float expected = v3_length(q);
            if (dist_prev[j] >= 0 && fabsf(dist_prev[j] - expected) <= 1e-2f * expected)
                from[i] = j;
        }
}

/* A strip of K frames side by side, each a picture w x ph. */
struct strip {
    int w, ph, frames;
    uint8_t *rgb;
};

static void strip_put(struct strip *s, const struct picture *p, int frame, int frames)
{
    if (!s->rgb) {
        s->w = p->width, s->ph = p->height, s->frames = frames;
        s->rgb = xcalloc((size_t)s->w * (size_t)frames * (size_t)s->ph * 3, 1);
    }
    for (int y = 0; y < s->ph; y++)
        memcpy(s->rgb + ((size_t)y * (size_t)(s->w * s->frames) + (size_t)frame * s->w) * 3,
               p->rgb + (size_t)y * s->w * 3, (size_t)s->w * 3);
}

static int strip_write(struct strip *s, const char *path)
{
    int rc = image_write_png(path, s->w * s->frames, s->ph, s->rgb);
    free(s->rgb);
    memset(s, 0, sizeof *s);
    return rc;
}

/* A motion row while its frames are rendered. */
struct live_row {
    struct motion_row *row;
    GLuint program;
    const void *settings;
    int source;              /* accumulated: the live row whose V it averages */
    float *v, *history, *prev_history;
    struct flicker fl;
    struct strip vis, err;
};

static int motion_scene(struct stab *st, int scene_index, int motion_index)
{
    const struct run_options *o = st->o;
    const struct scene *base = &st->scenes[scene_index];
    const struct motion *mo = &st->motions[motion_index];
    const int w = o->width, h = o->height, K = o->frames;
    const size_t count = (size_t)w * (size_t)h;
    struct light_frustum f0;
    if (light_frustum_fit(base, &f0) != 0)
        return -1;
    int node = -1;
    if (mo->kind == MOTION_CASTER_SHIFT)
        node = pose_find_node(base, mo->node, NULL);  /* found: check_motion_nodes */

    /* The rows: every technique per frame with its noise still; animated
     * too where its program reads the frame index; each also accumulated. */
    struct live_row *live = xcalloc((size_t)o->technique_count * 4, sizeof *live);
    int n = 0;
    for (int i = 0; i < o->technique_count; i++) {
        const struct technique *t = o->techniques[i];
        const void *settings = run_settings(o, t);
        GLuint program = run_program_get(&st->programs, t, settings, base->light.shape);
        if (!program) {
            free(live);
            return -1;
        }
        const bool noisy = receiver_program_animated(program);
        for (int animated = 0; animated <= (int)noisy; animated++)
            for (int acc = 0; acc <= 1; acc++) {
                st->rows = xrealloc(st->rows, sizeof *st->rows * (size_t)(st->row_count + 1));
                struct motion_row *r = &st->rows[st->row_count++];
                *r = (struct motion_row){.scene = scene_index, .motion = motion_index, .t = t,
                                         .animated = animated, .accumulated = acc};
                snprintf(r->label, sizeof r->label, "%s%s%s", t->name, animated ? "~anim" : "", acc ? "+ema" : "");
                live[n] = (struct live_row){.program = program, .settings = settings, .source = acc ? n - 1 : -1,
                                            .v = xmalloc(sizeof(float) * count)};
                if (acc)
                    live[n].history = xmalloc(sizeof(float) * count), live[n].prev_history = xmalloc(sizeof(float) * count);
                n++;
            }
    }
    /* rows may have moved: point the live rows at theirs now */
    for (int k = 0; k < n; k++)
        live[k].row = &st->rows[st->row_count - n + k];

    struct scene posed;
    struct scene_setup ss;
    scene_posed(base, &(struct scene_pose){0}, &posed);
    struct scene_camera prev_camera = posed.camera;
    int rc = scene_setup_open(&ss, &posed,
                              &(struct scene_setup_desc){w, h, o->shadow_map_size, o->gt_samples, 0, o->cache_dir, 0});
    /* A light's motion moves the map's texel grid with it (a spot light's
     * map is its view): the angular window stays frame 0's. So does a
     * caster's: the map does not follow the geometry. */
    const struct light_frustum window = ss.sm.frustum;
    int *from = xmalloc(sizeof(int) * count);
    float *prev_distance = xmalloc(sizeof(float) * count);
    struct picture pic = {0};
    char where[640];  /* the posed scene's "path": its errors name the motion and frame */
    for (int frame = 0; frame < K && !rc; frame++) {
        if (frame > 0 && mo->kind != MOTION_STATIC) {
            prev_camera = posed.camera;
            scene_unpose(&posed, base);
            const struct scene_pose p = motion_pose(mo, base, &f0, o->shadow_map_size, h, node, frame);
            scene_posed(base, &p, &posed);
            snprintf(where, sizeof where, "%s (motion %s, frame %d)", base->path, mo->label, frame);
            posed.path = where;
            receiver_set_camera(&ss.receiver, &posed);
            if (p.caster)
                scene_mesh_update_positions(&posed, &ss.mesh);
            gt_image_free(&ss.gt);
            rc = shadowmap_refit(&ss.sm, &posed, &window) ||
                 gt_obtain(&posed, &ss.sm.frustum,
                           &(struct gt_desc){.width = w, .height = h, .samples = o->gt_samples}, o->cache_dir,
                           &ss.gt);
            if (rc)
                break;
        }
        for (int k = 0; k < n && !rc; k++) {
            struct live_row *L = &live[k];
            if (L->row->accumulated)
                continue;
            struct metrics m = {0};
            ss.receiver.noise_frame = L->row->animated ? (float)frame : 0.0f;
            rc = scene_setup_cell(&ss, &(struct stage_timer_cell){L->row->t, L->settings, L->program}, &m);
            if (rc)
                break;
            memcpy(L->v, ss.v, sizeof(float) * count);
            L->row->nonfinite += m.nonfinite;
            flicker_add(&L->fl, L->v, ss.gt.v, ss.gt.noise, ss.scored, count);
            picture_visibility(L->v, ss.distance, ss.scored, w, h, &pic);
            strip_put(&L->vis, &pic, frame, K);
            picture_free(&pic);
            picture_error_heatmap(L->v, ss.gt.v, ss.scored, w, h, &pic);
            strip_put(&L->err, &pic, frame, K);
            picture_free(&pic);
        }
        if (rc)
            break;
        if (frame > 0)
            reproject(&posed.camera, &prev_camera, ss.distance, prev_distance, w, h, from);
        else
            for (size_t i = 0; i < count; i++)
                from[i] = -1;
        for (int k = 0; k < n; k++) {
            struct live_row *L = &live[k];
            if (!L->row->accumulated)
                continue;
            flicker_accumulate(L->history, L->prev_history, live[L->source].v, from, (float)o->accumulate, count);
            flicker_add(&L->fl, L->history, ss.gt.v, ss.gt.noise, ss.scored, count);
            float *t = L->history;
            L->history = L->prev_history, L->prev_history = t;
        }
        memcpy(prev_distance, ss.distance, sizeof(float) * count);
        if (isatty(STDERR_FILENO) && log_get_level() >= LOG_INFO)
            fprintf(stderr, "\r  %s, %s: frame %d/%d", base->name, mo->label, frame + 1, K);
    }
    if (isatty(STDERR_FILENO) && log_get_level() >= LOG_INFO)
        fprintf(stderr, "\n");
    for (int k = 0; k < n; k++) {
        struct live_row *L = &live[k];
        flicker_finish(&L->fl, &L->row->r);
        if (!rc && !L->row->accumulated) {
            char *dir = util_printf("%s/%s/%s/%s", o->out_dir, base->name, mo->label, L->row->label);
            char *vis = util_printf("%s/visibility_frames.png", dir), *err = util_printf("%s/error_frames.png", dir);
            rc = util_mkdirs(dir) || strip_write(&L->vis, vis) || strip_write(&L->err, err);
            free(dir), free(vis), free(err);
        }
        free(L->vis.rgb), free(L->err.rgb);
        flicker_free(&L->fl);
        free(L->v), free(L->history), free(L->prev_history);
        if (!rc) {
            const struct flicker_result *r = &L->row->r;
            log_info("  %-15s flicker %.5f (floor %.5f%s)  in the band %.4f (floor %.4f)  p99 %.4f  rmse mean %.4f  "
                     "max %.4f%s", L->row->label, r->flicker, r->floor, r->meaningful ? "" : ": not above it",
                     r->flicker_penumbra, r->floor_penumbra, r->flicker_p99, r->rmse_mean, r->rmse_max,
                     L->row->nonfinite ? "  NON-FINITE VALUES" : "");
        }
    }
    free(live), free(from), free(prev_distance);
    scene_setup_free(&ss);
    scene_unpose(&posed, base);
    return rc ? -1 : 0;
}

/* ---- variations --------------------------------------------------------- */

static void *value_settings(const struct stab *st, const struct variation *v, int value, const struct technique *t)
{
    void *s = memcpy(xmalloc(t->settings_size), run_settings(st->o, t), t->settings_size);
    if (v->kind == VARY_PARAM && t == v->t)
        params_set(t, s, v->p->name, v->texts[value]);  /* checked when parsed */
    return s;
}

static int vary_scene(struct stab *st, int scene_index, int var_index)
{
    const struct run_options *o = st->o;
    const struct scene *base = &st->scenes[scene_index];
    const struct variation *v = &st->vars[var_index];
    int rc = 0;
    for (int k = 0; k < v->count && !rc; k++) {
        const double x = v->values[k];
        struct scene posed;
        scene_posed(base, &(struct scene_pose){.light_scale = v->kind == VARY_LIGHT_SCALE ? (float)x : 0}, &posed);
        struct scene_setup ss;
        const struct scene_setup_desc desc = {o->width, o->height,
                                              v->kind == VARY_MAP_SIZE ? (int)x : o->shadow_map_size,
                                              o->gt_samples, 0, o->cache_dir,
                                              v->kind == VARY_DEPTH_RANGE ? (float)x : 0};
        rc = scene_setup_open(&ss, &posed, &desc);
        for (int i = 0; i < o->technique_count && !rc; i++) {
            const struct technique *t = o->techniques[i];
            if (v->kind == VARY_PARAM && t != v->t)
                continue;
            void *settings = value_settings(st, v, k, t);
            GLuint program = run_program_get(&st->programs, t, settings, base->light.shape);
            struct metrics m = {0};
            rc = !program || scene_setup_cell(&ss, &(struct stage_timer_cell){t, settings, program}, &m);
            free(settings);
            if (rc)
                break;
            st->points = xrealloc(st->points, sizeof *st->points * (size_t)(st->point_count + 1));
            st->points[st->point_count++] = (struct vary_point){scene_index, var_index, k, t, m, false};
            log_info("  %s=%s %-10s rmse %.4f  penumbra_rmse %.4f  leak %.4f  dark %.4f%s", v->name, v->texts[k],
                     t->name, m.rmse, m.penumbra_rmse, m.leak_fraction, m.dark_fraction,
                     m.nonfinite ? "  NON-FINITE VALUES" : "");
        }
        scene_setup_free(&ss);
        scene_unpose(&posed, base);
    }
    return rc ? -1 : 0;
}

/* The point of (scene, variation, value, technique), or NULL. */
static struct vary_point *find_point(struct stab *st, int s, int var, int value, const struct technique *t)
{
    for (int i = 0; i < st->point_count; i++) {
        struct vary_point *p = &st->points[i];
        if (p->scene == s && p->variation == var && p->value == value && p->t == t)
            return p;
    }
    return NULL;
}

/* The break rule (stability.h) for p against the reference point ref. */
static bool broken(const struct vary_point *p, const struct vary_point *ref)
{
    const struct metrics *m = &p->m, *r = &ref->m;
    if (m->nonfinite > 0)
        return true;
    if (!metrics_scored(m) || !metrics_scored(r))
        return false;
    return (m->rmse >= STABILITY_BREAK_RMSE_FACTOR * r->rmse && m->rmse >= r->rmse + STABILITY_BREAK_RMSE_RISE) ||
           m->leak_fraction >= r->leak_fraction + STABILITY_BREAK_FRACTION_RISE ||
           m->dark_fraction >= r->dark_fraction + STABILITY_BREAK_FRACTION_RISE;
}

/* Where technique t breaks on scene s under variation var: the first
 * broken value below the reference (walking down) and above it (walking
 * up); -1 for none. */
static void break_points(struct stab *st, int s, int var, const struct technique *t, int *below, int *above)
{
    const struct variation *v = &st->vars[var];
    const struct vary_point *ref = find_point(st, s, var, v->reference, t);
    *below = *above = -1;
    for (int k = v->reference - 1; ref && k >= 0 && *below < 0; k--) {
        const struct vary_point *p = find_point(st, s, var, k, t);
        if (p && broken(p, ref))
            *below = k;
    }
    for (int k = v->reference + 1; ref && k < v->count && *above < 0; k++) {
        const struct vary_point *p = find_point(st, s, var, k, t);
        if (p && broken(p, ref))
            *above = k;
    }
}

/* Every value that breaks t on scene s under var, in the variable's
 * order, as text ("" for none): past a break point a value may hold again
 * (a break point is where breaking starts, not a range). */
static void broken_values(struct stab *st, int s, int var, const struct technique *t, struct strbuf *out)
{
    const struct variation *v = &st->vars[var];
    for (int k = 0; k < v->count; k++) {
        const struct vary_point *p = find_point(st, s, var, k, t);
        if (k != v->reference && p && p->broken)  /* p->broken: against the reference, when measured */
            strbuf_list_printf(out, ", ", "%s", v->texts[k]);
    }
}

/* ---- outputs ------------------------------------------------------------ */

static const char break_rule[] =
    "a value breaks a technique where its V has any NaN/Inf, or, against the reference value, its rmse is "
    "at least " RUN_STR(STABILITY_BREAK_RMSE_FACTOR) " times as large and " RUN_STR(STABILITY_BREAK_RMSE_RISE)
    " larger, or its leak_fraction or dark_fraction " RUN_STR(STABILITY_BREAK_FRACTION_RISE) " larger";

static void add_number(cJSON *o, const char *key, double v)
{
    if (isfinite(v))
        cJSON_AddNumberToObject(o, key, v);
    else
        cJSON_AddNullToObject(o, key);
}

static void csv_number(struct strbuf *csv, double v, bool last)
{
    if (isfinite(v))
        strbuf_printf(csv, "%.6g", v);
    strbuf_printf(csv, last ? "\n" : ",");
}

static const char csv_header[] =
    "scene,technique,mode,name,value,row,noise,accumulated,frames,flicker,flicker_p99,flicker_floor,"
    "flicker_meaningful,flicker_penumbra,flicker_floor_penumbra,rmse_mean,rmse_max,mask_changes,rmse,penumbra_rmse,leak_fraction,dark_fraction,"
    "nonfinite,broken\n";

static int write_data(struct stab *st, cJSON *run)
{
    const struct run_options *o = st->o;
    struct strbuf csv = {0};
    strbuf_printf(&csv, "%s", csv_header);
    cJSON *doc = cJSON_CreateObject();
    cJSON_AddItemToObject(doc, "run", cJSON_Duplicate(run, true));
    cJSON *motions = cJSON_AddArrayToObject(doc, "motions");
    for (int i = 0; i < st->row_count; i++) {
        const struct motion_row *r = &st->rows[i];
        const struct motion *mo = &st->motions[r->motion];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "scene", st->scenes[r->scene].name);
        cJSON_AddStringToObject(j, "technique", r->t->name);
        cJSON_AddStringToObject(j, "motion", motion_kinds[mo->kind].name);
        if (*mo->node)
            cJSON_AddStringToObject(j, "node", mo->node);
        cJSON_AddNumberToObject(j, "step", mo->step);
        cJSON_AddStringToObject(j, "step_unit", motion_kinds[mo->kind].unit);
        cJSON_AddStringToObject(j, "row", r->label);
        if (!r->accumulated) {  /* its frames: the manifest the next run here removes */
            char *folder = util_printf("%s/%s/%s", st->scenes[r->scene].name, mo->label, r->label);
            cJSON_AddStringToObject(j, "frames_folder", folder);
            free(folder);
        }
        cJSON_AddStringToObject(j, "noise", r->animated ? "animated" : "still");
        cJSON_AddBoolToObject(j, "accumulated", r->accumulated);
        cJSON_AddNumberToObject(j, "frames", r->r.frames);
        cJSON_AddNumberToObject(j, "scored_frames", r->r.scored_frames);
        add_number(j, "flicker", r->r.flicker);
        add_number(j, "flicker_p99", r->r.flicker_p99);
        add_number(j, "flicker_floor", r->r.floor);
        add_number(j, "flicker_penumbra", r->r.flicker_penumbra);
        add_number(j, "flicker_floor_penumbra", r->r.floor_penumbra);
        cJSON_AddNumberToObject(j, "band_pixels", (double)r->r.band_pixels);
        cJSON_AddBoolToObject(j, "flicker_meaningful", r->r.meaningful);
        add_number(j, "rmse_mean", r->r.rmse_mean);
        add_number(j, "rmse_max", r->r.rmse_max);
        cJSON_AddNumberToObject(j, "pairs_pixels", (double)r->r.pairs_pixels);
        cJSON_AddNumberToObject(j, "mask_changes", (double)r->r.mask_changes);
        cJSON_AddNumberToObject(j, "nonfinite", (double)r->nonfinite);
        cJSON_AddItemToArray(motions, j);
        report_csv_field(&csv, st->scenes[r->scene].name);
        strbuf_printf(&csv, ",%s,motion,", r->t->name);
        report_csv_field(&csv, mo->name);
        strbuf_printf(&csv, ",%g,%s,%s,%s,%d,", mo->step, r->label, r->animated ? "animated" : "still",
                      r->accumulated ? "true" : "false", r->r.frames);
        csv_number(&csv, r->r.flicker, false);
        csv_number(&csv, r->r.flicker_p99, false);
        csv_number(&csv, r->r.floor, false);
        strbuf_printf(&csv, "%s,", r->r.meaningful ? "true" : "false");
        csv_number(&csv, r->r.flicker_penumbra, false);
        csv_number(&csv, r->r.floor_penumbra, false);
        csv_number(&csv, r->r.rmse_mean, false);
        csv_number(&csv, r->r.rmse_max, false);
        strbuf_printf(&csv, "%ld,,,,,%ld,\n", r->r.mask_changes, r->nonfinite);
    }
    cJSON *vars = cJSON_AddArrayToObject(doc, "variations");
    for (int i = 0; i < st->point_count; i++) {
        const struct vary_point *p = &st->points[i];
        const struct variation *v = &st->vars[p->variation];
        cJSON *j = cJSON_CreateObject();
        cJSON_AddStringToObject(j, "scene", st->scenes[p->scene].name);
        cJSON_AddStringToObject(j, "technique", p->t->name);
        cJSON_AddStringToObject(j, "variable", v->name);
        cJSON_AddStringToObject(j, "value", v->texts[p->value]);
        cJSON_AddBoolToObject(j, "reference", p->value == v->reference);
        for (int k = 0; k < METRIC_COUNT; k++)
            if (strncmp(metric_info[k].key, "ms_", 3) != 0)  /* not timed here */
                add_number(j, metric_info[k].key, metrics_value(&p->m, k));
        cJSON_AddBoolToObject(j, "broken", p->broken);
        cJSON_AddItemToArray(vars, j);
        report_csv_field(&csv, st->scenes[p->scene].name);
        strbuf_printf(&csv, ",%s,vary,", p->t->name);
        report_csv_field(&csv, v->name);
        strbuf_printf(&csv, ",");
        report_csv_field(&csv, v->texts[p->value]);
        strbuf_printf(&csv, ",%s,still,false,1,,,,,,,,,,", p->t->name);
        csv_number(&csv, p->m.rmse, false);
        csv_number(&csv, p->m.penumbra_rmse, false);
        csv_number(&csv, p->m.leak_fraction, false);
        csv_number(&csv, p->m.dark_fraction, false);
        strbuf_printf(&csv, "%ld,%s\n", p->m.nonfinite, p->broken ? "true" : "false");
    }
    cJSON *breaks = cJSON_AddArrayToObject(doc, "break_points");
    for (int s = 0; s < st->scene_count; s++)
        for (int var = 0; var < st->var_count; var++)
            for (int i = 0; i < o->technique_count; i++) {
                const struct technique *t = o->techniques[i];
                const struct variation *v = &st->vars[var];
                if (v->kind == VARY_PARAM && t != v->t)
                    continue;
                int below, above;
                break_points(st, s, var, t, &below, &above);
                cJSON *j = cJSON_CreateObject();
                cJSON_AddStringToObject(j, "scene", st->scenes[s].name);
                cJSON_AddStringToObject(j, "technique", t->name);
                cJSON_AddStringToObject(j, "variable", v->name);
                cJSON_AddStringToObject(j, "reference", v->texts[v->reference]);
                if (below >= 0)
                    cJSON_AddStringToObject(j, "breaks_at_or_below", v->texts[below]);
                else
                    cJSON_AddNullToObject(j, "breaks_at_or_below");
                if (above >= 0)
                    cJSON_AddStringToObject(j, "breaks_at_or_above", v->texts[above]);
                else
                    cJSON_AddNullToObject(j, "breaks_at_or_above");
                struct strbuf all = {0};
                broken_values(st, s, var, t, &all);
                cJSON_AddStringToObject(j, "broken_values", all.data ? all.data : "");
                strbuf_free(&all);
                cJSON_AddItemToArray(breaks, j);
            }
    cJSON_AddStringToObject(doc, "break_rule", break_rule);
    cJSON_AddItemToObject(doc, "charts", cJSON_Duplicate(st->charts, true));
    char *json_path = util_printf("%s/stability.json", o->out_dir), *csv_path = util_printf("%s/stability.csv", o->out_dir);
    int rc = report_write_json(json_path, doc) || util_write_file_atomic(csv_path, csv.data, csv.len);
    free(json_path), free(csv_path);
    cJSON_Delete(doc);
    strbuf_free(&csv);
    return rc ? -1 : 0;
}

/* Writes <out>/charts/<name>.svg and an <img> of it into html. */
static int chart_file(struct stab *st, const char *name, struct strbuf *svg, struct strbuf *html)
{
    cJSON_AddItemToArray(st->charts, cJSON_CreateString(name));
    char *path = util_printf("%s/charts/%s.svg", st->o->out_dir, name);
    int rc = util_write_file_atomic(path, svg->data, svg->len);
    free(path);
    strbuf_printf(html, "<figure class=\"chart\"><img src=\"charts/");
    report_url(html, name);
    strbuf_printf(html, ".svg\" alt=\"chart\" onerror=\"this.classList.add('missing')\"><figcaption><a href=\"charts/");
    report_url(html, name);
    strbuf_printf(html, ".svg\">charts/");
    strbuf_xml(html, name);
    strbuf_printf(html, ".svg</a></figcaption></figure>\n");
    strbuf_free(svg);
    return rc ? -1 : 0;
}

/* The row labels a flicker chart shows: per frame (still and animated) and
 * the animated rows accumulated (the still ones accumulated are in the
 * table and the files). */
static bool charted(const struct motion_row *r) { return !r->accumulated || r->animated; }

/* The flicker chart of one scene (s >= 0: the motions run on it) or the
 * mean over the scenes (s < 0: the motions run on every scene), if any. */
static int flicker_chart(struct stab *st, int s, const char *device, struct strbuf *html)
{
    /* items: the charted labels of the first motion row's (the same for each) */
    struct chart_item items[RUN_MAX_TECHNIQUES * 4];
    const struct motion_row *first[RUN_MAX_TECHNIQUES * 4];
    int n = 0;
    for (int i = 0; i < st->row_count && n < RUN_MAX_TECHNIQUES * 4; i++) {
        const struct motion_row *r = &st->rows[i];
        if (r->scene == st->rows[0].scene && r->motion == st->rows[0].motion && charted(r)) {
            first[n] = r;
            items[n++] = (struct chart_item){r->label, r->t->name, technique_group(r->t)};
        }
    }
    struct chart_series *series = xcalloc((size_t)st->motion_count + 1, sizeof *series);
    double *values = xcalloc((size_t)(n * st->motion_count) + 1, sizeof(double));
    int shown = 0;
    for (int m = 0; m < st->motion_count; m++) {
        if (s < 0 ? st->motions[m].scene >= 0 : !motion_on(&st->motions[m], s))
            continue;
        double floor_sum = 0;
        int floor_n = 0;
        for (int k = 0; k < n; k++) {
            double sum = 0;
            int count = 0;
            for (int i = 0; i < st->row_count; i++) {
                const struct motion_row *r = &st->rows[i];
                if (r->motion == m && (s < 0 || r->scene == s) && !strcmp(r->label, first[k]->label)) {
                    sum += r->r.flicker, count++;
                    if (k == 0)
                        floor_sum += r->r.floor, floor_n++;
                }
            }
            values[shown * n + k] = count ? sum / count : NAN;
        }
        series[shown] = (struct chart_series){st->motions[m].label, "mean |Δe| per pixel and frame",
                                              values + shown * n, NULL, NULL, "ground truth's own",
                                              floor_n ? floor_sum / floor_n : NAN};
        shown++;
    }
    if (!shown) {
        free(series), free(values);
        return 0;
    }
    char *title = s < 0 ? util_printf("Flicker under motion, mean over %d scene(s)", st->scene_count)
                        : util_printf("Flicker under motion: %s", st->scenes[s].name);
    char *subtitle = util_printf("%d frames at %dx%d, %d^2 map; ~anim: noise animated per frame; +ema: "
                                 "accumulated (alpha %g); on %s", st->o->frames, st->o->width, st->o->height,
                                 st->o->shadow_map_size, st->o->accumulate, device);
    struct strbuf svg = {0};
    chart_bars_svg(&svg, title, subtitle, items, n, series, shown);
    char *name = s < 0 ? xstrdup("flicker") : util_printf("flicker_%s", st->scenes[s].name);
    int rc = chart_file(st, name, &svg, html);
    free(series), free(values), free(title), free(subtitle), free(name);
    return rc;
}

static int vary_chart(struct stab *st, int s, int var, const char *device, struct strbuf *html)
{
    const struct run_options *o = st->o;
    const struct variation *v = &st->vars[var];
    static const int keys[] = {METRIC_rmse, METRIC_penumbra_rmse, METRIC_leak_fraction, METRIC_dark_fraction};
    static const char *const units[] = {"visibility", "visibility", "share of scored pixels", "share of scored pixels"};
    struct chart_line lines[4][RUN_MAX_TECHNIQUES];
    double *data = xcalloc((size_t)(4 * o->technique_count * v->count) + 1, sizeof(double));
    bool *marks = xcalloc((size_t)(o->technique_count * v->count) + 1, sizeof(bool));
    int n = 0;
    for (int i = 0; i < o->technique_count; i++) {
        const struct technique *t = o->techniques[i];
        if (v->kind == VARY_PARAM && t != v->t)
            continue;
        const struct vary_point *ref = find_point(st, s, var, v->reference, t);
        for (int k = 0; k < v->count; k++) {
            const struct vary_point *p = find_point(st, s, var, k, t);
            marks[n * v->count + k] = p && ref && broken(p, ref);
            for (int q = 0; q < 4; q++)
                data[(q * o->technique_count + n) * v->count + k] = p ? metrics_value(&p->m, keys[q]) : NAN;
        }
        for (int q = 0; q < 4; q++)
            lines[q][n] = (struct chart_line){{t->name, t->name, technique_group(t)}, v->count, v->values,
                                              data + (q * o->technique_count + n) * v->count, marks + n * v->count};
        n++;
    }
    struct chart_panel panels[4];
    for (int q = 0; q < 4; q++)
        panels[q] = (struct chart_panel){metric_info[keys[q]].key, units[q], lines[q], n};
    char *title = util_printf("%s: error against %s", st->scenes[s].name, v->name);
    char *subtitle = util_printf("%dx%d, %d GT samples, %d^2 map unless varied; on %s", o->width, o->height,
                                 o->gt_samples, o->shadow_map_size, device);
    char *x_label = v->kind == VARY_PARAM && (v->p->type == PARAM_ENUM || v->p->type == PARAM_BOOL)
                        ? util_printf("%s (choice index)", v->name)
                        : xstrdup(v->name);
    struct strbuf svg = {0};
    chart_lines_svg(&svg, title, subtitle, x_label, v->log_x, v->values[v->reference],
                    "broken (the break rule, against the reference value)", panels, 4);
    char *name = util_printf("vary_%s_%s", v->name, st->scenes[s].name);
    int rc = chart_file(st, name, &svg, html);
    free(data), free(marks), free(title), free(subtitle), free(x_label), free(name);
    return rc;
}

/* Frame sliders: each moves every strip of its group to its frame. */
static const char slider_script[] =
    "document.querySelectorAll('input.frame').forEach(function(s){\n"
    " s.addEventListener('input',function(){const g=s.dataset.group,t=+s.value;\n"
    "  document.querySelectorAll('img.strip[data-group=\"'+g+'\"]').forEach(function(i){\n"
    "   i.style.marginLeft=(-t*+i.dataset.w)+'px';});\n"
    "  document.getElementById('f-'+g).textContent=t;});});\n"
    "document.querySelectorAll('button.play').forEach(function(b){let timer=null;\n"
    " b.addEventListener('click',function(){const s=document.getElementById('s-'+b.dataset.group);\n"
    "  if(timer){clearInterval(timer);timer=null;b.textContent='play';return;}\n"
    "  b.textContent='stop';timer=setInterval(function(){s.value=(+s.value+1)%(+s.max+1);\n"
    "   s.dispatchEvent(new Event('input'));},125);});});\n";

static void flicker_cell(struct strbuf *h, const struct motion_row *r)
{
    if (!isfinite(r->r.flicker))
        strbuf_printf(h, "<td class=\"none\" colspan=\"2\">unscored</td>");
    else
        strbuf_printf(h, "<td%s title=\"p99 %.4f, rmse mean %.4f, max %.4f\">%.4f%s</td><td>%.4f</td>",
                      r->r.meaningful ? "" : " class=\"floor\"", r->r.flicker_p99, r->r.rmse_mean, r->r.rmse_max,
                      r->r.flicker, r->nonfinite ? " NaN!" : "", r->r.flicker_penumbra);
}

static void motion_section(struct stab *st, int s, struct strbuf *h, int *group)
{
    const struct run_options *o = st->o;
    const char *name = st->scenes[s].name;
    int m0 = 0;  /* the first motion run on s: the rows' labels */
    while (m0 < st->motion_count && !motion_on(&st->motions[m0], s))
        m0++;
    if (m0 == st->motion_count) {
        strbuf_printf(h, "<p>No motion runs on this scene.</p>\n");
        return;
    }
    strbuf_printf(h, "<table><thead><tr><th rowspan=\"2\">row</th>");
    for (int m = 0; m < st->motion_count; m++) {
        if (!motion_on(&st->motions[m], s))
            continue;
        strbuf_printf(h, "<th colspan=\"2\">");
        strbuf_xml(h, st->motions[m].label);
        strbuf_printf(h, "</th>");
    }
    strbuf_printf(h, "</tr><tr>");
    for (int m = 0; m < st->motion_count; m++)
        if (motion_on(&st->motions[m], s))
            strbuf_printf(h, "<th>flicker</th><th>in the band</th>");
    strbuf_printf(h, "</tr></thead><tbody>\n");
    for (int i = 0; i < st->row_count; i++) {
        const struct motion_row *r0 = &st->rows[i];
        if (r0->scene != s || r0->motion != m0)
            continue;
        strbuf_printf(h, "<tr><td class=\"l\">%s</td>", r0->label);
        for (int m = 0; m < st->motion_count; m++)
            for (int j = 0; j < st->row_count; j++)
                if (st->rows[j].scene == s && st->rows[j].motion == m && !strcmp(st->rows[j].label, r0->label))
                    flicker_cell(h, &st->rows[j]);
        strbuf_printf(h, "</tr>\n");
    }
    strbuf_printf(h, "<tr><td class=\"l\"><i>ground truth's floor</i></td>");
    for (int m = 0; m < st->motion_count; m++)
        for (int j = 0; j < st->row_count; j++)
            if (st->rows[j].scene == s && st->rows[j].motion == m) {
                strbuf_printf(h, "<td>%.4f</td><td>%.4f</td>", st->rows[j].r.floor, st->rows[j].r.floor_penumbra);
                break;
            }
    strbuf_printf(h, "</tr></tbody></table>\n");
    for (int m = 0; m < st->motion_count; m++) {
        const struct motion *mo = &st->motions[m];
        if (!motion_on(mo, s))
            continue;
        const int g = (*group)++;
        strbuf_printf(h, "<h4>");
        strbuf_xml(h, name);
        strbuf_printf(h, ", %s</h4>\n<p class=\"frames\"><button class=\"play\" data-group=\"%d\">play</button> "
                         "frame <input type=\"range\" class=\"frame\" id=\"s-%d\" data-group=\"%d\" min=\"0\" "
                         "max=\"%d\" value=\"0\"> <span id=\"f-%d\">0</span> of 0&ndash;%d</p>\n<div class=\"grid\">",
                      mo->label, g, g, g, o->frames - 1, g, o->frames - 1);
        for (int i = 0; i < st->row_count; i++) {
            const struct motion_row *r = &st->rows[i];
            if (r->scene != s || r->motion != m || r->accumulated)
                continue;
            static const char *const files[] = {"visibility_frames.png", "error_frames.png"};
            for (int f = 0; f < 2; f++) {
                strbuf_printf(h, "<figure><div class=\"crop\" style=\"width:%dpx\"><img class=\"strip\" "
                                 "data-group=\"%d\" data-w=\"%d\" style=\"width:%dpx\" src=\"",
                              o->width, g, o->width, o->width * o->frames);
                report_url(h, name);
                strbuf_printf(h, "/");
                report_url(h, mo->label);
                strbuf_printf(h, "/");
                report_url(h, r->label);
                strbuf_printf(h, "/%s\" alt=\"%s\" onerror=\"this.classList.add('missing')\"></div>"
                                 "<figcaption>%s: %s</figcaption></figure>", files[f], files[f], r->label,
                              f ? "signed error" : "V<sub>tech</sub>");
            }
        }
        strbuf_printf(h, "</div>\n");
    }
}

static int write_html(struct stab *st, cJSON *run)
{
    const struct run_options *o = st->o;
    const char *device = cJSON_GetStringValue(cJSON_GetObjectItem(run, "gl_renderer"));
    struct strbuf h = {0};
    strbuf_printf(&h, "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n"
                      "<title>shadowbench stability</title>\n<style>\n%s"
                      ".crop{overflow:hidden}.crop img{max-width:none;image-rendering:pixelated}"
                      ".grid figure{width:auto}td.floor{color:#999}h4{margin:1.2em 0 .3em}</style></head><body>\n"
                      "<h1>shadowbench stability</h1>\n", report_style);
    int rc = 0, group = 0;
    if (st->motion_count) {
        strbuf_printf(&h, "<h2 id=\"motion\">Motion: flicker</h2>\n<p>Each motion runs %d frames at %d&times;%d "
                          "with a %d&sup2; shadow map, every frame ray traced anew. <b>flicker</b> is the mean over "
                          "the pixels scored in both frames of a pair, and over the pairs, of |&Delta;V<sub>tech</sub> "
                          "&minus; &Delta;V<sub>gt</sub>| = |e<sub>t</sub> &minus; e<sub>t&minus;1</sub>|: how much "
                          "a pixel's error changes from one frame to the next (a pixel scored in one frame of a pair "
                          "only is left out and counted as mask_changes). The ground truth's own frame-to-frame noise "
                          "is the <b>floor</b>: a grey flicker is not above it, so not a meaningful number. <b>In the band</b>: "
                          "the same over the pixels whose V<sub>gt</sub> is in the penumbra band (0.02&ndash;0.98) in "
                          "either frame, where edges move (most pixels are lit or umbra and never flicker). Rows: "
                          "<i>T</i> per frame with its noise still (as <code>run</code> scores it); <i>T~anim</i> "
                          "with interleaved gradient noise moved each frame (Jimenez 2014), for techniques that use "
                          "noise; <i>+ema</i> the same frames accumulated by an exponential moving average "
                          "(weight %g for the new frame, reprojected where the camera moved), as TAA would. Hover a "
                          "number for its 99th percentile and the frames' rmse. The pictures are the frames: move "
                          "the slider or press play.</p>\n",
                      o->frames, o->width, o->height, o->shadow_map_size, o->accumulate);
        rc |= flicker_chart(st, -1, device ? device : "unknown", &h);
        for (int s = 0; s < st->scene_count; s++) {
            strbuf_printf(&h, "<h3>");
            strbuf_xml(&h, st->scenes[s].name);
            strbuf_printf(&h, "</h3>\n");
            motion_section(st, s, &h, &group);
            rc |= flicker_chart(st, s, device ? device : "unknown", &h);
        }
    }
    if (st->var_count) {
        strbuf_printf(&h, "<h2 id=\"vary\">Sensitivity: where each technique breaks</h2>\n<p>Break rule: %s. A "
                          "break point is the first value, walking away from the reference value (the dashed "
                          "line), that breaks the technique; a larger or smaller value may hold again, so the last column lists every "
                          "broken value, and the charts ring them.</p>\n",
                      break_rule);
        for (int var = 0; var < st->var_count; var++) {
            const struct variation *v = &st->vars[var];
            for (int s = 0; s < st->scene_count; s++) {
                strbuf_printf(&h, "<h3>");
                strbuf_xml(&h, v->name);
                strbuf_printf(&h, " on ");
                strbuf_xml(&h, st->scenes[s].name);
                strbuf_printf(&h, "</h3>\n<table><thead><tr><th>technique</th><th>breaks at or below</th><th>"
                                  "reference</th><th>breaks at or above</th><th>every broken value</th></tr>"
                                  "</thead><tbody>\n");
                for (int i = 0; i < o->technique_count; i++) {
                    const struct technique *t = o->techniques[i];
                    if (v->kind == VARY_PARAM && t != v->t)
                        continue;
                    int below, above;
                    break_points(st, s, var, t, &below, &above);
                    strbuf_printf(&h, "<tr><td class=\"l\">%s</td><td>", t->name);
                    strbuf_xml(&h, below >= 0 ? v->texts[below] : "holds");
                    strbuf_printf(&h, "</td><td>");
                    strbuf_xml(&h, v->texts[v->reference]);
                    strbuf_printf(&h, "</td><td>");
                    strbuf_xml(&h, above >= 0 ? v->texts[above] : "holds");
                    struct strbuf all = {0};
                    broken_values(st, s, var, t, &all);
                    strbuf_printf(&h, "</td><td>");
                    strbuf_xml(&h, all.data ? all.data : "none");
                    strbuf_free(&all);
                    strbuf_printf(&h, "</td></tr>\n");
                }
                strbuf_printf(&h, "</tbody></table>\n");
                rc |= vary_chart(st, s, var, device ? device : "unknown", &h);
            }
        }
    }
    report_html_end(&h, "Environment", run, slider_script);
    char *path = util_printf("%s/stability.html", o->out_dir);
    rc |= util_write_file_atomic(path, h.data, h.len);
    free(path);
    strbuf_free(&h);
    return rc ? -1 : 0;
}

/* ---- the command -------------------------------------------------------- */

/* Whether rel, a path below out of `parts` names, is one stability
 * writes: no empty, "." or ".." part, and every folder on the way a real
 * folder (not a link that would lead out of out). */
static bool own_path(const char *out, const char *rel, int parts)
{
    char *copy = xstrdup(rel), *rest = copy, *path = xstrdup(out);
    int n = 0;
    bool ok = true;
    for (char *part = strsep(&rest, "/"); part && ok; part = strsep(&rest, "/")) {
        ok = *part && strcmp(part, ".") && strcmp(part, "..") && ++n <= parts;
        char *next = util_printf("%s/%s", path, part);
        free(path), path = next;
        struct stat sb;
        ok = ok && lstat(path, &sb) == 0 && S_ISDIR(sb.st_mode);
    }
    free(copy), free(path);
    return ok && n == parts;
}

/* Removes what the last run into out wrote and listed in its
 * stability.json (each motion row's frames, the charts), and the folders
 * that leaves empty: nothing else, so a folder shared with `run`, or
 * holding files of the user's, keeps them. */
static void remove_last_run(const char *out)
{
    char *path = util_printf("%s/stability.json", out), *text = NULL;
    size_t size;
    cJSON *doc = util_read_file(path, &text, &size) == 0 ? cJSON_Parse(text) : NULL;
    free(text), free(path);
    const cJSON *row, *chart;
    cJSON_ArrayForEach(row, cJSON_GetObjectItemCaseSensitive(doc, "motions")) {
        const char *folder = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(row, "frames_folder"));
        if (!folder || !own_path(out, folder, 3))
            continue;
        for (const char *const *f = (const char *const[]){"visibility_frames.png", "error_frames.png", NULL}; *f; f++) {
            char *file = util_printf("%s/%s/%s", out, folder, *f);
            unlink(file);
            free(file);
        }
        char *dir = util_printf("%s/%s", out, folder);
        for (int up = 0; up < 3 && rmdir(dir) == 0; up++)  /* stops at the first folder not empty */
            *strrchr(dir, '/') = '\0';
        free(dir);
    }
    cJSON_ArrayForEach(chart, cJSON_GetObjectItemCaseSensitive(doc, "charts")) {
        const char *name = cJSON_GetStringValue(chart);
        if (!name || strchr(name, '/') || !own_path(out, "charts", 1))
            continue;
        char *file = util_printf("%s/charts/%s.svg", out, name);
        unlink(file);
        free(file);
    }
    cJSON_Delete(doc);
}

int stability_main(const struct run_options *o)
{
    static const char *const stale[] = {"stability.json", "stability.csv", "stability.html"};
    const double start = util_now_ms();
    struct stab st = {.o = o, .charts = cJSON_CreateArray()};
    static struct scene scenes[RUN_MAX_SCENES];
    int status = EXIT_USAGE;
    static const char *const default_motions[] = STABILITY_DEFAULT_MOTIONS,
                             *const default_varies[] = STABILITY_DEFAULT_VARIES,
                             *const default_scenes[] = STABILITY_DEFAULT_SCENES;
    const bool defaults = !o->motion_count && !o->vary_count;
    const int motion_count = defaults ? (int)(sizeof default_motions / sizeof *default_motions) : o->motion_count;
    const int vary_count = defaults ? (int)(sizeof default_varies / sizeof *default_varies) : o->vary_count;
    /* room for these and every scene's own */
    st.motions = xcalloc((size_t)(motion_count + RUN_MAX_SCENES * SCENE_MAX_MOTIONS), sizeof *st.motions);
    bool scene_motions = false;  /* --motion scene: each scene's own motions */
    for (int i = 0; i < motion_count; i++) {
        const char *spec = defaults ? default_motions[i] : o->motions[i];
        struct motion m;
        if (!strcmp(spec, "scene")) {
            if (scene_motions) {
                log_error("--motion: scene is given twice");
                goto out;
            }
            scene_motions = true;
        } else if (parse_motion("--motion", spec, -1, -1, &m) != 0 || add_motion(&st, &m) != 0) {
            goto out;
        }
    }
    for (int i = 0; i < vary_count; i++) {
        if (parse_vary(o, defaults ? default_varies[i] : o->varies[i], &st.vars[i]) != 0)
            goto out;
        st.var_count++;
        for (int j = 0; j < i; j++)
            if (!strcmp(st.vars[j].name, st.vars[i].name)) {
                log_error("--vary: %s is varied twice", st.vars[i].name);
                goto out;
            }
    }
    struct run_options scene_options = *o;  /* the default scenes when none is named */
    if (!o->scene_count) {
        scene_options.scene_count = (int)(sizeof default_scenes / sizeof *default_scenes);
        memcpy(scene_options.scenes, default_scenes, sizeof default_scenes);
    }
    st.scenes = scenes;
    if (o->gt_samples < 4) {  /* the floor compares two halves of the samples */
        log_error("--gt-samples: stability needs at least 4 (its noise floor compares two halves of the samples)");
        goto out;
    }
    if (run_load_scenes(&scene_options, scenes, &st.scene_count) != 0)
        goto out;
    for (int s = 0; s < st.scene_count; s++) {
        struct light_frustum f;
        if (light_frustum_fit(&scenes[s], &f) != 0)
            goto out;
        for (int i = 0; scene_motions && i < scenes[s].motion_count; i++) {
            struct motion m;
            char *what = util_printf("%s: extras.shadowbench.motions[%d]", scenes[s].path, i);
            const int bad = parse_motion(what, scenes[s].motions[i], s, i, &m) || add_motion(&st, &m);
            free(what);
            if (bad)
                goto out;
        }
    }
    if (o->motion_count && !st.motion_count) {  /* only --motion scene */
        log_error("--motion scene: none of the scenes lists motions of its own (extras.shadowbench.motions)");
        goto out;
    }
    if (check_motion_nodes(&st) != 0 || run_claim_out_dir(o->out_dir) != 0 || shader_init(o->shader_dir) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    if (gl_context_create(o->gl) != 0) {  /* no such context here: bad usage (exit 2), as a bad --shaders */
        status = EXIT_USAGE;
        goto out;
    }
    remove_last_run(o->out_dir);
    for (size_t i = 0; i < sizeof stale / sizeof *stale; i++) {  /* this run's, or none */
        char *path = util_printf("%s/%s", o->out_dir, stale[i]);
        unlink(path);
        free(path);
    }
    int shared = 0;
    for (int m = 0; m < st.motion_count; m++)
        shared += st.motions[m].scene < 0;
    log_info("stability: %d scene(s), %d technique(s), %d motion(s) and %d of the scenes' own, of %d frames, %d "
             "variation(s), %dx%d, %d GT samples, %d^2 shadow map, on %s", st.scene_count, o->technique_count, shared,
             st.motion_count - shared, o->frames, st.var_count, o->width, o->height, o->gt_samples,
             o->shadow_map_size, gl_context_renderer());
    int rc = 0;
    for (int s = 0; s < st.scene_count && !rc; s++)
        for (int m = 0; m < st.motion_count && !rc; m++) {
            if (!motion_on(&st.motions[m], s))
                continue;
            log_info("scene %s, motion %s", scenes[s].name, st.motions[m].label);
            rc = motion_scene(&st, s, m);
        }
    for (int s = 0; s < st.scene_count && !rc; s++)
        for (int v = 0; v < st.var_count && !rc; v++) {
            log_info("scene %s, varying %s", scenes[s].name, st.vars[v].name);
            rc = vary_scene(&st, s, v);
        }
    if (!rc) {
        for (int i = 0; i < st.point_count; i++) {
            struct vary_point *p = &st.points[i];
            const struct vary_point *ref = find_point(&st, p->scene, p->variation, st.vars[p->variation].reference, p->t);
            p->broken = ref && broken(p, ref);
        }
        cJSON *run = run_json(o, (util_now_ms() - start) * 1e-3);
        cJSON_DeleteItemFromObject(run, "timing_method");  /* stability times nothing */
        cJSON_AddNumberToObject(run, "accumulate", o->accumulate);
        char *charts = util_printf("%s/charts", o->out_dir);
        rc = util_mkdirs(charts) || write_html(&st, run) || write_data(&st, run);
        free(charts);
        for (size_t i = 0; rc && i < sizeof stale / sizeof *stale; i++) {  /* none, rather than a mixed set */
            char *path = util_printf("%s/%s", o->out_dir, stale[i]);
            unlink(path);
            free(path);
        }
        cJSON_Delete(run);
    }
    if (!rc) {
        long bad = 0;
        for (int i = 0; i < st.row_count; i++)
            bad += st.rows[i].nonfinite > 0 || !isfinite(st.rows[i].r.flicker) ||
                   st.rows[i].r.scored_frames < st.rows[i].r.frames;
        for (int i = 0; i < st.point_count; i++)
            bad += st.points[i].m.nonfinite > 0 || !metrics_scored(&st.points[i].m);
        if (bad)
            log_error("%ld row(s) with NaN/Inf visibility, or a frame or value with nothing to score (see "
                      "stability.csv: scored_frames, empty metrics)", bad);
        status = bad ? EXIT_CHECK_FAILED : EXIT_OK;
        printf("report: %s/stability.html\ndata: %s/stability.csv\n", o->out_dir, o->out_dir);
        log_info("stability finished in %.1f s", (util_now_ms() - start) * 1e-3);
    }
    run_programs_free(&st.programs);
    gl_context_destroy();
out:
    for (int i = 0; i < st.var_count; i++)
        variation_free(&st.vars[i]);
    for (int s = 0; s < st.scene_count; s++)
        scene_free(&scenes[s]);
    free(st.rows), free(st.points), free(st.motions);
    cJSON_Delete(st.charts);
    return status;
}
