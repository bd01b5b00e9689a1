#include "stability.h"
#include "base/log.h"
#include "base/util.h"
#include "score/break_rule.h"
#include "techniques/params.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const struct stability_variable stability_variables[VARY_PARAM] = {
#define X(id, name, ref, lo, hi, help) {name, help, ref, lo, hi},
    STABILITY_VARIABLES(X)
#undef X
};

/* The settings technique t runs at in the study. */
static const void *settings_of(const struct stability *st, const struct technique *t)
{
    for (int i = 0; i < st->technique_count; i++)
        if (st->techniques[i] == t)
            return st->settings[i];
    return NULL;
}

/* ---- motions ------------------------------------------------------------ */

int stability_add_motion(struct stability *st, const struct motion *m)
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
    if (st->motion_count == st->motion_capacity) {
        st->motion_capacity = st->motion_capacity ? 2 * st->motion_capacity : 16;
        st->motions = xrealloc(st->motions, sizeof *st->motions * (size_t)st->motion_capacity);
    }
    st->motions[st->motion_count++] = *m;
    return 0;
}

int stability_check_nodes(const struct stability *st)
{
    for (int v = 0; v < st->var_count; v++)
        for (int s = 0; s < st->scene_count; s++) {
            const struct scene *sc = &st->scenes[s];
            const double x = st->vars[v].values[st->vars[v].count - 1];  /* increasing: the widest */
            if (st->vars[v].kind == VARY_LIGHT_SCALE && sc->light.shape == LIGHT_SUN &&
                !(2 * sc->light.half_angle * x * 180 / M_PI <= 30)) {
                log_error("--vary light_scale=%g: %s's sun would be %.3g degrees across, beyond the 30 the scene format "
                          "allows", x, sc->name, 2 * sc->light.half_angle * x * 180 / M_PI);
                return -1;
            }
        }
    for (int m = 0; m < st->motion_count; m++)
        for (int s = 0; s < st->scene_count; s++) {
            const struct motion *mo = &st->motions[m];
            const struct scene *sc = &st->scenes[s];
            int count;
            if (mo->kind != MOTION_CASTER_SHIFT || !motion_on(mo, s))
                continue;
            const int node = pose_find_node(sc, mo->node, &count);
            /* the sun's texels have one size at every depth */
            if (node >= 0 && sc->light.shape != LIGHT_SUN && !(pose_light_depth_of_node(sc, node) > 0)) {
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

/* A motion row while its frames are rendered. */
struct live_row {
    struct motion_row *row;
    const void *settings;
    void *animated_settings;  /* owned: the settings with animate_noise on (the ~anim rows) */
    int source;               /* accumulated: the live row whose V it averages */
    float *v, *history, *prev_history;
    struct flicker fl;
};

static void live_row_free(struct live_row *L)
{
    free(L->v), free(L->history), free(L->prev_history), free(L->animated_settings);
}

/* Technique t's settings with animate_noise on, newly malloc'ed, where it
 * has that parameter and it is off; NULL otherwise. */
static void *animated_copy(const struct technique *t, const void *settings)
{
    const struct technique_param *p = params_find(t, "animate_noise");
    if (!p || params_get(p, settings) != 0)
        return NULL;
    void *copy = memcpy(xmalloc(t->settings_size), settings, t->settings_size);
    params_put(p, copy, 1);
    return copy;
}

/* The rows of motion m on scene s: every technique per frame with its
 * settings (its noise still unless they animate it), and animated too
 * where animate_noise on makes its program read the frame index (it has
 * noise to animate); each also accumulated. Returns how many (-1: a
 * program did not compile). */
static int add_rows(struct stability *st, int s, int m, size_t count, struct live_row *live)
{
    int n = 0;
    for (int i = 0; i < st->technique_count; i++) {
        const struct technique *t = st->techniques[i];
        const enum light_shape shape = st->scenes[s].light.shape;
        void *variants[2] = {(void *)st->settings[i], animated_copy(t, st->settings[i])};
        for (int a = 0; a < 2 && variants[a]; a++) {
            const GLuint program = programs_get(&st->programs, t, variants[a], shape, true).receiver;
            if (!program) {  /* the rows so far go too */
                for (int k = 0; k < n; k++)
                    live_row_free(&live[k]);
                free(variants[1]);  /* no row of this technique owns it yet */
                st->row_count -= n;
                return -1;
            }
            const bool animated = receiver_program_animated(program);
            if (a == 1 && !animated) {  /* no noise: the same frames as the row above */
                free(variants[1]);
                break;
            }
            for (int acc = 0; acc <= 1; acc++) {
                st->rows = xrealloc(st->rows, sizeof *st->rows * (size_t)(st->row_count + 1));
                struct motion_row *r = &st->rows[st->row_count++];
                *r = (struct motion_row){.scene = s, .motion = m, .t = t, .animated = animated, .accumulated = acc};
                snprintf(r->label, sizeof r->label, "%s%s%s", t->name, animated ? "~anim" : "", acc ? "+ema" : "");
                live[n] = (struct live_row){.settings = variants[a], .source = acc ? n - 1 : -1,
                                            .v = xmalloc(sizeof(float) * count)};
                if (a == 1 && !acc)
                    live[n].animated_settings = variants[1];  /* freed with this row */
                if (acc)
                    live[n].history = xmalloc(sizeof(float) * count),
                    live[n].prev_history = xmalloc(sizeof(float) * count);
                n++;
            }
        }
    }
    /* rows may have moved: point the live rows at theirs now */
    for (int k = 0; k < n; k++)
        live[k].row = &st->rows[st->row_count - n + k];
    return n;
}

int stability_motion(struct stability *st, int s, int m)
{
    const struct scene *base = &st->scenes[s];
    const struct motion *mo = &st->motions[m];
    const int w = st->width, h = st->height, K = st->frames;
    const size_t count = (size_t)w * (size_t)h;
    struct light_frustum f0;
    if (light_frustum_fit(base, (float)w / (float)h, &f0) != 0)
        return -1;
    const int node = mo->kind == MOTION_CASTER_SHIFT ? pose_find_node(base, mo->node, NULL) : -1;  /* found:
                                                                                     stability_check_nodes */
    struct live_row *live = xcalloc((size_t)st->technique_count * 4, sizeof *live);
    const int n = add_rows(st, s, m, count, live);
    if (n < 0) {
        free(live);
        return -1;
    }

    struct scene posed;
    struct scene_setup ss;
    scene_posed(base, &(struct scene_pose){0}, &posed);
    struct scene_camera prev_camera = posed.camera;
    int rc = scene_setup_open(&ss, &posed, &(struct scene_setup_desc){w, h, st->shadow_map_size, st->gt_samples, 0,
                                                                      st->cache_dir, 0, &st->programs,
                                                                      &st->cascades});
    /* A light's motion moves the map's texel grid with it (a spot light's
     * map is its view): the angular window stays frame 0's. So does a
     * caster's: the map does not follow the geometry. A camera's motion
     * refits the sun's maps to the view, as an engine does every frame
     * (where snapping matters); an area light's map does not depend on
     * the camera. */
    const struct shadow_cascades window = ss.cascades;  /* its frusta only */
    const bool follow = mo->kind == MOTION_CAMERA_SHIFT || mo->kind == MOTION_CAMERA_YAW;  /* and pixels are
                                                                   compared on the surface (flicker_add) */
    int *from = xmalloc(sizeof(int) * count);
    float *prev_distance = xmalloc(sizeof(float) * count);
    char where[640];  /* the posed scene's "path": its errors name the motion and frame */
    for (int frame = 0; frame < K && !rc; frame++) {
        if (frame > 0 && mo->kind != MOTION_STATIC) {
            prev_camera = posed.camera;
            scene_unpose(&posed, base);
            const struct scene_pose p = motion_pose(mo, base, &f0, st->shadow_map_size, h, node, frame);
            scene_posed(base, &p, &posed);
            snprintf(where, sizeof where, "%s (motion %s, frame %d)", base->path, mo->label, frame);
            posed.path = where;
            receiver_set_camera(&ss.receiver, &posed);
            if (p.caster)
                scene_mesh_update_positions(&posed, &ss.mesh);
            gt_image_free(&ss.gt);
            rc = shadow_cascades_refit(&ss.cascades, &posed, follow ? NULL : &window) ||
                 gt_obtain(&posed, &ss.cascades.view,
                           &(struct gt_desc){.width = w, .height = h, .samples = st->gt_samples}, st->cache_dir,
                           &ss.gt);
            if (rc)
                break;
            scene_setup_truth_posed(&ss);
        }
        /* The last frame's pixel of each point, from the truth's hit distances
         * (the same surfaces GL draws, within METRICS_DEPTH_TOLERANCE). */
        if (frame > 0)
            flicker_reproject(&posed.camera, &prev_camera, ss.gt.distance, prev_distance, w, h, from);
        else
            for (size_t i = 0; i < count; i++)
                from[i] = -1;
        for (int k = 0; k < n && !rc; k++) {
            struct live_row *L = &live[k];
            if (L->row->accumulated)
                continue;
            struct metrics mt = {0};
            ss.receiver.noise_frame = (float)frame;  /* read by a program that animates its noise */
            rc = scene_setup_cell(&ss, L->row->t, L->settings, &mt);
            if (rc)
                break;
            memcpy(L->v, ss.v, sizeof(float) * count);
            L->row->nonfinite += mt.nonfinite;
            flicker_add(&L->fl, L->v, ss.gt.v, ss.gt.noise, ss.scored, follow ? from : NULL, count);
            if (st->on_frame)
                rc = st->on_frame(st->user, L->row, frame, K, &ss, L->v);
        }
        if (rc)
            break;
        for (int k = 0; k < n; k++) {
            struct live_row *L = &live[k];
            if (!L->row->accumulated)
                continue;
            flicker_accumulate(L->history, L->prev_history, live[L->source].v, from, (float)st->accumulate, count);
            flicker_add(&L->fl, L->history, ss.gt.v, ss.gt.noise, ss.scored, follow ? from : NULL, count);
            float *t = L->history;
            L->history = L->prev_history, L->prev_history = t;
        }
        memcpy(prev_distance, ss.gt.distance, sizeof(float) * count);
        log_progress("  %s, %s: frame %d/%d", base->name, mo->label, frame + 1, K);
    }
    log_progress_done();
    for (int k = 0; k < n; k++) {
        struct live_row *L = &live[k];
        flicker_finish(&L->fl, &L->row->r);
        L->row->frame_rmse = L->fl.frame_rmse, L->fl.frame_rmse = NULL;  /* the row's now */
        flicker_free(&L->fl);
        live_row_free(L);
        const struct flicker_result *r = &L->row->r;
        if (!rc)
            log_info("  %-15s flicker %.5f (floor %.5f%s)  in the band %.4f (floor %.4f)  p99 %.4f  rmse mean %.4f  "
                     "max %.4f%s", L->row->label, r->flicker, r->floor, r->meaningful ? "" : ": not above it",
                     r->flicker_penumbra, r->floor_penumbra, r->flicker_p99, r->rmse_mean, r->rmse_max,
                     L->row->nonfinite ? "  NON-FINITE VALUES" : "");
    }
    free(live), free(from), free(prev_distance);
    scene_setup_free(&ss);
    scene_unpose(&posed, base);
    return rc ? -1 : 0;
}

/* ---- variations --------------------------------------------------------- */

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

static void variation_free(struct variation *v)
{
    for (int i = 0; i < v->count; i++)
        free(v->texts[i]);
    v->count = 0;
}

/* The variable or technique parameter that v->name names, its reference
 * value into *reference and, for a parameter, a copy of its technique's
 * settings to check values on into *work. Returns 0 or -1 (logged). */
static int variation_target(const struct stability *st, struct variation *v, double *reference, void **work)
{
    const char *dot = strchr(v->name, '.');
    if (!dot) {
        int k = 0;
        while (k < VARY_PARAM && strcmp(stability_variables[k].name, v->name) != 0)
            k++;
        if (k == VARY_PARAM) {
            struct strbuf known = {0};
            for (int i = 0; i < VARY_PARAM; i++)
                strbuf_list_printf(&known, ", ", "%s", stability_variables[i].name);
            log_error("--vary: '%s' is neither %s nor a technique parameter T.P", v->name, known.data);
            strbuf_free(&known);
            return -1;
        }
        v->kind = (enum variable_kind)k;
        *reference = k == VARY_MAP_SIZE        ? st->shadow_map_size
                     : k == VARY_CASCADES      ? (st->cascades.count > 0 ? st->cascades.count : 1)
                     : k == VARY_CASCADE_LAMBDA ? st->cascades.lambda
                                               : stability_variables[k].reference;
        return 0;
    }
    char tech[64];
    snprintf(tech, sizeof tech, "%.*s", (int)(dot - v->name), v->name);
    v->kind = VARY_PARAM;
    if (!(v->t = technique_find(tech))) {
        log_error("--vary: unknown technique '%s' (see 'shadowbench list')", tech);
        return -1;
    }
    const void *base = settings_of(st, v->t);
    if (!base) {
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
    *work = memcpy(xmalloc(v->t->settings_size), base, v->t->settings_size);
    *reference = params_get(v->p, base);
    return 0;
}

/* One listed value, checked, into v's list. Returns 0 or -1 (logged). */
static int add_value(struct variation *v, const char *list, const char *text, void *work)
{
    double value = 0;
    int rc = 0;
    if (!*text) {
        log_error("--vary %s: an empty value in '%s'", v->name, list);
        return -1;
    }
    if (v->count == STABILITY_MAX_VALUES - 1) {  /* room for the reference */
        log_error("--vary %s: at most %d values", v->name, STABILITY_MAX_VALUES - 1);
        return -1;
    }
    if (v->kind == VARY_PARAM) {
        rc = params_set(v->t, work, v->p->name, text);
        value = rc ? 0 : params_get(v->p, work);
    } else if ((rc = util_parse_finite(v->name, text, &value)) == 0) {
        const bool whole = (v->kind != VARY_MAP_SIZE && v->kind != VARY_CASCADES) || value == floor(value);
        if (!whole || value < stability_variables[v->kind].lo || value > stability_variables[v->kind].hi) {
            log_error("--vary %s: %s is out of range [%g, %g]%s", v->name, text, stability_variables[v->kind].lo,
                      stability_variables[v->kind].hi, whole ? "" : " or not a whole number");
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
    return rc;
}

int stability_add_variation(struct stability *st, const char *spec)
{
    if (st->var_count == STABILITY_MAX_VARIATIONS) {
        log_error("--vary: at most %d", STABILITY_MAX_VARIATIONS);
        return -1;
    }
    struct variation *v = &st->vars[st->var_count];
    memset(v, 0, sizeof *v);
    const char *eq = strchr(spec, '=');
    if (!eq || eq == spec || !eq[1]) {
        log_error("--vary: '%s' is not NAME=V1,V2,... (see --help)", spec);
        return -1;
    }
    snprintf(v->name, sizeof v->name, "%.*s", (int)(eq - spec), spec);
    void *work = NULL;  /* VARY_PARAM: the technique's settings, for checking each value */
    double reference = NAN;
    int rc = variation_target(st, v, &reference, &work);
    char *copy = xstrdup(eq + 1), *rest = copy;
    for (char *text = strsep(&rest, ","); text && !rc; text = strsep(&rest, ","))
        rc = add_value(v, eq + 1, text, work);
    free(copy);
    /* The reference value is always measured: breaks are counted from it. */
    bool has_reference = false;
    for (int i = 0; i < v->count; i++)
        has_reference |= v->values[i] == reference;
    if (!rc && !has_reference) {
        if (v->kind == VARY_PARAM)
            v->texts[v->count] = xmalloc(64), params_value_text(v->t, settings_of(st, v->t), v->p->name,
                                                                v->texts[v->count], 64);
        else
            v->texts[v->count] = util_printf("%g", reference);
        v->values[v->count++] = reference;
    }
    free(work);
    for (int j = 0; j < st->var_count && !rc; j++)
        if (!strcmp(st->vars[j].name, v->name)) {
            log_error("--vary: %s is varied twice", v->name);
            rc = -1;
        }
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
    st->var_count++;
    return 0;
}

int stability_vary(struct stability *st, int s, int var)
{
    const struct scene *base = &st->scenes[s];
    const struct variation *v = &st->vars[var];
    int rc = 0;
    for (int k = 0; k < v->count && !rc; k++) {
        const double x = v->values[k];
        struct scene posed;
        scene_posed(base, &(struct scene_pose){.light_scale = v->kind == VARY_LIGHT_SCALE ? (float)x : 0}, &posed);
        struct scene_setup ss;
        struct cascade_settings cascades = st->cascades;
        if (v->kind == VARY_CASCADES)
            cascades.count = (int)x;
        if (v->kind == VARY_CASCADE_LAMBDA)
            cascades.split = CASCADE_SPLIT_PRACTICAL, cascades.lambda = (float)x;
        const struct scene_setup_desc desc = {st->width, st->height,
                                              v->kind == VARY_MAP_SIZE ? (int)x : st->shadow_map_size,
                                              st->gt_samples, 0, st->cache_dir,
                                              v->kind == VARY_DEPTH_RANGE ? (float)x : 0, &st->programs,
                                              &cascades};
        rc = scene_setup_open(&ss, &posed, &desc);
        for (int i = 0; i < st->technique_count && !rc; i++) {
            const struct technique *t = st->techniques[i];
            if (v->kind == VARY_PARAM && t != v->t)
                continue;
            void *settings = memcpy(xmalloc(t->settings_size), st->settings[i], t->settings_size);
            if (v->kind == VARY_PARAM)
                params_set(t, settings, v->p->name, v->texts[k]);  /* checked when parsed */
            struct metrics m = {0};
            rc = scene_setup_cell(&ss, t, settings, &m);
            free(settings);
            if (rc)
                break;
            st->points = xrealloc(st->points, sizeof *st->points * (size_t)(st->point_count + 1));
            st->points[st->point_count++] = (struct vary_point){s, var, k, t, m, false};
            log_info("  %s=%s %-10s rmse %.4f  penumbra_rmse %.4f  leak %.4f  dark %.4f%s", v->name, v->texts[k],
                     t->name, m.rmse, m.penumbra_rmse, m.leak_fraction, m.dark_fraction,
                     m.nonfinite ? "  NON-FINITE VALUES" : "");
        }
        scene_setup_free(&ss);
        scene_unpose(&posed, base);
    }
    return rc ? -1 : 0;
}

const struct vary_point *stability_point(const struct stability *st, int s, int var, int value,
                                         const struct technique *t)
{
    for (int i = 0; i < st->point_count; i++) {
        const struct vary_point *p = &st->points[i];
        if (p->scene == s && p->variation == var && p->value == value && p->t == t)
            return p;
    }
    return NULL;
}

/* The metrics of t's points on scene s under var, by value (NULL: none). */
static void point_metrics(const struct stability *st, int s, int var, const struct technique *t,
                          const struct metrics **m)
{
    for (int k = 0; k < st->vars[var].count; k++) {
        const struct vary_point *p = stability_point(st, s, var, k, t);
        m[k] = p ? &p->m : NULL;
    }
}

void stability_judge(struct stability *st)
{
    for (int i = 0; i < st->point_count; i++) {
        struct vary_point *p = &st->points[i];
        const int reference = st->vars[p->variation].reference;
        const struct vary_point *ref = stability_point(st, p->scene, p->variation, reference, p->t);
        p->broken = ref && break_rule_broken(&p->m, &ref->m);
    }
}

void stability_break_points(const struct stability *st, int s, int var, const struct technique *t, int *below,
                            int *above)
{
    const struct metrics *m[STABILITY_MAX_VALUES];
    point_metrics(st, s, var, t, m);
    break_rule_points(m, st->vars[var].count, st->vars[var].reference, below, above);
}

void stability_broken_values(const struct stability *st, int s, int var, const struct technique *t,
                             struct strbuf *out)
{
    const struct variation *v = &st->vars[var];
    for (int k = 0; k < v->count; k++) {
        const struct vary_point *p = stability_point(st, s, var, k, t);
        if (k != v->reference && p && p->broken)  /* p->broken: against the reference, when measured */
            strbuf_list_printf(out, ", ", "%s", v->texts[k]);
    }
}

void stability_free(struct stability *st)
{
    for (int i = 0; i < st->var_count; i++)
        variation_free(&st->vars[i]);
    programs_free(&st->programs);
    for (int i = 0; i < st->row_count; i++)
        free(st->rows[i].frame_rmse);
    free(st->rows), free(st->points), free(st->motions);
    st->rows = NULL, st->points = NULL, st->motions = NULL;
    st->row_count = st->point_count = st->motion_count = st->var_count = 0;
}
