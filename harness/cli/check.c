/* shadowbench check: the regression check (pipeline/regression.h for its
 * cells, score/baseline.h for the format and the comparison). One line per
 * cell; what moved under it; check.html of the cells that moved. */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "output/check_page.h"
#include "output/out_dir.h"
#include "output/provenance.h"
#include "output/results_set.h"
#include "pipeline/regression.h"

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static void print_status(const char *status, const struct regression_cell *c, const char *extra)
{
    printf("  %-11s %-22s %s%s\n", status, c->scene->name, c->label, extra);
    fflush(stdout);  /* progress, in order with stderr's */
}

/* c compared with its baseline: its line and, unless it passed, what moved. */
static void compare(struct regression_cell *c, const struct options *o)
{
    const struct baseline_comparison *k = &c->cmp;
    baseline_compare(&c->base, &c->now, c->v, &c->cmp);
    c->compared = true;
    print_status(baseline_status_names[k->status], c, "");
    if (k->status != BASELINE_PASS || k->picture_moved) {
        for (int g = 0; g < BASELINE_GUARDS; g++) {
            const int m = baseline_guards[g].metric;
            const double base = baseline_metric(&c->base, m), now = metrics_value(&c->now, m);
            if (k->direction[g])
                printf("      %-16s %10.5f -> %10.5f  (%+.5f, tolerance %.5f: %s)\n", metric_info[m].key, base, now,
                       now - base, baseline_tolerance(&c->base, m), k->direction[g] > 0 ? "worse" : "better");
        }
        printf("      picture: %.2f %% of pixels moved by more than %g (allowed %.2f %%)%s\n",
               100.0 * k->moved_fraction, c->base.pixel_threshold, 100.0 * c->base.max_moved,
               k->picture_moved && !k->worse && !k->better ? ", with no metric better" : "");
    }
    if (k->status == BASELINE_IMPROVED)
        printf("      record it: shadowbench check --update --scene %s --technique %s --baselines %s\n",
               c->scene->name, c->t->name, o->baselines_dir);
    /* The baseline's parameters against what its name means today. */
    if (!regression_params_current(c)) {
        printf("      its recorded parameters are no longer what '%s' means (a default changed?): record it "
               "anew\n", c->label);
        if (k->status == BASELINE_PASS)
            c->cmp.status = BASELINE_REGRESSED;
    }
}

/* The scene's setup for cell c: kept while the cells agree on it, with the
 * ground truths of the other seeds when recording. Returns 0 or -1. */
static int setup_for(struct scene_setup *ss, struct baseline_setup *open, struct gt_image *extra,
                     const struct regression_cell *c, const struct options *o, struct program_cache *programs)
{
    if (ss->scene && baseline_setup_equal(open, &c->setup))
        return 0;
    scene_setup_free(ss);
    for (int k = 0; k < BASELINE_SEEDS - 1; k++)
        gt_image_free(&extra[k]);
    const struct baseline_setup *b = &c->setup;
    if (scene_setup_open(ss, c->scene, &(struct scene_setup_desc){b->width, b->height, b->shadow_map_size,
                                                                   b->gt_samples, b->gt_seed, o->cache_dir, 0,
                                                                   programs, NULL}) != 0)
        return -1;
    ss->receiver.noise_frame = REGRESSION_NOISE_FRAME;
    *open = *b;
    for (int k = 0; k < BASELINE_SEEDS - 1 && o->update; k++) {
        const struct gt_desc d = {.width = b->width, .height = b->height, .samples = b->gt_samples,
                                  .seed = b->gt_seed + 1 + (uint32_t)k};
        if (gt_obtain(c->scene, &ss->cascades.view, &d, o->cache_dir, &extra[k]) != 0)
            return -1;
    }
    return 0;
}

/* Renders, compares (or, into the baselines folder `record`, records)
 * every cell of one scene. Returns -1 on a runtime error, else the number
 * of failures (regressions, missing baselines, idle parameters,
 * improvements with --strict). */
static int check_scene(struct regression *r, const struct scene *s, const struct options *o, const cJSON *provenance,
                       const char *record, struct program_cache *programs)
{
    int failures = 0;
    struct scene_setup ss = {0};
    struct baseline_setup open = {0};
    struct gt_image extra[BASELINE_SEEDS - 1] = {0};
    for (int i = 0; i < r->count && failures >= 0; i++) {
        struct regression_cell *c = &r->cells[i];
        if (c->scene != s)
            continue;
        if (!c->base.doc && !o->update) {
            c->cmp.status = BASELINE_MISSING;
            char *how = util_printf("   (record it: shadowbench check --update --scene %s --technique %s "
                                    "--baselines %s)", s->name, c->t->name, o->baselines_dir);
            print_status(baseline_status_names[BASELINE_MISSING], c, how);
            free(how);
            failures++;
            continue;
        }
        bool comparable = c->base.doc != NULL;
        if (o->update) {  /* recorded anew: today's settings for its name */
            comparable = comparable && baseline_setup_equal(&c->setup, &baseline_setup_default) &&
                         regression_params_current(c);
            memcpy(c->settings, c->label_settings, c->t->settings_size);
            c->setup = baseline_setup_default;
        }
        if (setup_for(&ss, &open, extra, c, o, programs) != 0 || regression_render(&ss, c) != 0) {
            failures = -1;
            break;
        }
        if (o->update) {
            baseline_spread(c->v, ss.distance, metrics_depth_tolerance(c->t->depth_tolerance), &c->now, extra, BASELINE_SEEDS - 1,
                            c->spread);
            if (comparable)
                compare(c, o);
            else
                print_status("new", c, c->base.doc ? "   (its settings changed: not compared)" : "");
            const struct baseline_record rec = {s->name, c->label, c->t, c->settings, c->setup, &c->now, c->v,
                                                c->spread, provenance};
            char *json = regression_file(record, c, "json"), *png = regression_file(record, c, "png");
            if (baseline_write(json, png, &rec) != 0)
                failures = -1;
            free(json), free(png);
        } else {
            compare(c, o);
            failures += c->cmp.status == BASELINE_REGRESSED || (c->cmp.status == BASELINE_IMPROVED && o->strict);
        }
        if (failures >= 0 && c->declared) {
            struct regression_param idle[64];
            const int n = regression_idle_params(&ss, c, idle, 64);
            for (int k = 0; k < n; k++)
                printf("  IDLE        %-22s %s: setting %s.%s back to %s changes no pixel (is it used?)\n", s->name,
                       c->label, idle[k].t->name, idle[k].p->name, idle[k].def);
            failures += n;
        }
    }
    scene_setup_free(&ss);
    for (int k = 0; k < BASELINE_SEEDS - 1; k++)
        gt_image_free(&extra[k]);
    return failures;
}

/* The baselines folder is a folder (with --update, claimed and its next
 * set opened: the cells are recorded as one set), and --out is not it or
 * inside it: the page's pictures would overwrite the baselines'. Returns 0
 * or -1 (logged). */
static int check_folders(const struct options *o, struct results_set *record)
{
    struct stat st;
    if (stat(o->baselines_dir, &st) == 0 && !S_ISDIR(st.st_mode)) {
        log_error("--baselines %s: not a folder", o->baselines_dir);
        return -1;
    }
    const bool inside = util_path_within(o->out_dir, o->baselines_dir);
    if (inside)
        log_error("--out %s: inside the baselines folder %s (its pictures would overwrite them)", o->out_dir,
                  o->baselines_dir);
    if (inside || (o->update && results_set_open(record, o->baselines_dir, 2) != 0))
        return -1;
    return out_dir_claim(o->out_dir);
}

/* With every shipped scene checked, the folders of the baselines folder
 * that no scene is called (a scene renamed or removed, or a user's own not
 * named with --scene): their baselines are not checked. Each said; returns
 * how many. */
static int orphans(const struct options *o, const struct scene *scenes, int scene_count)
{
    struct dirent **names = NULL;
    const int count = scandir(o->baselines_dir, &names, NULL, alphasort);
    int n = 0;
    for (int i = 0; i < count; i++) {
        const char *name = names[i]->d_name;
        char *path = util_printf("%s/%s", o->baselines_dir, name);
        bool known = name[0] == '.' || !util_is_dir(path);
        for (int s = 0; s < scene_count && !known; s++)
            known = strcmp(scenes[s].name, name) == 0;
        if (!known) {
            char *shown = xstrdup(name);  /* a folder's name may hold a newline or a terminal escape */
            util_printable(shown);
            printf("  ORPHANED    %s/%s: no shipped scene is called '%s', so none of its baselines is checked "
                   "(remove the folder, or name its scene with --scene)\n", o->baselines_dir, shown, shown);
            free(shown);
            n++;
        }
        free(path);
        free(names[i]);
    }
    free(names);
    return n;
}

/* Every cell's baseline read; --update repairs what it cannot read. */
static int read_baselines(struct regression *r, const struct options *o)
{
    for (int i = 0; i < r->count; i++) {
        struct regression_cell *c = &r->cells[i];
        const enum log_level level = log_get_level();
        if (o->update)
            log_set_level(LOG_NONE);
        const int rc = regression_read(c);
        log_set_level(level);
        if (rc == 0)
            continue;
        if (!o->update)
            return -1;
        log_warn("%s: not readable by this build (see check without --update): recorded anew", c->json_path);
        baseline_free(&c->base);
    }
    return 0;
}

int check_main(const struct options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE;
    struct regression r = {.baselines_dir = o->baselines_dir, .tuned_dir = o->tuned_dir};
    struct program_cache programs = {0};
    struct results_set record = {0};
    cJSON *provenance = NULL;
    if ((o->update && cli_require_committed(o, "check --update") != 0) ||
        cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0 || check_folders(o, &record) != 0 ||
        regression_collect(&r, scenes, scene_count, o->techniques, o->technique_count) != 0 ||
        read_baselines(&r, o) != 0)
        goto out;
    if (cli_gl_open(o, o->gl) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    provenance = provenance_json(o->argc, o->argv, false, o->timing);
    printf("check: %d cells on %d scene(s) against %s%s\n", r.count, scene_count, o->baselines_dir,
           o->update ? " (recording them anew)" : "");
    int failures = 0;
    for (int s = 0; s < scene_count && failures >= 0; s++) {
        const int f = check_scene(&r, &scenes[s], o, provenance, record.next, &programs);
        failures = f < 0 ? -1 : failures + f;
    }
    if (failures >= 0 && o->scene_count == 0) {  /* every scene: every parameter set by a declared cell */
        struct regression_param missing[256];
        const int n = regression_uncovered(&r, o->techniques, o->technique_count, missing, 256);
        for (int k = 0; k < n; k++)
            printf("  UNCOVERED   %s.%s: no cell sets it away from its default (add one to the .regression cells "
                   "of techniques/%s.c)\n", missing[k].t->name, missing[k].p->name, missing[k].t->name);
        failures += n;
        const int orphaned = orphans(o, scenes, scene_count);
        failures += o->strict ? orphaned : 0;
    }
    if (failures >= 0 && o->update) {  /* the new baselines as one set, held from signals (run.c) */
        util_signals_defer();
        failures = results_set_commit(&record) != 0 ? -1 : failures;
        util_signals_finished(failures == 0 ? EXIT_OK : EXIT_CHECK_FAILED);
    }
    if (failures >= 0 && check_page_write(&r, o->out_dir) != 0)
        failures = -1;
    if (failures >= 0) {
        int n[4] = {0};
        for (int i = 0; i < r.count; i++)
            n[r.cells[i].cmp.status]++;
        printf("check: %d passed, %d REGRESSED, %d improved, %d without a baseline%s; %.1f s; page of moved cells: "
               "%s/%s\n", n[BASELINE_PASS], n[BASELINE_REGRESSED], n[BASELINE_IMPROVED], n[BASELINE_MISSING],
               o->update ? " (recorded anew)" : "", (util_now_ms() - start) * 1e-3, o->out_dir,
               output_files[OUTPUT_CHECK_PAGE]);
        status = failures ? EXIT_CHECK_FAILED : EXIT_OK;
    }
    if (status == EXIT_CHECK_FAILED && engine_faulted())  /* an engine that could not render: said, 2 */
        status = EXIT_USAGE;
    programs_free(&programs);
    gl_context_destroy();
out:
    /* after a usage error: nothing to say of it; after an engine's fault, what was kept */
    results_set_free(&record, status != EXIT_USAGE || engine_faulted());
    cJSON_Delete(provenance);
    regression_free(&r);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
