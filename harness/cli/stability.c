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

int stability_main(const struct options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE;
    struct stability st = {.width = o->width, .height = o->height, .gt_samples = o->gt_samples,
                           .shadow_map_size = o->shadow_map_size, .frames = o->frames, .accumulate = o->accumulate,
                           .cache_dir = o->cache_dir, .technique_count = o->technique_count, .scenes = scenes,
                           .cascades = o->cascades};
    struct stability_output so = {0};
    for (int i = 0; i < o->technique_count; i++)
        st.techniques[i] = o->techniques[i], st.settings[i] = cli_settings(o, o->techniques[i]);
    const int scene_motions = plan(&st, o);
    if (scene_motions < 0)
        goto out;
    if (o->gt_samples < 4) {  /* the floor compares two halves of the samples */
        log_error("--gt-samples: stability needs at least 4 (its noise floor compares two halves of the samples)");
        goto out;
    }
    if (cli_load_scenes(o, stability_default_scenes, (int)ARRAY_SIZE(stability_default_scenes), scenes,
                        CLI_MAX_SCENES, &scene_count) != 0)
        goto out;
    st.scene_count = scene_count;
    if (scene_motions && add_scene_motions(&st, scenes, scene_count) != 0)
        goto out;
    if (o->motion_count && !st.motion_count) {  /* only --motion scene */
        log_error("--motion scene: none of the scenes lists motions of its own (extras.shadowbench.motions)");
        goto out;
    }
    if (stability_check_nodes(&st) != 0 || out_dir_claim(o->out_dir) != 0 || cli_gl_open(o, o->gl) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    stability_output_begin(&so, &st, o->out_dir);
    st.on_frame = stability_output_frame, st.user = &so;
    int shared = 0;
    for (int m = 0; m < st.motion_count; m++)
        shared += st.motions[m].scene < 0;
    log_info("stability: %d scene(s), %d technique(s), %d motion(s) and %d of the scenes' own, of %d frames, %d "
             "variation(s), %dx%d, %d GT samples, %d^2 shadow map, on %s", scene_count, o->technique_count, shared,
             st.motion_count - shared, o->frames, st.var_count, o->width, o->height, o->gt_samples,
             o->shadow_map_size, gl_context_renderer());
    int rc = 0;
    for (int s = 0; s < scene_count && !rc; s++)
        for (int m = 0; m < st.motion_count && !rc; m++)
            if (motion_on(&st.motions[m], s)) {
                log_info("scene %s, motion %s", scenes[s].name, st.motions[m].label);
                rc = stability_motion(&st, s, m) || stability_output_frames(&so);
            }
    for (int s = 0; s < scene_count && !rc; s++)
        for (int v = 0; v < st.var_count && !rc; v++) {
            log_info("scene %s, varying %s", scenes[s].name, st.vars[v].name);
            rc = stability_vary(&st, s, v);
        }
    if (!rc) {
        util_signals_defer();  /* its files are written as a set: whole, then the status (run.c) */
        stability_judge(&st);
        cJSON *run = cli_run_record(o, false, (util_now_ms() - start) * 1e-3);
        cJSON_AddNumberToObject(run, "accumulate", o->accumulate);
        rc = stability_output_write(&so, run);
        cJSON_Delete(run);
    }
    if (!rc)
        status = judge(&st);
    cli_done(o, status, !rc, "stability", OUTPUT_STABILITY_PAGE, "data", OUTPUT_STABILITY_CSV, start);
    programs_free(&st.programs);  /* with its context */
    gl_context_destroy();
out:
    stability_output_free(&so);
    stability_free(&st);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
