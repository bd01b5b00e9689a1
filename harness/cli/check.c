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

/* What check says of a cell (its lines on stdout, its failures), kept for
 * its shard's record (docs/scale-out.md). */
struct cell_said {
    char *text;    /* its lines (owned) */
    int failures;
    bool done;     /* checked by this process */
};

static void print_status(FILE *f, const char *status, const struct regression_cell *c, const char *extra)
{
    fprintf(f, "  %-11s %-22s %s%s\n", status, c->scene->name, c->label, extra);
}

/* c compared with its baseline: its line and, unless it passed, what moved. */
static void compare(FILE *f, struct regression_cell *c, const struct options *o)
{
    const struct baseline_comparison *k = &c->cmp;
    baseline_compare(&c->base, &c->now, c->v, &c->cmp);
    c->compared = true;
    print_status(f, baseline_status_names[k->status], c, "");
    if (k->status != BASELINE_PASS || k->picture_moved) {
        for (int g = 0; g < BASELINE_GUARDS; g++) {
            const int m = baseline_guards[g].metric;
            const double base = baseline_metric(&c->base, m), now = metrics_value(&c->now, m);
            if (k->direction[g])
                fprintf(f, "      %-16s %10.5f -> %10.5f  (%+.5f, tolerance %.5f: %s)\n", metric_info[m].key, base,
                        now, now - base, baseline_tolerance(&c->base, m), k->direction[g] > 0 ? "worse" : "better");
        }
        fprintf(f, "      picture: %.2f %% of pixels moved by more than %g (allowed %.2f %%)%s\n",
                100.0 * k->moved_fraction, c->base.pixel_threshold, 100.0 * c->base.max_moved,
                k->picture_moved && !k->worse && !k->better ? ", with no metric better" : "");
    }
    if (k->status == BASELINE_IMPROVED)
        fprintf(f, "      record it: shadowbench check --update --scene %s --technique %s --baselines %s\n",
                c->scene->name, c->t->name, o->baselines_dir);
    /* The baseline's parameters against what its name means today. */
    if (!regression_params_current(c)) {
        fprintf(f, "      its recorded parameters are no longer what '%s' means (a default changed?): record it "
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

/* Renders, compares (or, into the baselines folder `record`, records) cell
 * c, its lines into f and, if it moved, its heatmap into --out. Returns its
 * failures (a regression, a missing
 * baseline, idle parameters, an improvement with --strict), or -1 on a
 * runtime error. */
static int check_cell(FILE *f, struct regression_cell *c, const struct options *o, const cJSON *provenance,
                      const char *record, struct program_cache *programs, struct scene_setup *ss,
                      struct baseline_setup *open, struct gt_image *extra)
{
    const struct scene *s = c->scene;
    int failures = 0;
    if (!c->base.doc && !o->update) {
        c->cmp.status = BASELINE_MISSING;
        char *how = util_printf("   (record it: shadowbench check --update --scene %s --technique %s "
                                "--baselines %s)", s->name, c->t->name, o->baselines_dir);
        print_status(f, baseline_status_names[BASELINE_MISSING], c, how);
        free(how);
        return 1;
    }
    bool comparable = c->base.doc != NULL;
    if (o->update) {  /* recorded anew: today's settings for its name */
        comparable = comparable && baseline_setup_equal(&c->setup, &baseline_setup_default) &&
                     regression_params_current(c);
        memcpy(c->settings, c->label_settings, c->t->settings_size);
        c->setup = baseline_setup_default;
    }
    if (setup_for(ss, open, extra, c, o, programs) != 0 || regression_render(ss, c) != 0)
        return -1;
    if (o->update) {
        baseline_spread(c->v, ss->distance, metrics_depth_tolerance(c->t->depth_tolerance), &c->now, extra,
                        BASELINE_SEEDS - 1, c->spread);
        if (comparable)
            compare(f, c, o);
        else
            print_status(f, "new", c, c->base.doc ? "   (its settings changed: not compared)" : "");
        const struct baseline_record rec = {s->name, c->label, c->t, c->settings, c->setup, &c->now, c->v,
                                            c->spread, provenance};
        char *json = regression_file(record, c, "json"), *png = regression_file(record, c, "png");
        if (baseline_write(json, png, &rec) != 0)
            failures = -1;
        free(json), free(png);
    } else {
        compare(f, c, o);
        failures += c->cmp.status == BASELINE_REGRESSED || (c->cmp.status == BASELINE_IMPROVED && o->strict);
    }
    if (failures >= 0 && c->declared) {
        struct regression_param idle[64];
        const int n = regression_idle_params(ss, c, idle, 64);
        for (int k = 0; k < n; k++)
            fprintf(f, "  IDLE        %-22s %s: setting %s.%s back to %s changes no pixel (is it used?)\n", s->name,
                    c->label, idle[k].t->name, idle[k].p->name, idle[k].def);
        failures += n;
    }
    return failures >= 0 && check_page_heatmap(c, o->out_dir) < 0 ? -1 : failures;
}

/* Checks this shard's cells of one scene (owner[i]: cell i's shard), each
 * said on stdout when done and kept in said[i]. Returns -1 on a runtime
 * error, else the number of failures. */
static int check_scene(struct regression *r, const struct scene *s, const struct options *o, const cJSON *provenance,
                       const char *record, struct program_cache *programs, const int *owner, struct cell_said *said)
{
    int failures = 0;
    struct scene_setup ss = {0};
    struct baseline_setup open = {0};
    struct gt_image extra[BASELINE_SEEDS - 1] = {0};
    for (int i = 0; i < r->count && failures >= 0; i++) {
        struct regression_cell *c = &r->cells[i];
        if (c->scene != s || !shard_owns(&o->shard, owner[i]))
            continue;
        char *text = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&text, &len);
        if (!f)
            util_out_of_memory(BUFSIZ);
        const int k = check_cell(f, c, o, provenance, record, programs, &ss, &open, extra);
        fclose(f);
        fputs(text, stdout);
        fflush(stdout);  /* progress, in order with stderr's */
        said[i] = (struct cell_said){text, k, true};
        failures = k < 0 ? -1 : failures + k;
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

/* The checks of the whole selection, with every scene checked (not --scene):
 * every parameter set by a declared cell, and no baselines of a scene that
 * is not shipped. Said; returns the failures. */
static int whole_checks(const struct options *o, const struct regression *r, const struct scene *scenes,
                        int scene_count)
{
    if (o->scene_count != 0)
        return 0;
    struct regression_param missing[256];
    const int n = regression_uncovered(r, o->techniques, o->technique_count, missing, 256);
    for (int k = 0; k < n; k++)
        printf("  UNCOVERED   %s.%s: no cell sets it away from its default (add one to the .regression cells "
               "of techniques/%s.c)\n", missing[k].t->name, missing[k].p->name, missing[k].t->name);
    const int orphaned = orphans(o, scenes, scene_count);
    return n + (o->strict ? orphaned : 0);
}

/* The last line: how many cells of each status (n[status]). */
static void summary(const struct options *o, const int *n, double seconds)
{
    printf("check: %d passed, %d REGRESSED, %d improved, %d without a baseline%s; %.1f s; page of moved cells: "
           "%s/%s\n", n[BASELINE_PASS], n[BASELINE_REGRESSED], n[BASELINE_IMPROVED], n[BASELINE_MISSING],
           o->update ? " (recorded anew)" : "", seconds, o->out_dir, output_files[OUTPUT_CHECK_PAGE]);
}

/* The owner (1..shards) of each cell, in the order check checks them
 * (scene by scene, each scene's cells in r's order): contiguous runs of
 * about equal expected cost (cli_cell_cost). */
static void check_owners(const struct regression *r, const struct scene *scenes, int scene_count, int shards,
                         int *owner)
{
    int *order = xmalloc(sizeof *order * (size_t)(r->count + 1)), n = 0, *in_order = NULL;
    double *cost = xmalloc(sizeof *cost * (size_t)(r->count + 1));
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < r->count; i++)
            if (r->cells[i].scene == &scenes[s]) {
                cost[n] = cli_cell_cost(r->cells[i].t);
                order[n++] = i;
            }
    in_order = xmalloc(sizeof *in_order * (size_t)(n + 1));
    shard_split_contiguous(cost, n, shards, in_order);
    for (int k = 0; k < n; k++)
        owner[order[k]] = in_order[k];
    free(order), free(cost), free(in_order);
}

static void said_free(struct cell_said *said, int n)
{
    for (int i = 0; i < n && said; i++)
        free(said[i].text);
    free(said);
}

/* The check's cells in its order, as one number (cli_merge_plan). */
static uint64_t check_plan(const struct regression *r, const struct scene *scenes, int scene_count)
{
    uint64_t h = UTIL_HASH_INIT;
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < r->count; i++)
            if (r->cells[i].scene == &scenes[s])
                h = cli_plan_add(cli_plan_add(h, scenes[s].name), r->cells[i].label);
    return h;
}

/* A moved cell's section of the page as its shard records it. */
static cJSON *section_json(const struct check_section *s)
{
    cJSON *j = cJSON_CreateObject(), *guards = cJSON_AddArrayToObject(j, "guards");
    util_json_add_number(j, "moved_fraction", s->moved_fraction);
    util_json_add_number(j, "pixel_threshold", s->pixel_threshold);
    util_json_add_number(j, "max_moved", s->max_moved);
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        cJSON *e = cJSON_CreateObject();
        util_json_add_number(e, "baseline", s->base[g]);
        util_json_add_number(e, "now", s->now[g]);
        util_json_add_number(e, "tolerance", s->tolerance[g]);
        cJSON_AddItemToArray(guards, e);
    }
    return j;
}

/* The section of cell c from its shard's record j (section_json's):
 * 0, or -1 when j is not one. */
static int section_read(const cJSON *j, const struct regression_cell *c, int status, struct check_section *s)
{
    const cJSON *guards = cJSON_GetObjectItem(j, "guards");
    *s = (struct check_section){.status = status, .scene = c->scene->name, .label = c->label,
                                .moved_fraction = util_json_number(j, "moved_fraction"),
                                .pixel_threshold = util_json_number(j, "pixel_threshold"),
                                .max_moved = util_json_number(j, "max_moved")};
    for (int g = 0; g < BASELINE_GUARDS; g++) {
        const cJSON *e = cJSON_GetArrayItem(guards, g);
        s->base[g] = util_json_number(e, "baseline"), s->now[g] = util_json_number(e, "now");
        s->tolerance[g] = util_json_number(e, "tolerance");
    }
    return cJSON_GetArraySize(guards) == BASELINE_GUARDS ? 0 : -1;
}

/* A shard's record of cell c ("cells" of its shard.json), or NULL. */
static const cJSON *shard_cell(const cJSON *record, const struct regression_cell *c)
{
    const cJSON *e;
    cJSON_ArrayForEach(e, cJSON_GetObjectItem(record, "cells"))
        if (!strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(e, "scene")) ?: "", c->scene->name) &&
            !strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(e, "cell")) ?: "", c->label))
            return e;
    return NULL;
}

int check_main(const struct options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE, *owner = NULL;
    struct regression r = {.baselines_dir = o->baselines_dir, .tuned_dir = o->tuned_dir};
    struct program_cache programs = {0};
    struct results_set record = {0};
    struct cell_said *said = NULL;
    cJSON *provenance = NULL;
    if ((o->update && cli_require_committed(o, "check --update") != 0) ||
        cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0 || check_folders(o, &record) != 0 ||
        regression_collect(&r, scenes, scene_count, o->techniques, o->technique_count) != 0 ||
        read_baselines(&r, o) != 0)
        goto out;
    cli_shard_begin(o);
    owner = xcalloc((size_t)r.count + 1, sizeof *owner);
    said = xcalloc((size_t)r.count + 1, sizeof *said);
    check_owners(&r, scenes, scene_count, o->shard.count ? o->shard.count : 1, owner);
    if (cli_gl_open(o, o->gl) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    provenance = provenance_json(o->argc, o->argv, false, o->timing);
    int mine = 0;
    for (int i = 0; i < r.count; i++)
        mine += shard_owns(&o->shard, owner[i]);
    if (o->shard.count)
        printf("check: shard %d of %d: %d of %d cells on %d scene(s) against %s\n", o->shard.index, o->shard.count,
               mine, r.count, scene_count, o->baselines_dir);
    else
        printf("check: %d cells on %d scene(s) against %s%s\n", r.count, scene_count, o->baselines_dir,
               o->update ? " (recording them anew)" : "");
    int failures = 0;
    for (int s = 0; s < scene_count && failures >= 0; s++) {
        const int f = check_scene(&r, &scenes[s], o, provenance, record.next, &programs, owner, said);
        failures = f < 0 ? -1 : failures + f;
    }
    if (failures >= 0 && !o->shard.count)  /* a shard's are the merge's */
        failures += whole_checks(o, &r, scenes, scene_count);
    if (failures >= 0 && o->update) {  /* the new baselines as one set, held from signals (run.c) */
        util_signals_defer();
        failures = results_set_commit(&record) != 0 ? -1 : failures;
        util_signals_finished(failures == 0 ? EXIT_OK : EXIT_CHECK_FAILED);
    }
    struct strbuf page = {0};  /* each moved cell's section, in the cells' order */
    struct check_section sec;
    for (int i = 0; i < r.count; i++)
        if (said[i].done && check_section_of(&r.cells[i], &sec))
            check_page_section(&page, &sec);
    if (failures >= 0 && check_page_write_sections(page.data, o->out_dir) != 0)
        failures = -1;
    strbuf_free(&page);
    if (failures >= 0) {
        int n[4] = {0};
        for (int i = 0; i < r.count; i++)
            n[r.cells[i].cmp.status] += said[i].done;
        summary(o, n, (util_now_ms() - start) * 1e-3);
        status = failures ? EXIT_CHECK_FAILED : EXIT_OK;
    }
    if (failures >= 0 && o->shard.count) {  /* each cell as said, for the merge */
        cJSON *more = cli_shard_more((util_now_ms() - start) * 1e-3, check_plan(&r, scenes, scene_count)),
              *cells = cJSON_AddArrayToObject(more, "cells");
        for (int i = 0; i < r.count; i++) {
            if (!said[i].done)
                continue;
            cJSON *c = cJSON_CreateObject();
            cJSON_AddStringToObject(c, "scene", r.cells[i].scene->name);
            cJSON_AddStringToObject(c, "cell", r.cells[i].label);
            cJSON_AddNumberToObject(c, "status", r.cells[i].cmp.status);
            cJSON_AddNumberToObject(c, "failures", said[i].failures);
            cJSON_AddStringToObject(c, "said", said[i].text);
            if (check_section_of(&r.cells[i], &sec))  /* its section's numbers */
                cJSON_AddItemToObject(c, "moved", section_json(&sec));
            cJSON_AddItemToArray(cells, c);
        }
        if (cli_shard_end(o, scenes, scene_count, more) != 0)
            status = EXIT_CHECK_FAILED;
    }
    if (status == EXIT_CHECK_FAILED && engine_faulted())  /* an engine that could not render: said, 2 */
        status = EXIT_USAGE;
    programs_free(&programs);
    gl_context_destroy();
out:
    /* after a usage error: nothing to say of it; after an engine's fault, what was kept */
    results_set_free(&record, status != EXIT_USAGE || engine_faulted());
    cJSON_Delete(provenance);
    said_free(said, r.count);
    free(owner);
    regression_free(&r);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}

int check_merge(const struct options *o, const struct merge_input *in)
{
    static struct scene scenes[CLI_MAX_SCENES];
    int scene_count = 0, status = EXIT_USAGE, *owner = NULL, failures = 0, n[4] = {0};
    struct regression r = {.baselines_dir = o->baselines_dir, .tuned_dir = o->tuned_dir};
    struct results_set none = {0};
    struct strbuf page = {0};
    struct merged {
        const char *said;
        long status, failures;
        bool moved;
        struct check_section sec;
    } *m = NULL;
    if (o->update) {  /* no shard records: --shard refuses it */
        log_error("merge: the shards record check --update, which is not sharded");
        goto out;
    }
    if (cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0 ||
        regression_collect(&r, scenes, scene_count, o->techniques, o->technique_count) != 0 ||
        cli_merge_plan(in, check_plan(&r, scenes, scene_count)) != 0)
        goto out;
    owner = xcalloc((size_t)r.count + 1, sizeof *owner);
    m = xcalloc((size_t)r.count + 1, sizeof *m);
    check_owners(&r, scenes, scene_count, in->count, owner);
    for (int i = 0; i < r.count; i++) {  /* every cell's record first: a shard that lacks one says nothing */
        const struct regression_cell *c = &r.cells[i];
        const cJSON *e = shard_cell(in->records[owner[i]], c), *moved = cJSON_GetObjectItem(e, "moved");
        m[i].said = cJSON_GetStringValue(cJSON_GetObjectItem(e, "said"));
        m[i].moved = moved != NULL;
        /* a cell that regressed or has no baseline is a failure; one that
         * passed may still fail (a parameter that changes nothing) */
        if (!m[i].said || !util_json_whole(e, "status", 0, BASELINE_MISSING, &m[i].status) ||
            !util_json_whole(e, "failures", 0, 1e6, &m[i].failures) ||
            ((m[i].status == BASELINE_REGRESSED || m[i].status == BASELINE_MISSING ||
              (m[i].status == BASELINE_IMPROVED && o->strict)) && !m[i].failures) ||
            (moved && section_read(moved, c, (int)m[i].status, &m[i].sec))) {
            log_error("merge: %s: its shard.json holds no record of cell %s/%s, which it owns", in->dirs[owner[i]],
                      c->scene->name, c->label);
            goto out;
        }
    }
    if (check_folders(o, &none) != 0)
        goto out;
    cli_shard_begin(o);  /* a shard's record left in OUT would make it pass for one */
    status = EXIT_CHECK_FAILED;  /* the shards are read: what fails now is a write */
    printf("check: %d cells on %d scene(s) against %s\n", r.count, scene_count, o->baselines_dir);
    for (int s = 0; s < scene_count; s++)
        for (int i = 0; i < r.count; i++) {
            const struct regression_cell *c = &r.cells[i];
            if (c->scene != &scenes[s])
                continue;
            fputs(m[i].said, stdout);
            n[m[i].status]++;
            failures += (int)m[i].failures;
        }
    for (int i = 0; i < r.count; i++) {  /* each moved cell's section and heatmap, in the page's order */
        const struct regression_cell *c = &r.cells[i];
        if (!m[i].moved)
            continue;
        char *from = util_printf("%s/%s/%s.png", in->dirs[owner[i]], c->scene->name, c->label),
             *to = util_printf("%s/%s/%s.png", o->out_dir, c->scene->name, c->label);
        const int rc = cli_copy_file(from, to);
        free(from), free(to);
        if (rc)
            goto out;
        check_page_section(&page, &m[i].sec);
    }
    failures += whole_checks(o, &r, scenes, scene_count);
    if (check_page_write_sections(page.data, o->out_dir) != 0)
        goto out;
    summary(o, n, cli_merge_seconds(in));
    status = failures ? EXIT_CHECK_FAILED : EXIT_OK;
out:
    strbuf_free(&page);
    free(owner), free(m);
    regression_free(&r);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
