/* Protects `shadowbench tune` (docs/tuning.md): the search is deterministic;
 * leave-one-scene-out never looks at the held-out scene; every technique's
 * tune values are in range and hold its default; the frontier it writes is
 * a Pareto front; run's tuned cells use each scene's fold setting, and a
 * scene the tuning did not see its light kind's (settings_by_light), else
 * the all-scene one; --set holds a parameter (out of the space, at its
 * value in every setting the file records) while the others are searched;
 * a stale or out-of-range tuned file is one line naming it, exit 2. */
#include "check.h"
#include "read_json.h"
#include "run_cmd.h"
#include "base/util.h"
#include "score/tune_search.h"
#include "techniques/params.h"
#include "techniques/technique.h"

#include <cjson/cJSON.h>
#include <string.h>

static const char *sb;
static char dir[] = "/tmp/sb_test_tune_XXXXXX";

/* A synthetic objective over 3 parameters of 5 values: scene k is a bowl
 * centred at target[k] (with a coupling term, so one round is not always
 * enough), plus a cost per evaluation log. */
struct synthetic {
    int target[8][3];
    int scenes;
    int calls[8];
    char order[4096];  /* "k:a,b,c;" per call */
    int scene_poisoned;  /* -1, or a scene whose objective is replaced by garbage */
};

static int synthetic_eval(void *user, const int *p, int k, struct tune_sample *s)
{
    struct synthetic *y = user;
    double e = 0;
    for (int d = 0; d < 3; d++)
        e += (p[d] - y->target[k][d]) * (p[d] - y->target[k][d]);
    e += 0.5 * (p[0] - p[1]) * (p[0] - p[1]) * (k % 2);
    if (k == y->scene_poisoned)
        e = 1000 - 37 * p[0] + 11 * p[2] * p[1];  /* another optimum altogether */
    *s = (struct tune_sample){e, 1.0 + p[0], 0.9 + p[0], 1.1 + p[0], NAN, false};
    y->calls[k]++;
    size_t n = strlen(y->order);
    snprintf(y->order + n, sizeof y->order - n, "%d:%d,%d,%d;", k, p[0], p[1], p[2]);
    return 0;
}

static struct tune_memo synthetic_memo(struct synthetic *y)
{
    struct tune_memo m = {.dims = 3, .counts = {5, 5, 5}, .scenes = y->scenes, .eval = synthetic_eval, .user = y};
    return m;
}

static void search(void)
{
    struct synthetic y = {.target = {{4, 1, 2}, {3, 3, 0}, {4, 2, 2}, {0, 1, 4}}, .scenes = 4,
                          .scene_poisoned = -1};
    const int start[3] = {2, 2, 2};
    int fold[TUNE_MAX_SCENES][TUNE_MAX_DIMS] = {{0}}, again[TUNE_MAX_SCENES][TUNE_MAX_DIMS] = {{0}};
    double held[TUNE_MAX_SCENES], held_again[TUNE_MAX_SCENES];

    /* One scene: coordinate descent reaches the bowl's centre. */
    struct tune_memo m = synthetic_memo(&y);
    int best[TUNE_MAX_DIMS];
    double score;
    const int one = 0;
    CHECK(tune_descend(&m, &one, 1, start, best, &score) == 0 && score == 0 && best[0] == 4 && best[1] == 1 &&
              best[2] == 2, "scene 0 alone: best %d,%d,%d score %g", best[0], best[1], best[2], score);
    tune_memo_free(&m);

    /* Deterministic: the same calls in the same order, the same choices. */
    m = synthetic_memo(&y);
    y.order[0] = '\0';
    CHECK(tune_cross_validate(&m, start, NULL, fold, held) == 0, "cross-validation");
    char *first = xstrdup(y.order);
    tune_memo_free(&m);
    m = synthetic_memo(&y);
    y.order[0] = '\0';
    tune_cross_validate(&m, start, NULL, again, held_again);
    CHECK(strcmp(first, y.order) == 0 && memcmp(fold, again, sizeof fold) == 0 &&
              memcmp(held, held_again, sizeof(double) * 4) == 0, "two searches differ");
    free(first);
    tune_memo_free(&m);

    /* No leak: poisoning scene k (another optimum altogether) changes
     * nothing that fold k chose, though it does move the choice made on
     * every scene (so the poison is strong enough to show a leak). */
    const int all_scenes[4] = {0, 1, 2, 3};
    int clean_all[TUNE_MAX_DIMS], poisoned_all[TUNE_MAX_DIMS];
    m = synthetic_memo(&y);
    tune_descend(&m, all_scenes, 4, start, clean_all, &score);
    tune_memo_free(&m);
    for (int k = 0; k < y.scenes; k++) {
        y.scene_poisoned = k;
        m = synthetic_memo(&y);
        tune_cross_validate(&m, start, NULL, again, held_again);
        CHECK(memcmp(fold[k], again[k], sizeof fold[k]) == 0, "fold %d moved when its held-out scene changed", k);
        tune_descend(&m, all_scenes, 4, start, poisoned_all, &score);
        CHECK(memcmp(clean_all, poisoned_all, sizeof(int) * 3) != 0,
              "poisoning scene %d did not move the all-scene choice: the test could not see a leak", k);
        tune_memo_free(&m);
    }
    y.scene_poisoned = -1;

    /* The memo: a cell is evaluated once, however many searches ask. */
    m = synthetic_memo(&y);
    tune_cross_validate(&m, start, NULL, fold, held);
    const long cells = m.evaluations;
    tune_cross_validate(&m, start, NULL, again, held_again);
    CHECK(m.evaluations == cells, "a second cross-validation evaluated %ld more cells", m.evaluations - cells);
    tune_memo_free(&m);

    /* Folds by group (the light's kind): each scene's fold is chosen on the
     * other scenes of its group alone; a scene alone in its group, on every
     * other scene. */
    const int pairs[4] = {0, 0, 1, 1}, lone[4] = {0, 0, 0, 1};
    const int group_of[4][3] = {{1}, {0}, {3}, {2}}, others_of_3[3] = {0, 1, 2};
    m = synthetic_memo(&y);
    CHECK(tune_cross_validate(&m, start, pairs, fold, held) == 0, "cross-validation by group");
    for (int k = 0; k < 4; k++) {
        tune_descend(&m, group_of[k], 1, start, best, &score);
        CHECK(memcmp(fold[k], best, sizeof(int) * 3) == 0, "fold %d was not chosen on its group's other scene", k);
    }
    tune_cross_validate(&m, start, lone, again, held_again);
    tune_descend(&m, others_of_3, 3, start, best, &score);
    CHECK(memcmp(again[3], best, sizeof(int) * 3) == 0, "a scene alone in its group: its fold, on every other scene");
    tune_memo_free(&m);
}

/* Every tuned parameter's values are in its range, distinct, and hold its
 * default (the search starts there). */
static void tables(void)
{
    for (const struct technique *const *t = technique_list; *t; t++)
        for (const struct technique_param *p = (*t)->params; p->name; p++) {
            double v[64];
            const int n = params_tune_values(p, v, 64);
            bool has_default = n == 0;
            for (int i = 0; i < n; i++) {
                if (p->type == PARAM_FLOAT || p->type == PARAM_INT)
                    CHECK(v[i] >= p->min && v[i] <= p->max, "%s.%s: tune value %g outside [%g, %g]", (*t)->name,
                          p->name, v[i], p->min, p->max);
                for (int j = 0; j < i; j++)
                    CHECK(v[i] != v[j], "%s.%s: %g twice", (*t)->name, p->name, v[i]);
                has_default |= (float)v[i] == (float)p->def;
            }
            CHECK(has_default, "%s.%s: its tune values lack its default", (*t)->name, p->name);
        }
}

static void write_json(const char *path, const cJSON *j)
{
    char *text = cJSON_Print(j);
    util_write_file_atomic(path, text, strlen(text));
    cJSON_free(text);
}

static void expect_fail(const char *cmd, const char *line)
{
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 2 && err.data && strcmp(err.data, line) == 0, "exit %d\n  got:    %s  wanted: %s", status,
          err.data ? err.data : "", line);
    strbuf_free(&err);
}

/* Runs `shadowbench tune ARGS` (ARGS with the scratch folder's %s twice
 * at most), which must succeed. */
static void run_tune(const char *what, const char *args)
{
    char *tail = util_printf(args, dir, dir), *cmd = util_printf("%s tune %s", sb, tail);
    struct strbuf err = {0};
    CHECK(run_cmd(cmd, &err, NULL) == 0, "%s: %s", what, err.data);
    strbuf_free(&err);
    free(cmd), free(tail);
}

/* A small tune of hard on two area-light scenes and two sun scenes, then run
 * with its settings. */
static void command(void)
{
    run_tune("tune", "--technique hard --scene parallel_planes --scene contact_hardening --scene sun_contact "
                     "--scene sun_wide --width 64 --height 64 --gt-samples 16 --frames 1 --no-cache -q --out %s/tune "
                     "--write-tuned --allow-uncommitted --tuned %s/tuned");
    char *cmd;
    char *path = util_printf("%s/tuned/hard.json", dir);
    cJSON *j = read_json(path);
    CHECK(j, "%s: not written", path);
    if (!j)
        return;
    /* The frontier: increasing time, decreasing error (a Pareto front), and
     * no setting tried is both faster and better than a point of it. */
    const cJSON *front = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "frontier"), "all"), *p;
    double last_ms = -1, last_error = INFINITY;
    int n = 0;
    cJSON_ArrayForEach(p, front) {
        const double ms = cJSON_GetObjectItem(p, "ms")->valuedouble, e = cJSON_GetObjectItem(p, "error")->valuedouble;
        CHECK(ms >= last_ms && e < last_error, "frontier point %d: %g ms, %g after %g ms, %g", n, ms, e, last_ms,
              last_error);
        last_ms = ms, last_error = e, n++;
    }
    CHECK(n >= 1, "an empty frontier");
    const cJSON *folds = cJSON_GetObjectItem(j, "folds");
    CHECK(cJSON_GetArraySize(folds) == 4, "a fold per scene");
    /* A scene the tuning saw gets its fold's setting; one it did not see
     * its light kind's, else the all-scene one: each made to differ, then
     * read back by run, with settings_by_light and without it. */
    const cJSON *f0 = cJSON_GetArrayItem(folds, 0);
    CHECK(strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(f0, "scene")), "parallel_planes") == 0,
          "the folds in the order of --scene");
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(f0, "settings"), "slope_bias", cJSON_CreateNumber(3.5));
    cJSON *by_light = cJSON_GetObjectItem(j, "settings_by_light");
    CHECK(cJSON_GetObjectItem(by_light, "area") && cJSON_GetObjectItem(by_light, "sun") &&
              cJSON_GetArraySize(by_light) == 2,
          "settings_by_light holds area and sun");
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(by_light, "area"), "slope_bias", cJSON_CreateNumber(1.5));
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(by_light, "sun"), "slope_bias", cJSON_CreateNumber(2.5));
    cJSON_ReplaceItemInObject(cJSON_GetObjectItem(j, "settings"), "slope_bias", cJSON_CreateNumber(0.5));
    const struct { const char *scene; double with_kinds, without; } cases[] = {
        {"floating_box_sphere", 1.5, 0.5}, {"sun_grazing", 2.5, 0.5}, {"parallel_planes", 3.5, 3.5}};
    for (int pass = 0; pass < 2; pass++) {  /* pass 1: without settings_by_light */
        if (pass)
            cJSON_DeleteItemFromObject(j, "settings_by_light");
        write_json(path, j);
        for (size_t k = 0; k < ARRAY_SIZE(cases); k++) {
            cmd = util_printf("%s run --technique hard --scene %s --settings tuned --width 32 --height 32 "
                              "--gt-samples 4 --frames 1 --no-cache -q --tuned %s/tuned --out %s/cases", sb,
                              cases[k].scene, dir, dir);
            CHECK(run_cmd(cmd, NULL, NULL) == 0, "%s", cmd);
            free(cmd);
            char *metrics = util_printf("%s/cases/%s/hard@tuned/metrics.json", dir, cases[k].scene);
            cJSON *m = read_json(metrics);
            const cJSON *slope = cJSON_GetObjectItem(cJSON_GetObjectItem(m, "params"), "slope_bias");
            const double want = pass ? cases[k].without : cases[k].with_kinds;
            CHECK(cJSON_IsNumber(slope) && slope->valuedouble == want, "hard@tuned on %s%s: slope_bias is not %g",
                  cases[k].scene, pass ? " (no settings_by_light)" : "", want);
            cJSON_Delete(m);
            free(metrics);
        }
    }
    /* A kind of one scene gets no setting of its own (its scenes' fold and
     * an unseen scene of it take every scene's): two area scenes, one sun. */
    cmd = util_printf("%s tune --technique hard --scene parallel_planes --scene contact_hardening --scene "
                      "sun_contact --width 32 --height 32 --gt-samples 4 --frames 1 --no-cache -q --out %s/tune3",
                      sb, dir);
    CHECK(run_cmd(cmd, NULL, NULL) == 0, "%s", cmd);
    free(cmd);
    char *three = util_printf("%s/tune3/hard.json", dir);
    cJSON *t3 = read_json(three);
    const cJSON *kinds3 = cJSON_GetObjectItem(t3, "settings_by_light");
    CHECK(cJSON_GetObjectItem(kinds3, "area") && cJSON_GetArraySize(kinds3) == 1,
          "a tuning of two area scenes and one sun scene: settings_by_light holds area alone");
    cJSON_Delete(t3);
    free(three);

    /* --settings auto, run's default: the tuned cell where a technique has a
     * tuned file (hard), its default cell where it has none (pcf); with a
     * --set, every technique's default cells. */
    const char *const auto_cases[][3] = {{"", "hard@tuned", "pcf"}, {"--set pcf.radius_texels=3", "hard", "pcf"}};
    for (size_t k = 0; k < ARRAY_SIZE(auto_cases); k++) {
        cmd = util_printf("%s run --technique hard,pcf --scene parallel_planes %s --width 32 --height 32 "
                          "--gt-samples 4 --frames 1 --no-cache -q --tuned %s/tuned --out %s/auto%zu", sb,
                          auto_cases[k][0], dir, dir, k);
        CHECK(run_cmd(cmd, NULL, NULL) == 0, "%s", cmd);
        free(cmd);
        char *matrix = util_printf("%s/auto%zu/matrix.json", dir, k);
        cJSON *mj = read_json(matrix), *cells = mj ? cJSON_GetObjectItem(mj, "cells") : NULL;
        CHECK(cJSON_GetArraySize(cells) == 2 &&
                  strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(cJSON_GetArrayItem(cells, 0), "cell")),
                         auto_cases[k][1]) == 0 &&
                  strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(cJSON_GetArrayItem(cells, 1), "cell")),
                         auto_cases[k][2]) == 0,
              "run %s: the cells are not %s and %s", auto_cases[k][0], auto_cases[k][1], auto_cases[k][2]);
        cJSON_Delete(mj);
        free(matrix);
    }

    /* A run larger than the committed benchmark's main job says how long it
     * will take before it starts: on the line through the benchmark's two
     * runs (1 cell in 1 s, 3 in 5 s: 2 cells, 3 s), only at its settings and
     * on its renderer; a broken file says nothing and changes nothing. */
    char *run_json = util_printf("%s/auto0/run.json", dir), *est = util_printf("%s/est/results/bench", dir);
    cJSON *rj = read_json(run_json);
    const char *renderer = cJSON_GetStringValue(cJSON_GetObjectItem(rj, "gl_renderer"));
    CHECK(renderer && util_mkdirs(est) == 0, "a renderer in %s", run_json);
    const char *const benches[] = {"{\"device\": {\"cpu\": \"CPU X\", \"gl_renderer\": \"%s\"}, \"settings\": "
                                   "{\"width\": 32, \"height\": 32, \"gt_samples\": 4, \"shadow_map_size\": 1024, "
                                   "\"frames\": 1, \"warmup_frames\": 0}, \"main_job\": {\"cells\": 1, "
                                   "\"warm_median_seconds\": 1}, \"full_run\": {\"cells\": 3, \"warm_seconds\": 5}}",
                                   "{\"device\": {\"gl_renderer\": \"%s\"}, \"main_job\": {\"cells\": \"1\"}, [",
                                   "{\"device\": {\"gl_renderer\": \"%s\"}, \"settings\": {\"width\": 32}, "
                                   "\"main_job\": {\"cells\": -1e308, \"warm_median_seconds\": 1e308}}"};
    for (size_t k = 0; k < ARRAY_SIZE(benches) && renderer; k++) {
        char *file = util_printf("%s/main_job.json", est), *text = util_printf(benches[k], renderer);
        CHECK(util_write_file_atomic(file, text, strlen(text)) == 0, "writing %s", file);
        cmd = util_printf("cd %s/est && %s run --technique hard,pcf --scene parallel_planes --settings default "
                          "--width 32 --height 32 --gt-samples 4 --frames 1 --no-cache --tuned %s/tuned --out "
                          "%s/est/run", dir, sb, dir, dir);
        struct strbuf err = {0};
        CHECK(run_cmd(cmd, &err, NULL) == 0, "%s: %s", cmd, err.data);
        const bool said = strstr(err.data, "run: 2 cells: about 3 s on CPU X") != NULL;
        CHECK(k == 0 ? said : !strstr(err.data, "about"), "benchmark %zu: %s", k, err.data);
        strbuf_free(&err);
        free(cmd), free(file), free(text);
    }
    cJSON_Delete(rj);
    free(run_json), free(est);

    /* Stale and out-of-range files: one line naming the file, exit 2. */
    const cJSON *settings = cJSON_GetObjectItem(j, "settings");
    cJSON *slope = cJSON_DetachItemFromObject((cJSON *)settings, "slope_bias");
    cJSON_AddItemToObject((cJSON *)settings, "slope_bias_renamed", slope);
    write_json(path, j);
    char *run = util_printf("%s run --technique hard --scene parallel_planes --tuned %s/tuned --out %s/run2", sb,
                            dir, dir);
    char *line = util_printf("shadowbench: error: %s: settings: hard.slope_bias_renamed: unknown parameter (hard "
                             "has: constant_bias, slope_bias)\n", path);
    expect_fail(run, line);
    free(line);
    cJSON_DeleteItemFromObject((cJSON *)settings, "slope_bias_renamed");
    cJSON_AddNumberToObject((cJSON *)settings, "slope_bias", 99);
    write_json(path, j);
    line = util_printf("shadowbench: error: %s: settings: hard.slope_bias: 99 is out of range [0.0, 16.0]\n", path);
    expect_fail(run, line);
    free(line);
    /* settings_by_light is read as strictly: a kind's setting out of range
     * (settings itself in range), then a key that is no light kind */
    cJSON *kinds = cJSON_AddObjectToObject(j, "settings_by_light");
    cJSON_AddItemToObject(kinds, "sun", cJSON_Duplicate(settings, true));  /* slope_bias 99 */
    cJSON_ReplaceItemInObject((cJSON *)settings, "slope_bias", cJSON_CreateNumber(1));
    write_json(path, j);
    line = util_printf("shadowbench: error: %s: settings_by_light.sun: hard.slope_bias: 99 is out of range [0.0, "
                       "16.0]\n", path);
    expect_fail(run, line);
    free(line);
    cJSON_DeleteItemFromObject(kinds, "sun");
    cJSON_AddItemToObject(kinds, "Sun", cJSON_Duplicate(settings, true));
    write_json(path, j);
    line = util_printf("shadowbench: error: %s: \"settings_by_light\" must be an object with keys area and sun "
                       "only\n", path);
    expect_fail(run, line);
    free(line);
    cJSON_DeleteItemFromObject(j, "settings_by_light");
    cJSON_DeleteItemFromObject((cJSON *)settings, "slope_bias");
    write_json(path, j);
    line = util_printf("shadowbench: error: %s: settings: lacks hard.slope_bias (recorded before the parameter "
                       "existed)\n", path);
    expect_fail(run, line);
    free(line);
    /* An error no visibility has (it hung the chart's axis) */
    cJSON *summary_tuned = cJSON_GetObjectItem(cJSON_GetObjectItem(j, "summary"), "tuned");
    const double kept = cJSON_GetObjectItem(summary_tuned, "error")->valuedouble;
    cJSON_AddNumberToObject((cJSON *)settings, "slope_bias", 1);
    cJSON_ReplaceItemInObject(summary_tuned, "error", cJSON_CreateNumber(1.7e308));
    write_json(path, j);
    line = util_printf("shadowbench: error: %s: \"summary\" (default, tuned) or \"frontier\" (all, scenes) is "
                       "missing or malformed\n", path);
    expect_fail(run, line);
    free(line);
    cJSON_ReplaceItemInObject(summary_tuned, "error", cJSON_CreateNumber(kept));
    cJSON_DeleteItemFromObject((cJSON *)settings, "slope_bias");
    /* A fold missing: its scene would get the setting fitted on it. */
    cJSON_AddNumberToObject((cJSON *)settings, "slope_bias", 1);
    cJSON_DeleteItemFromArray(cJSON_GetObjectItem(j, "folds"), 1);
    write_json(path, j);
    line = util_printf("shadowbench: error: %s: \"scenes\" must name 2 or more scenes, each once, and \"folds\" "
                       "hold one per scene in that order\n", path);
    expect_fail(run, line);
    free(line);
    free(run);
    cJSON_Delete(j);
    free(path);

    /* Usage. */
    char *bad = util_printf("%s tune --scene parallel_planes --out %s/one", sb, dir);
    expect_fail(bad, "shadowbench: error: tune: needs 2 to 64 scenes (each scene's setting is chosen on the "
                     "others), got 1\n");
    free(bad);
    bad = util_printf("%s tune --objective mae", sb);
    expect_fail(bad, "shadowbench: error: --objective: 'mae' is not one of: penumbra_rmse, rmse, shaded_rmse\n");
    free(bad);
    bad = util_printf("%s tune --technique hard --set pcf.samples=16", sb);
    expect_fail(bad, "shadowbench: error: --set: pcf is not among the techniques selected with --technique\n");
    free(bad);
    bad = util_printf("%s run --settings tuned --set hard.slope_bias=1", sb);
    expect_fail(bad, "shadowbench: error: --settings tuned: --set and --sweep change default cells, and this run "
                     "has none\n");
    free(bad);
    bad = util_printf("%s run --settings tuned --technique hard --tuned %s/nothing", sb, dir);
    char *want = util_printf("shadowbench: error: --tuned %s/nothing: no such folder\n", dir);
    expect_fail(bad, want);
    free(bad), free(want);
    char *empty = util_printf("%s/empty", dir);
    util_mkdirs(empty);
    bad = util_printf("%s run --settings tuned --technique hard --tuned %s", sb, empty);
    want = util_printf("shadowbench: error: %s/hard.json: no tuned settings for hard (shadowbench tune "
                       "--write-tuned makes them)\n", empty);
    expect_fail(bad, want);
    free(bad), free(want);
    /* Not a regular file: said, not taken for "no tuned file". */
    char *folder = util_printf("%s/hard.json", empty);
    util_mkdirs(folder);
    bad = util_printf("%s run --technique hard --tuned %s", sb, empty);
    want = util_printf("shadowbench: error: %s: cannot read: Is a directory\n", folder);
    expect_fail(bad, want);
    free(bad), free(want), free(folder);
    /* tune writes only into a folder of tuned settings, and only with --write-tuned */
    char *notes = util_printf("%s/notes.txt", empty);
    util_write_file_atomic(notes, "mine", 4);
    bad = util_printf("%s tune --technique hard --scene parallel_planes --scene contact_hardening --write-tuned "
                      "--allow-uncommitted "
                      "--tuned %s --out %s/t2", sb, empty, dir);
    want = util_printf("shadowbench: error: --tuned %s: holds notes.txt, which tune does not write: name a folder "
                       "of tuned settings\n", empty);
    expect_fail(bad, want);
    free(notes), free(bad), free(want), free(empty);
    bad = util_printf("%s tune --tuned %s/tuned", sb, dir);
    expect_fail(bad, "shadowbench: error: --tuned: tune writes there only with --write-tuned\n");
    free(bad);
    bad = util_printf("%s run --technique hard --set pcf.samples=64", sb);
    expect_fail(bad, "shadowbench: error: --set: pcf is not among the techniques selected with --technique\n");
    free(bad);
}

/* tune --cost fetches: every point counts its fetches, the frontiers are
 * Pareto fronts of error against them, the file says so, and run draws the
 * frontier chart by fetches. pcf's samples set its fetches exactly, so
 * the front is a staircase over tap counts. */
static void cost_fetches(void)
{
    /* the pattern held: the staircase is over tap counts, and each pattern's
     * programs are compiled anew on a machine whose shader cache is cold */
    run_tune("tune --cost fetches", "--technique pcf --set pcf.pattern=poisson --cost fetches --scene parallel_planes "
                                    "--scene contact_hardening --width 48 --height 48 --gt-samples 16 --frames 1 "
                                    "--no-cache -q --out %s/tune_fetches --write-tuned --allow-uncommitted --tuned "
                                    "%s/tuned_fetches");
    char *path = util_printf("%s/tuned_fetches/pcf.json", dir);
    cJSON *j = read_json(path);
    CHECK(j && strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(j, "cost")), "fetches") == 0,
          "%s: cost fetches", path);
    const cJSON *p;
    double last = -1, last_error = INFINITY;
    int n = 0;
    cJSON_ArrayForEach(p, cJSON_GetObjectItem(cJSON_GetObjectItem(j, "frontier"), "all")) {
        const cJSON *f = cJSON_GetObjectItem(p, "fetches");
        const double e = cJSON_GetObjectItem(p, "error")->valuedouble;
        CHECK(cJSON_IsNumber(f) && f->valuedouble >= last && e < last_error,
              "fetches frontier point %d: %g fetches, %g after %g, %g", n, cJSON_GetNumberValue(f), e, last,
              last_error);
        /* pcf: its tap count on every pixel of these scenes inside the map */
        CHECK(cJSON_IsNumber(f) && f->valuedouble <= 128 && f->valuedouble >= 15, "pcf's fetches are its taps: %g",
              cJSON_GetNumberValue(f));
        last = cJSON_GetNumberValue(f), last_error = e, n++;
    }
    CHECK(n >= 1, "an empty frontier");
    cJSON_Delete(j);
    free(path);
    char *cmd = util_printf("%s run --technique pcf --scene parallel_planes --scene contact_hardening --width 32 --height 32 "
                      "--gt-samples 4 --frames 1 --no-cache -q --tuned %s/tuned_fetches --out %s/run_fetches", sb, dir,
                      dir);
    CHECK(run_cmd(cmd, NULL, NULL) == 0, "%s", cmd);
    free(cmd);
    char *svg = util_printf("%s/run_fetches/charts/frontier.svg", dir), *text = NULL;
    size_t size;
    CHECK(util_read_file(svg, &text, &size) == 0 && strstr(text, "fetches per covered pixel"),
          "%s: the frontier chart's axis is fetches", svg);
    free(text), free(svg);
}

static bool keeps_held(const cJSON *settings)
{
    const char *rotation = cJSON_GetStringValue(cJSON_GetObjectItem(settings, "rotation"));
    return cJSON_GetNumberValue(cJSON_GetObjectItem(settings, "samples")) == 16 && rotation &&
           strcmp(rotation, "blue_noise") == 0;
}

/* tune --set: seed 003's 16 taps and blue noise held, pcf's other
 * parameters searched; a tuned parameter held (samples) leaves the space */
static void held(void)
{
    run_tune("tune --set", "--technique pcf --set pcf.samples=16 --set pcf.rotation=blue_noise --set "
                           "pcf.pattern=poisson --scene parallel_planes --scene contact_hardening --width 32 --height 32 "
                           "--gt-samples 16 --frames 1 --no-cache -q --out %s/tune_held");
    char *path = util_printf("%s/tune_held/pcf.json", dir);
    cJSON *j = read_json(path);
    CHECK(j, "%s: not written", path);
    if (!j) {
        free(path);
        return;
    }
    const cJSON *held = cJSON_GetObjectItem(j, "held"), *space = cJSON_GetObjectItem(j, "space");
    CHECK(cJSON_GetNumberValue(cJSON_GetObjectItem(held, "samples")) == 16 &&
              strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(held, "rotation")), "blue_noise") == 0 &&
              cJSON_GetArraySize(held) == 3,
          "%s: held lists the three parameters --set", path);
    CHECK(!cJSON_GetObjectItem(space, "samples") && cJSON_GetObjectItem(space, "radius_texels"),
          "%s: samples left the space, radius_texels is in it", path);
    /* every setting it records keeps them: the all-scene one and each fold's */
    int settings = 1, kept = keeps_held(cJSON_GetObjectItem(j, "settings"));
    const cJSON *fold;
    cJSON_ArrayForEach(fold, cJSON_GetObjectItem(j, "folds"))
        settings++, kept += keeps_held(cJSON_GetObjectItem(fold, "settings"));
    CHECK(settings == 3 && kept == settings, "%s: %d of %d settings keep the held values", path, kept, settings);
    cJSON_Delete(j);
    free(path);
}

TEST_MAIN(dir, search, tables, command, cost_fetches, held)
