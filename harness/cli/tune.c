/* shadowbench tune: every selected technique tuned on the scenes
 * (pipeline/tuner.h), each record written to <out>/<technique>.json as it
 * is done and, with --write-tuned, into the tuned folder that run reads
 * (score/tuned.h) as one set once every technique is (output/results_set.h). */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "output/out_dir.h"
#include "output/provenance.h"
#include "output/report.h"
#include "output/results_set.h"
#include "pipeline/tuner.h"
#include "score/tuned.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* --write-tuned writes into a folder of tuned settings: one holding
 * anything else (someone's own files) is refused. */
static int tuned_dir_ours(const char *dir)
{
    DIR *d = opendir(dir);
    const char *stranger = NULL;
    for (struct dirent *e; d && !stranger && (e = readdir(d));) {
        const char *n = e->d_name, *dot = strrchr(n, '.');
        bool ours = results_set_own_name(n);
        for (int i = 0; technique_list[i] && !ours && dot && !strcmp(dot, ".json"); i++)
            ours = strlen(technique_list[i]->name) == (size_t)(dot - n) &&
                   !strncmp(n, technique_list[i]->name, (size_t)(dot - n));
        if (!ours)
            stranger = n;
    }
    if (stranger)
        log_error("--tuned %s: holds %s, which tune does not write: name a folder of tuned settings", dir,
                  stranger);
    if (d)
        closedir(d);
    return stranger ? -1 : 0;
}

static int write_file(const char *dir, const char *name, const cJSON *j)
{
    char *path = util_printf("%s/%s.json", dir, name);
    int rc = report_write_json(path, j);
    free(path);
    return rc;
}

/* <out>/tune.json: which techniques (techniques[0..count-1]), and whether
 * every one is done; with `more`'s keys (taken; may be NULL). */
static int tune_state(const struct options *o, const struct technique *const *techniques, int count, bool complete,
                      double seconds, cJSON *more)
{
    cJSON *j = cJSON_CreateObject();
    cJSON_AddBoolToObject(j, "complete", complete);
    cJSON_AddNumberToObject(j, "seconds", seconds);
    cJSON *t = cJSON_AddArrayToObject(j, "techniques");
    for (int i = 0; i < count; i++)
        cJSON_AddItemToArray(t, cJSON_CreateString(techniques[i]->name));
    util_json_merge(j, more);
    cJSON_Delete(more);
    char *path = out_dir_path(o->out_dir, OUTPUT_TUNE_JSON);
    int rc = report_write_json(path, j);
    free(path);
    cJSON_Delete(j);
    return rc;
}

void tune_owners(const struct options *o, int shards, int *owner)
{
    double cost[CLI_MAX_TECHNIQUES];
    for (int i = 0; i < o->technique_count; i++)
        cost[i] = tune_space_size(o->techniques[i], o->held[technique_index(o->techniques[i])]) *
                  cli_cell_cost(o->techniques[i]);
    shard_split_balanced(cost, o->technique_count, shards, owner);
}

/* Tunes techniques[0..count-1] in turn, each record written into out and
 * into tuned (NULL: none); returns the exit status. */
static int tune_all(const struct options *o, const struct technique *const *techniques, int count, const char *tuned,
                    const struct scene *scenes, struct scene_setup *setups, int scene_count,
                    struct program_cache *programs)
{
    const struct tune_options to = {o->width, o->height, o->gt_samples, o->shadow_map_size, o->frames, o->warmup,
                                    o->timing, o->objective, o->cost_fetches};
    struct tune_progress progress = {.start_ms = util_now_ms(), .per_size = TUNE_PER_SIZE_GUESS};
    static struct tuner tuners[CLI_MAX_TECHNIQUES];
    for (int i = 0; i < count; i++) {
        const struct technique *t = techniques[i];
        if (tuner_init(&tuners[i], t, cli_settings(o, t), o->held[technique_index(t)], &to, scenes, setups,
                       scene_count, &progress) != 0) {
            for (int k = 0; k <= i; k++)
                tuner_free(&tuners[k]);
            return EXIT_USAGE;
        }
        progress.size_left += tuner_size(&tuners[i]);
    }
    int status = EXIT_OK;
    for (int i = 0; i < count; i++) {
        cJSON *record = NULL;
        const enum tuner_result rc = status == EXIT_OK ? tuner_run(&tuners[i], &record) : TUNER_FAILED;
        if (record) {
            cJSON *provenance = provenance_json(o->argc, o->argv, true, o->timing);
            util_json_merge(record, provenance);
            cJSON_Delete(provenance);
            if (write_file(o->out_dir, techniques[i]->name, record) != 0 ||
                (tuned && write_file(tuned, techniques[i]->name, record) != 0))
                status = EXIT_CHECK_FAILED;
            cJSON_Delete(record);
        }
        if (status == EXIT_OK && rc != TUNER_DONE)
            status = rc == TUNER_UNDEFINED ? EXIT_USAGE : EXIT_CHECK_FAILED;
        programs_free(programs);  /* a technique's settings are its own */
        tuner_free(&tuners[i]);
    }
    return status != EXIT_OK && engine_faulted() ? EXIT_USAGE : status;  /* an engine's fault: said, 2 */
}

/* With --write-tuned, the tuned folder is checked first (one it cannot
 * write is refused before --out is made) and neither folder is inside the
 * other (the swapped set would take --out with it, or --out would hold a
 * folder it did not make). Returns 0 or -1 (logged). */
static int folders_apart(const struct options *o)
{
    if (!o->write_tuned || (!util_path_within(o->out_dir, o->tuned_dir) && !util_path_within(o->tuned_dir, o->out_dir)))
        return 0;
    log_error("--out %s and --tuned %s: one inside the other; name two folders apart", o->out_dir, o->tuned_dir);
    return -1;
}

/* The tuning's techniques in its order, as one number (cli_merge_plan). */
static uint64_t tune_plan(const struct options *o)
{
    uint64_t h = UTIL_HASH_INIT;
    for (int i = 0; i < o->technique_count; i++)
        h = cli_plan_add(h, o->techniques[i]->name);
    return h;
}

int tune_main(const struct options *o)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    static struct scene_setup setups[CLI_MAX_SCENES];
    struct program_cache programs = {0};
    struct results_set tuned = {0};
    int scene_count = 0, status = EXIT_USAGE, opened = 0;
    if ((o->write_tuned && cli_require_committed(o, "tune --write-tuned") != 0) ||
        cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0)
        goto out;
    if (scene_count < 2 || scene_count > TUNE_MAX_SCENES) {
        log_error("tune: needs 2 to %d scenes (each scene's setting is chosen on the others), got %d",
                  TUNE_MAX_SCENES, scene_count);
        goto out;
    }
    if (folders_apart(o) != 0)
        goto out;
    /* a shard writes none: the merge writes them all as one set */
    const bool write_tuned = o->write_tuned && !o->shard.count;
    if ((write_tuned && (tuned_dir_ours(o->tuned_dir) != 0 || results_set_open(&tuned, o->tuned_dir, 1) != 0)) ||
        out_dir_claim(o->out_dir) != 0)
        goto out;
    cli_shard_begin(o);
    /* this shard's techniques (every one unsharded) */
    const struct technique *mine[CLI_MAX_TECHNIQUES];
    int owner[CLI_MAX_TECHNIQUES], count = 0;
    tune_owners(o, o->shard.count ? o->shard.count : 1, owner);
    for (int i = 0; i < o->technique_count; i++)
        if (shard_owns(&o->shard, owner[i]))
            mine[count++] = o->techniques[i];
    if (tune_state(o, mine, count, false, 0, NULL) != 0) {  /* a write that fails: a runtime error */
        status = EXIT_CHECK_FAILED;
        goto out;
    }
    if (cli_gl_open(o, o->gl) != 0)
        goto out;
    status = EXIT_CHECK_FAILED;
    if (o->shard.count)
        log_info("tune: shard %d of %d: %d of the %d techniques%s", o->shard.index, o->shard.count, count,
                 o->technique_count, o->write_tuned ? " (the merge writes --tuned)" : "");
    log_info("tune: %d technique(s) on %d scenes, %dx%d, %d GT samples, %d^2 shadow map, objective mean %s, "
             "median of %d frames per cell, on %s", count, scene_count, o->width, o->height,
             o->gt_samples, o->shadow_map_size, metric_info[o->objective].key, o->frames, gl_context_renderer());
    for (; opened < scene_count; opened++)
        if (scene_setup_open(&setups[opened], &scenes[opened],
                             &(struct scene_setup_desc){o->width, o->height, o->shadow_map_size, o->gt_samples, 0,
                                                        o->cache_dir, 0, &programs, &o->cascades}) != 0) {
            opened++;  /* scene_setup_open leaves it to be freed */
            goto out_gl;
        }
    status = tune_all(o, mine, count, tuned.next, scenes, setups, scene_count, &programs);
    if (status == EXIT_OK) {
        util_signals_defer();  /* the tuned set, then tune.json "complete": as one step (run.c) */
        const double seconds = (util_now_ms() - start) * 1e-3;
        if ((write_tuned && results_set_commit(&tuned) != 0) || tune_state(o, mine, count, true, seconds, NULL) != 0 ||
            cli_shard_end(o, scenes, scene_count, cli_shard_more(seconds, tune_plan(o))) != 0)
            status = EXIT_CHECK_FAILED;
        util_signals_finished(status);
        if (status == EXIT_OK) {
            printf("tuned: %s/<technique>.json%s%s\n", o->out_dir, write_tuned ? " and " : "",
                   write_tuned ? o->tuned_dir : "");
            log_info("tune finished in %.0f s", seconds);
        }
    }
out_gl:
    for (int s = 0; s < opened; s++)
        scene_setup_free(&setups[s]);
    programs_free(&programs);
    gl_context_destroy();
out:
    results_set_free(&tuned, status != EXIT_USAGE);  /* after a usage error: nothing to say of it */
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}

int tune_merge(const struct options *o, const struct merge_input *in)
{
    const double start = util_now_ms();
    static struct scene scenes[CLI_MAX_SCENES];
    struct results_set tuned = {0};
    int scene_count = 0, status = EXIT_USAGE, owner[CLI_MAX_TECHNIQUES];
    cJSON *records[CLI_MAX_TECHNIQUES] = {0};
    if ((o->write_tuned && cli_require_committed(o, "merge of tune --write-tuned") != 0) ||
        cli_load_scenes(o, NULL, 0, scenes, CLI_MAX_SCENES, &scene_count) != 0 || folders_apart(o) != 0 ||
        cli_merge_plan(in, tune_plan(o)) != 0)
        goto out;
    tune_owners(o, in->count, owner);
    for (int i = 0; i < o->technique_count; i++) {  /* each record as its shard wrote it, read as run reads it */
        struct tuned tu;
        const enum tuned_load_result rc = tuned_load(in->dirs[owner[i]], o->techniques[i], &tu);
        if (rc == TUNED_NONE)
            log_error("merge: %s/%s.json: missing (the shard that owns %s's tuning)", in->dirs[owner[i]],
                      o->techniques[i]->name, o->techniques[i]->name);
        if (rc != TUNED_LOADED)
            goto out;
        records[i] = cJSON_Duplicate(tu.doc, true);
        tuned_free(&tu);
    }
    if ((o->write_tuned && (tuned_dir_ours(o->tuned_dir) != 0 || results_set_open(&tuned, o->tuned_dir, 1) != 0)) ||
        out_dir_claim(o->out_dir) != 0)
        goto out;
    cli_shard_begin(o);  /* a shard's record left in OUT would make it pass for one */
    status = EXIT_CHECK_FAILED;  /* the shards are read: what fails now is a write */
    if (tune_state(o, o->techniques, o->technique_count, false, 0, NULL) != 0)
        goto out;
    for (int i = 0; i < o->technique_count; i++)
        if (write_file(o->out_dir, o->techniques[i]->name, records[i]) != 0 ||
            (tuned.next && write_file(tuned.next, o->techniques[i]->name, records[i]) != 0))
            goto out;
    util_signals_defer();
    cJSON *more = cJSON_CreateObject();
    cli_merge_record(more, in);
    if ((!o->write_tuned || results_set_commit(&tuned) == 0) &&
        tune_state(o, o->techniques, o->technique_count, true, cli_merge_seconds(in), more) == 0)
        status = EXIT_OK;
    util_signals_finished(status);
    if (status == EXIT_OK) {
        printf("tuned: %s/<technique>.json%s%s\n", o->out_dir, o->write_tuned ? " and " : "",
               o->write_tuned ? o->tuned_dir : "");
        log_info("merge finished in %.1f s", (util_now_ms() - start) * 1e-3);
    }
out:
    for (int i = 0; i < o->technique_count; i++)
        cJSON_Delete(records[i]);
    results_set_free(&tuned, status != EXIT_USAGE);
    for (int s = 0; s < scene_count; s++)
        scene_free(&scenes[s]);
    return status;
}
