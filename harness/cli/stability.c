/* shadowbench stability: motions (flicker) and variations (break points);
 * pipeline/stability.h says what it measures, output/stability_page.h
 * what it writes. */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "output/out_dir.h"
#include "output/stability_page.h"
#include "pipeline/stability.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char *const stability_default_scenes[STABILITY_DEFAULT_SCENES] = {"floating_box_sphere",
                                                                        "overlapping_occluders", "sun_contact"};
const char *const stability_default_motions[STABILITY_DEFAULT_MOTIONS] = {"static", "light_shift", "light_rotate",
                                                                          "camera_shift", "scene"};
const char *const stability_default_varies[STABILITY_DEFAULT_VARIES] = {
    "shadow_map_size=256,512,1024,2048,4096", "light_scale=0.25,0.5,1,2,4", "depth_range=1,10,100,1000,10000"};

/* The motions of the command line (or the defaults) and, with "scene", of
 * each scene; the variations. Returns 0 or -1 (logged). */
static int plan(struct stability *st, const struct options *o)
{
    const bool defaults = !o->motion_count && !o->vary_count;
    const int motion_count = defaults ? (int)ARRAY_SIZE(stability_default_motions) : o->motion_count;
    const int vary_count = defaults ? (int)ARRAY_SIZE(stability_default_varies) : o->vary_count;
    bool scene_motions = false;  /* --motion scene: each scene's own motions */
    for (int i = 0; i < motion_count; i++) {
        const char *spec = defaults ? stability_default_motions[i] : o->motions[i];
        struct motion m;
        if (!strcmp(spec, "scene")) {
            if (scene_motions) {
                log_error("--motion: scene is given twice");
                return -1;
            }
            scene_motions = true;
        } else if (motion_parse("--motion", spec, -1, -1, &m) != 0 || stability_add_motion(st, &m) != 0) {
            return -1;
        }
    }
    for (int i = 0; i < vary_count; i++)
        if (stability_add_variation(st, defaults ? stability_default_varies[i] : o->varies[i]) != 0)
            return -1;
    return scene_motions ? 1 : 0;
}

/* Each scene's own motions (with --motion scene). Returns 0 or -1. */
static int add_scene_motions(struct stability *st, const struct scene *scenes, int scene_count)
{
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < scenes[s].motion_count; i++) {
            struct motion m;
            char *what = util_printf("%s: extras.shadowbench.motions[%d]", scenes[s].path, i);
            const int bad = motion_parse(what, scenes[s].motions[i], s, i, &m) || stability_add_motion(st, &m);
            free(what);
            if (bad)
                return -1;
        }
    return 0;
}

/* The exit status of the study: NaN/Inf rows, or frames or values with
 * nothing to score, fail (said once). */
static int judge(const struct stability *st)
{
    long bad = 0;
    for (int i = 0; i < st->row_count; i++)
        bad += st->rows[i].nonfinite > 0 || !isfinite(st->rows[i].r.flicker) ||
               st->rows[i].r.scored_frames < st->rows[i].r.frames;
    for (int i = 0; i < st->point_count; i++)
        bad += st->points[i].m.nonfinite > 0 || !metrics_scored(&st->points[i].m);
    if (bad)
        log_error("%ld row(s) with NaN/Inf visibility, or a frame or value with nothing to score (see "
                  "stability.csv: scored_frames, empty metrics)", bad);
    return bad ? EXIT_CHECK_FAILED : EXIT_OK;
}

/* The study's units, in the order it runs them: each motion on each scene
 * it runs on, then each variation on each scene (motion or variation -1). */
struct unit {
    int scene, motion, variation;
};

/* The units of st into *out (malloc'ed), their owners (1..shards) into
 * *owner: balanced by expected cost (a motion's frames, a variation's
 * values, times the techniques they render). Returns how many. */
static int plan_units(const struct stability *st, int shards, struct unit **out, int **owner)
{
    const int max = st->scene_count * (st->motion_count + st->var_count) + 1;
    struct unit *u = xmalloc(sizeof *u * (size_t)max);
    double *cost = xmalloc(sizeof *cost * (size_t)max);
    int n = 0;
    for (int s = 0; s < st->scene_count; s++)
        for (int m = 0; m < st->motion_count; m++)
            if (motion_on(&st->motions[m], s)) {
                cost[n] = (double)st->frames * st->technique_count;
                u[n++] = (struct unit){s, m, -1};
            }
    for (int s = 0; s < st->scene_count; s++)
        for (int v = 0; v < st->var_count; v++) {
            cost[n] = (double)st->vars[v].count * (st->vars[v].kind == VARY_PARAM ? 1 : st->technique_count);
            u[n++] = (struct unit){s, -1, v};
        }
    *owner = xcalloc((size_t)n + 1, sizeof **owner);
    shard_split_balanced(cost, n, shards, *owner);
    free(cost);
    *out = u;
    return n;
}

/* A flicker result's fields: X(name, kind): d a double, n a count, b a
 * bool; how each is written into a JSON object and read from one. */
#define FLICKER_FIELDS(X)                                                                                   \
    X(flicker, d) X(flicker_p99, d) X(floor, d) X(flicker_penumbra, d) X(floor_penumbra, d) X(meaningful, b) \
    X(rmse_mean, d) X(rmse_max, d) X(rmse_jump, d) X(pairs_pixels, n) X(band_pixels, n) X(mask_changes, n)  \
    X(frames, n) X(scored_frames, n)
#define PUT_d(o, k, x) util_json_add_number(o, k, x)
#define PUT_n(o, k, x) cJSON_AddNumberToObject(o, k, (double)(x))
#define PUT_b(o, k, x) cJSON_AddBoolToObject(o, k, x)
#define GET_d(o, k, x) ((x) = util_json_number(o, k), true)
#define GET_n(o, k, x) (util_json_whole(o, k, 0, 1e15, &whole) && ((x) = whole, true))
#define GET_b(o, k, x) ((x) = cJSON_IsTrue(cJSON_GetObjectItem(o, k)), true)

/* The shard's record of its rows and points, every number as measured
 * (for the merge, docs/scale-out.md). */
static cJSON *results_json(const struct stability *st)
{
    cJSON *j = cJSON_CreateObject(), *rows = cJSON_AddArrayToObject(j, "rows"),
          *points = cJSON_AddArrayToObject(j, "points");
    for (int i = 0; i < st->row_count; i++) {
        const struct motion_row *r = &st->rows[i];
        cJSON *o = cJSON_CreateObject(), *f = cJSON_CreateObject(), *frames = cJSON_CreateArray();
        cJSON_AddNumberToObject(o, "scene", r->scene);
        cJSON_AddNumberToObject(o, "motion", r->motion);
        cJSON_AddStringToObject(o, "technique", r->t->name);
        cJSON_AddBoolToObject(o, "animated", r->animated);
        cJSON_AddBoolToObject(o, "accumulated", r->accumulated);
#define X(name, kind) PUT_##kind(f, #name, r->r.name);
        FLICKER_FIELDS(X)
#undef X
        cJSON_AddItemToObject(o, "flicker", f);
        for (int k = 0; k < r->r.frames; k++) {
            cJSON *v = cJSON_CreateObject();
            util_json_add_number(v, "rmse", r->frame_rmse[k]);
            cJSON_AddItemToArray(frames, v);
        }
        cJSON_AddItemToObject(o, "frame_rmse", frames);
        cJSON_AddNumberToObject(o, "nonfinite", (double)r->nonfinite);
        cJSON_AddItemToArray(rows, o);
    }
    for (int i = 0; i < st->point_count; i++) {
        const struct vary_point *p = &st->points[i];
        cJSON *o = cJSON_CreateObject(), *m = cJSON_CreateObject();
        cJSON_AddNumberToObject(o, "scene", p->scene);
        cJSON_AddNumberToObject(o, "variation", p->variation);
        cJSON_AddNumberToObject(o, "value", p->value);
        cJSON_AddStringToObject(o, "technique", p->t->name);
        for (int k = 0; k < METRIC_COUNT; k++)
            util_json_add_number(m, metric_info[k].key, metrics_value(&p->m, k));
        cJSON_AddItemToObject(o, "metrics", m);
        cJSON_AddItemToArray(points, o);
    }
    return j;
}

/* Row e of a shard's record into r, its unit's (st's frames): 0, or -1
 * when it is not a row this study makes. */
static int read_row(const struct stability *st, const cJSON *e, const struct unit *u, const struct technique *t,
                    struct motion_row *r)
{
    const cJSON *f = cJSON_GetObjectItem(e, "flicker"), *frames = cJSON_GetObjectItem(e, "frame_rmse");
    *r = (struct motion_row){.scene = u->scene, .motion = u->motion, .t = t,
                             .animated = cJSON_IsTrue(cJSON_GetObjectItem(e, "animated")),
                             .accumulated = cJSON_IsTrue(cJSON_GetObjectItem(e, "accumulated"))};
    snprintf(r->label, sizeof r->label, "%s%s%s", t->name, r->animated ? "~anim" : "", r->accumulated ? "+ema" : "");
    long whole;
    bool ok = util_json_whole(e, "nonfinite", 0, 1e15, &r->nonfinite);
#define X(name, kind) ok = ok && GET_##kind(f, #name, r->r.name);
    FLICKER_FIELDS(X)
#undef X
    if (!ok || r->r.frames > st->frames || r->r.scored_frames > r->r.frames ||
        cJSON_GetArraySize(frames) != r->r.frames)
        return -1;
    r->frame_rmse = xcalloc((size_t)r->r.frames + 1, sizeof *r->frame_rmse);
    for (int k = 0; k < r->r.frames; k++)
        r->frame_rmse[k] = util_json_number(cJSON_GetArrayItem(frames, k), "rmse");
    return 0;
}

/* Unit u's rows and points from a shard's record into st, exactly those
 * the study makes: a motion's rows technique by technique (each per frame
 * and accumulated, then, where its program animates noise, the same
 * animated), a variation's points value by value, technique by technique.
 * Returns 0 or -1 (anything else: not the shard that owns it). */
static int read_unit(struct stability *st, const cJSON *record, const struct unit *u)
{
    const cJSON *e;
    long scene, index, value;
    int next = 0, pair = 0, k = 0;  /* motion: the technique next, rows of it so far; variation: the point next */
    const struct variation *v = u->variation >= 0 ? &st->vars[u->variation] : NULL;
    const int per_value = v && v->kind == VARY_PARAM ? 1 : st->technique_count;
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(record, u->motion >= 0 ? "rows" : "points")) {
        if (!util_json_whole(e, "scene", 0, st->scene_count - 1, &scene) || scene != u->scene ||
            !util_json_whole(e, u->motion >= 0 ? "motion" : "variation", 0, 1e9, &index) ||
            index != (u->motion >= 0 ? u->motion : u->variation))
            continue;
        const struct technique *t = technique_find(cJSON_GetStringValue(cJSON_GetObjectItem(e, "technique")) ?: "");
        if (u->motion >= 0) {
            struct motion_row r;
            if (pair == 4 || (pair == 2 && next + 1 < st->technique_count && t == st->techniques[next + 1]))
                next++, pair = 0;  /* the next technique's rows */
            if (next >= st->technique_count || t != st->techniques[next] || read_row(st, e, u, t, &r) != 0)
                return -1;
            if (r.accumulated != (pair % 2 == 1) || (pair >= 2 && !r.animated) ||
                (pair % 2 == 1 && r.animated != st->rows[st->row_count - 1].animated)) {
                free(r.frame_rmse);
                return -1;
            }
            st->rows = xrealloc(st->rows, sizeof *st->rows * (size_t)(st->row_count + 1));
            st->rows[st->row_count++] = r;
            pair++;
        } else {
            const struct technique *want = v->kind == VARY_PARAM ? v->t : st->techniques[k % per_value];
            struct vary_point p = {.scene = u->scene, .variation = u->variation, .t = t};
            if (k >= v->count * per_value || t != want || !util_json_whole(e, "value", 0, v->count - 1, &value) ||
                value != k / per_value || metrics_read_json(cJSON_GetObjectItem(e, "metrics"), &p.m) != 0)
                return -1;
            p.value = (int)value;
            st->points = xrealloc(st->points, sizeof *st->points * (size_t)(st->point_count + 1));
            st->points[st->point_count++] = p;
            k++;
        }
    }
    return u->motion >= 0 ? (next == st->technique_count - 1 && (pair == 2 || pair == 4) ? 0 : -1)
                          : (k == v->count * per_value ? 0 : -1);
}

/* The study o describes, planned into st over scenes (loaded into
 * scenes[0..*scene_count-1]). Returns 0 or -1 (logged). */
static int open_study(const struct options *o, struct stability *st, struct scene *scenes, int *scene_count)
{
    *st = (struct stability){.width = o->width, .height = o->height, .gt_samples = o->gt_samples,
                             .shadow_map_size = o->shadow_map_size, .frames = o->frames,
                             .accumulate = o->accumulate, .cache_dir = o->cache_dir,
                             .technique_count = o->technique_count, .scenes = scenes, .cascades = o->cascades};
    for (int i = 0; i < o->technique_count; i++)
        st->techniques[i] = o->techniques[i], st->settings[i] = cli_settings(o, o->techniques[i]);
    const int scene_motions = plan(st, o);
    if (scene_motions < 0)
        return -1;
    if (o->gt_samples < 4) {  /* the floor compares two halves of the samples */
        log_error("--gt-samples: stability needs at least 4 (its noise floor compares two halves of the samples)");
        return -1;
    }
    if (cli_load_scenes(o, stability_default_scenes, (int)ARRAY_SIZE(stability_default_scenes), scenes,
                        CLI_MAX_SCENES, scene_count) != 0)
        return -1;
    st->scene_count = *scene_count;
    if (scene_motions && add_scene_motions(st, scenes, *scene_count) != 0)
        return -1;
    if (o->motion_count && !st->motion_count) {  /* only --motion scene */
        log_error("--motion scene: none of the scenes lists motions of its own (extras.shadowbench.motions)");
        return -1;
    }
    return stability_check_nodes(st);
}

/* The study's units in its order, as one number (cli_merge_plan). */
static uint64_t stability_plan(const struct stability *st, const struct unit *u, int n)
{
    uint64_t h = UTIL_HASH_INIT;
    for (int i = 0; i < n; i++)
        h = cli_plan_add(cli_plan_add(h, st->scenes[u[i].scene].name),
                         u[i].motion >= 0 ? st->motions[u[i].motion].label : st->vars[u[i].variation].name);
    return h;
}

/* run.json's keys of the study (stability.json's "run"). */
static cJSON *study_record(const struct options *o, double seconds)
{
    cJSON *run = cli_run_record(o, false, seconds);
    cJSON_AddNumberToObject(run, "accumulate", o->accumulate);
    return run;
}

int stability_main(const struct options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE, *owner = NULL, unit_count = 0;
    struct stability st = {0};
    struct stability_output so = {0};
    struct unit *units = NULL;
    if (open_study(o, &st, scenes, &scene_count) != 0 || out_dir_claim(o->out_dir) != 0 ||
        cli_gl_open(o, o->gl) != 0)
        goto out;
    cli_shard_begin(o);
    unit_count = plan_units(&st, o->shard.count ? o->shard.count : 1, &units, &owner);
    status = EXIT_CHECK_FAILED;
    stability_output_begin(&so, &st, o->out_dir);
    st.on_frame = stability_output_frame, st.user = &so;
    int shared = 0, mine = 0;
    for (int m = 0; m < st.motion_count; m++)
        shared += st.motions[m].scene < 0;
    for (int i = 0; i < unit_count; i++)
        mine += shard_owns(&o->shard, owner[i]);
    if (o->shard.count)
        log_info("stability: shard %d of %d: %d of the %d motions and variations on their scenes", o->shard.index,
                 o->shard.count, mine, unit_count);
    log_info("stability: %d scene(s), %d technique(s), %d motion(s) and %d of the scenes' own, of %d frames, %d "
             "variation(s), %dx%d, %d GT samples, %d^2 shadow map, on %s", scene_count, o->technique_count, shared,
             st.motion_count - shared, o->frames, st.var_count, o->width, o->height, o->gt_samples,
             o->shadow_map_size, gl_context_renderer());
    int rc = 0;
    for (int i = 0; i < unit_count && !rc; i++) {
        const struct unit *u = &units[i];
        if (!shard_owns(&o->shard, owner[i]))
            continue;
        if (u->motion >= 0) {
            log_info("scene %s, motion %s", scenes[u->scene].name, st.motions[u->motion].label);
            rc = stability_motion(&st, u->scene, u->motion) || stability_output_frames(&so);
        } else {
            log_info("scene %s, varying %s", scenes[u->scene].name, st.vars[u->variation].name);
            rc = stability_vary(&st, u->scene, u->variation);
        }
    }
    if (!rc) {
        util_signals_defer();  /* its files are written as a set: whole, then the status (run.c) */
        stability_judge(&st);
        const double seconds = (util_now_ms() - start) * 1e-3;
        cJSON *run = study_record(o, seconds);
        rc = stability_output_write(&so, run);
        cJSON_Delete(run);
        cJSON *more = cli_shard_more(seconds, stability_plan(&st, units, unit_count)), *results = results_json(&st);
        util_json_merge(more, results);
        cJSON_Delete(results);
        if (rc)
            cJSON_Delete(more);
        else
            rc = cli_shard_end(o, scenes, scene_count, more) != 0;
    }
    if (!rc)
        status = judge(&st);
    cli_done(o, status, !rc, "stability", OUTPUT_STABILITY_PAGE, "data", OUTPUT_STABILITY_CSV, start);
    programs_free(&st.programs);  /* with its context */
    gl_context_destroy();
out:
    free(units), free(owner);
    stability_output_free(&so);
    stability_free(&st);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}

int stability_merge(const struct options *o, const struct merge_input *in)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE, *owner = NULL, unit_count = 0;
    struct stability st = {0};
    struct stability_output so = {0};
    struct unit *units = NULL;
    if (open_study(o, &st, scenes, &scene_count) != 0)
        goto out;
    unit_count = plan_units(&st, in->count, &units, &owner);
    if (cli_merge_plan(in, stability_plan(&st, units, unit_count)) != 0)
        goto out;
    for (int i = 0; i < unit_count; i++)  /* each unit's rows and points, in the study's order */
        if (read_unit(&st, in->records[owner[i]], &units[i]) != 0) {
            log_error("merge: %s: its shard.json holds no results of scene %s's %s %s, which it owns",
                      in->dirs[owner[i]], scenes[units[i].scene].name, units[i].motion >= 0 ? "motion" : "variation",
                      units[i].motion >= 0 ? st.motions[units[i].motion].label : st.vars[units[i].variation].name);
            goto out;
        }
    if (out_dir_claim(o->out_dir) != 0)
        goto out;
    cli_shard_begin(o);  /* a shard's record left in OUT would make it pass for one */
    status = EXIT_CHECK_FAILED;  /* the shards are read: what fails now is a write */
    stability_output_begin(&so, &st, o->out_dir);
    /* each row's frames from the shard that ran it, where it wrote them */
    for (int i = 0, k = 0; i < unit_count; i++)
        for (; k < st.row_count && st.rows[k].scene == units[i].scene && st.rows[k].motion == units[i].motion; k++)
            for (int f = 0; f < 2; f++) {
                const struct motion_row *r = &st.rows[k];
                char *at = util_printf("%s/%s/%s/%s", scenes[r->scene].name, st.motions[r->motion].label, r->label,
                                       stability_frame_files[f]),
                     *from = util_printf("%s/%s", in->dirs[owner[i]], at), *to = util_printf("%s/%s", o->out_dir, at);
                const int rc = r->accumulated ? 0 : cli_copy_file(from, to);  /* accumulated rows have none */
                free(at), free(from), free(to);
                if (rc)
                    goto out;
            }
    util_signals_defer();
    stability_judge(&st);
    cJSON *run = study_record(o, cli_merge_seconds(in));
    cli_merge_record(run, in);
    const int rc = stability_output_write(&so, run);
    cJSON_Delete(run);
    status = rc ? EXIT_CHECK_FAILED : judge(&st);
    cli_done(o, status, !rc, "merge", OUTPUT_STABILITY_PAGE, "data", OUTPUT_STABILITY_CSV, start);
out:
    free(units), free(owner);
    stability_output_free(&so);
    stability_free(&st);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
