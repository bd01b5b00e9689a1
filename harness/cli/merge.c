/* Shards and their merge (docs/scale-out.md, docs/design.md §13): what a
 * sharded command records of itself (shard.json), and `shadowbench merge
 * OUT SHARD...`, which checks that the shards are the N parts of one
 * command of one code and hands them to that command's merge (run.c,
 * tune.c, check.c, stability.c). */
#include "cli.h"
#include "base/log.h"
#include "base/util.h"
#include "output/out_dir.h"
#include "output/provenance.h"
#include "output/report.h"
#include "truth/groundtruth.h"

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

void cli_shard_begin(const struct options *o)
{
    char *path = out_dir_path(o->out_dir, OUTPUT_SHARD_JSON);
    unlink(path);
    free(path);
    if (o->shard.count)
        free(provenance_code_id());  /* the code as the shard starts (provenance.h) */
}

int cli_shard_end(const struct options *o, const struct scene *scenes, int scene_count, cJSON *more)
{
    if (o->shard.count == 0) {
        cJSON_Delete(more);
        return 0;
    }
    cJSON *j = cJSON_CreateObject();
    cJSON *s = cJSON_AddObjectToObject(j, "shard");
    cJSON_AddNumberToObject(s, "index", o->shard.index);
    cJSON_AddNumberToObject(s, "count", o->shard.count);
    cJSON_AddStringToObject(j, "command", commands[o->cmd].name);
    cJSON *args = cJSON_AddArrayToObject(j, "arguments");
    for (int i = 2; i < o->argc; i++)  /* o->argv[1] is the command; placement is indexed from it */
        if (!o->placement || !o->placement[i - 1])
            cJSON_AddItemToArray(args, cJSON_CreateString(o->argv[i]));
    char *code = provenance_code_id();
    cJSON_AddStringToObject(j, "code", code);
    free(code);
    cJSON_AddNumberToObject(j, "ground_truth_version", GT_VERSION);
    cJSON *list = cJSON_AddArrayToObject(j, "scenes");
    for (int i = 0; i < scene_count; i++) {
        cJSON *e = cJSON_CreateObject();
        char bytes[17];
        snprintf(bytes, sizeof bytes, "%016llx", (unsigned long long)scenes[i].hash);
        cJSON_AddStringToObject(e, "name", scenes[i].name);
        cJSON_AddStringToObject(e, "bytes", bytes);
        cJSON_AddItemToArray(list, e);
    }
    util_json_merge(j, more);
    cJSON_Delete(more);
    cJSON *provenance = provenance_json(o->argc, o->argv, o->cmd == CMD_RUN || o->cmd == CMD_TUNE, o->timing);
    cJSON_AddItemToObject(j, "provenance", provenance);
    cJSON_AddTrueToObject(j, "complete");
    char *path = out_dir_path(o->out_dir, OUTPUT_SHARD_JSON);
    const int rc = report_write_json(path, j);
    free(path);
    cJSON_Delete(j);
    return rc;
}

/* The shard in folder dir: its record, or NULL (logged). The folder's
 * lock is held shared until the process ends: no shadowbench writes
 * there while it is merged, and one writing there now is refused. */
static cJSON *read_shard(const char *dir)
{
    char *path = out_dir_path(dir, OUTPUT_SHARD_JSON), *text = NULL, *lock = util_printf("%s/.lock", dir);
    size_t size;
    cJSON *j = NULL;
    const int fd = open(lock, O_RDONLY | O_CLOEXEC | O_NOFOLLOW);  /* none: a shard copied without it */
    const bool busy = fd >= 0 && flock(fd, LOCK_SH | LOCK_NB) != 0;
    free(lock);
    if (!util_is_dir(dir))
        log_error("merge: %s: not a folder", dir);
    else if (busy)
        log_error("merge: %s: a shadowbench is writing there now: merge it once its command has finished", dir);
    else if (util_read_file(path, &text, &size) != 0)
        log_error("merge: %s: no shard.json, so not a finished shard (its command failed, was stopped, is still "
                  "running, or ran without --shard)", dir);
    else if (!(j = cJSON_Parse(text)) || !cJSON_IsObject(cJSON_GetObjectItem(j, "shard")) ||
             !cJSON_IsString(cJSON_GetObjectItem(j, "command")) ||
             !cJSON_IsArray(cJSON_GetObjectItem(j, "arguments")) || !cJSON_IsTrue(cJSON_GetObjectItem(j, "complete")))
        log_error("merge: %s: not a shard record shadowbench writes", path);
    else {
        free(text), free(path);
        return j;
    }
    cJSON_Delete(j);
    free(text), free(path);
    return NULL;
}

static int shard_number(const cJSON *j, const char *key)
{
    const double v = cJSON_GetNumberValue(cJSON_GetObjectItem(cJSON_GetObjectItem(j, "shard"), key));
    return v >= 1 && v <= SHARD_MAX && v == (int)v ? (int)v : 0;
}

/* What must agree across shards: each key's text, and how to say it differs. */
static const struct {
    const char *key, *what;
} same[] = {
    {"command", "another command"},
    {"arguments", "other arguments (settings, scenes or techniques)"},
    {"code", "other code"},
    {"ground_truth_version", "another ground-truth version"},
    {"scenes", "other scenes (names or bytes)"},
    {"plan", "other cells (the tuned settings or baselines they read)"},
};

/* Checks that records[0..n-1] (of folders dirs) are shards 1..N of one
 * command of one code, this program's; their folders by index into
 * by_index[1..N]. Returns 0 or -1 (one line logged). */
static int check_shards(cJSON *const *records, char *const *dirs, int n, const char **by_index)
{
    const int count = shard_number(records[0], "count");
    for (int i = 0; i < n; i++) {
        const int k = shard_number(records[i], "index"), c = shard_number(records[i], "count");
        if (!k || c != count || k > count) {
            log_error("merge: %s is shard %d of %d, %s shard %d of %d: not parts of one split", dirs[i], k, c,
                      dirs[0], shard_number(records[0], "index"), count);
            return -1;
        }
        for (size_t s = 0; s < ARRAY_SIZE(same); s++) {
            char *a = cJSON_PrintUnformatted(cJSON_GetObjectItem(records[0], same[s].key));
            char *b = cJSON_PrintUnformatted(cJSON_GetObjectItem(records[i], same[s].key));
            const bool differ = !a || !b || strcmp(a, b) != 0;
            if (!b)
                log_error("merge: %s: its shard.json records no %s: not a shard this shadowbench wrote", dirs[i],
                          same[s].key);
            else if (differ)
                log_error("merge: %s is a shard of %s than %s (%s: %s against %s)", dirs[i], same[s].what, dirs[0],
                          same[s].key, b ? b : "none", a ? a : "none");
            cJSON_free(a), cJSON_free(b);
            if (differ)
                return -1;
        }
        if (by_index[k]) {
            log_error("merge: %s and %s are both shard %d of %d: give each shard once", by_index[k], dirs[i], k,
                      count);
            return -1;
        }
        by_index[k] = dirs[i];
    }
    struct strbuf missing = {0};
    for (int k = 1, listed = 0; k <= count; k++)
        if (!by_index[k] && listed++ < 10)
            strbuf_list_printf(&missing, ", ", "%d", k);
    if (n + 10 < count)
        strbuf_printf(&missing, " and %d more", count - n - 10);
    if (missing.data)
        log_error("merge: shard(s) %s of %d missing: every shard's folder is needed", missing.data, count);
    const bool incomplete = missing.data != NULL;
    strbuf_free(&missing);
    if (incomplete)
        return -1;
    char *code = provenance_code_id();
    const char *theirs = cJSON_GetStringValue(cJSON_GetObjectItem(records[0], "code"));
    const bool unknown = !theirs || strstr(theirs, "unknown"), other = unknown || strcmp(theirs, code) != 0;
    if (unknown)
        log_error("merge: the shards could not name their code (%s): nothing tells whether they ran one code",
                  theirs ? theirs : "none recorded");
    else if (other)
        log_error("merge: the shards ran %s, this shadowbench is %s: merge with the code the shards ran",
                  theirs, code);
    free(code);
    return other ? -1 : 0;
}

/* The command line the shards split, writing into out: parsed into *o
 * (its argv kept in *argv_out, freed by the caller). Returns 0 or -1. */
static int unsharded_options(const cJSON *record, const char *out, struct options *o, char ***argv_out)
{
    const cJSON *args = cJSON_GetObjectItem(record, "arguments");
    const int n = cJSON_GetArraySize(args);
    char **argv = xcalloc((size_t)n + 5, sizeof *argv);
    int argc = 0;
    argv[argc++] = "shadowbench";
    argv[argc++] = cJSON_GetStringValue(cJSON_GetObjectItem(record, "command"));
    for (const cJSON *a = args ? args->child : NULL; a; a = a->next)
        argv[argc++] = cJSON_GetStringValue(a);
    argv[argc++] = "--out";
    argv[argc++] = (char *)out;
    *argv_out = argv;
    int cmd = -1;
    for (int k = 0; k < COMMAND_COUNT; k++)
        if (argv[1] && !strcmp(commands[k].name, argv[1]))
            cmd = k;
    if (cmd != CMD_RUN && cmd != CMD_TUNE && cmd != CMD_CHECK && cmd != CMD_STABILITY) {
        log_error("merge: the shards record a command that is not run, tune, check or stability");
        return -1;
    }
    for (int i = 2; i < argc; i++)  /* what a shard's command line held, or not a shard's */
        if (!argv[i] || !strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            log_error("merge: the shards record arguments no shard ran with (%s)", argv[i] ? argv[i] : "not text");
            return -1;
        }
    *o = (struct options){.argc = argc, .argv = argv};
    if (cli_parse(argc - 1, argv + 1, (enum command)cmd, o) != CLI_PARSE_OK) {
        log_error("merge: the shards' command line does not parse here (above)");
        return -1;
    }
    return 0;
}

int merge_main(const struct options *mo)
{
    if (mo->operand_count < 2) {
        log_error("merge: needs OUT and at least one SHARD folder (see --help)");
        return EXIT_USAGE;
    }
    const char *out = mo->operands[0];
    char *const *dirs = mo->operands + 1;
    struct stat st;
    if (!*out || (stat(out, &st) == 0 && !S_ISDIR(st.st_mode))) {
        log_error("merge: OUT '%s': %s", out, *out ? "not a folder" : "an empty folder name");
        return EXIT_USAGE;
    }
    const int n = mo->operand_count - 1;
    cJSON **records = xcalloc((size_t)n, sizeof *records);
    const char **by_index = NULL;
    char **argv = NULL;
    struct options o = {0};
    int status = EXIT_USAGE;
    for (int i = 0; i < n; i++) {
        if (!(records[i] = read_shard(dirs[i])))
            goto out;
        if (util_path_within(out, dirs[i]) || util_path_within(dirs[i], out)) {
            log_error("merge: OUT %s and the shard %s: one inside the other; name a folder apart", out, dirs[i]);
            goto out;
        }
    }
    by_index = xcalloc((size_t)shard_number(records[0], "count") + 1, sizeof *by_index);
    if (check_shards(records, dirs, n, by_index) != 0 || unsharded_options(records[0], out, &o, &argv) != 0)
        goto out;
    /* the shards by index, as the split numbers them */
    const int count = shard_number(records[0], "count");
    cJSON **ordered = xcalloc((size_t)count + 1, sizeof *ordered);
    for (int i = 0; i < n; i++)
        ordered[shard_number(records[i], "index")] = records[i];
    const struct merge_input in = {by_index, ordered, count, mo};
    log_info("merge: %d shard(s) of %s into %s", count, commands[o.cmd].name, out);
    switch (o.cmd) {
    case CMD_RUN: status = run_merge(&o, &in); break;
    case CMD_TUNE: status = tune_merge(&o, &in); break;
    case CMD_CHECK: status = check_merge(&o, &in); break;
    default: status = stability_merge(&o, &in); break;
    }
    free(ordered);
out:
    cli_options_free(&o);
    free(argv);
    free(by_index);
    for (int i = 0; i < n; i++)
        cJSON_Delete(records[i]);
    free(records);
    return status;
}

bool cli_is_file(const char *path)
{
    struct stat st;
    if (lstat(path, &st) == 0 && S_ISREG(st.st_mode))
        return true;
    log_error("merge: %s: %s", path, access(path, F_OK) != 0 && errno == ENOENT ? "missing"
                                                                                 : "not a file (a link, a folder)");
    return false;
}

int cli_copy_file(const char *from, const char *to)
{
    if (!cli_is_file(from))
        return -1;
    char *dir = xstrdup(to), *slash = strrchr(dir, '/'), *data = NULL;
    if (slash)
        *slash = '\0';
    size_t size;
    const int err = util_read_file(from, &data, &size);
    if (err)
        log_error("merge: %s: %s", from, util_read_error(err));
    const int rc = err || (slash && util_mkdirs_own(dir, 1) != 0) || util_write_file_atomic(to, data, size) != 0;
    free(data), free(dir);
    return rc ? -1 : 0;
}

uint64_t cli_plan_add(uint64_t plan, const char *name)
{
    return util_hash(plan, name, strlen(name) + 1);
}

static void plan_text(uint64_t plan, char text[17])
{
    snprintf(text, 17, "%016llx", (unsigned long long)plan);
}

cJSON *cli_shard_more(double seconds, uint64_t plan)
{
    cJSON *j = cJSON_CreateObject();
    char text[17];
    plan_text(plan, text);
    cJSON_AddNumberToObject(j, "seconds", seconds);
    cJSON_AddStringToObject(j, "plan", text);
    return j;
}

int cli_merge_plan(const struct merge_input *in, uint64_t plan)
{
    char text[17];
    plan_text(plan, text);
    const char *theirs = cJSON_GetStringValue(cJSON_GetObjectItem(in->records[1], "plan"));
    if (theirs && !strcmp(theirs, text))
        return 0;
    log_error("merge: the shards split other cells than their command line gives here (plan %s, here %s): the "
              "tuned settings or baselines it reads are not those they read (merge in the folder they ran in; if "
              "those files changed since, run the shards again)", theirs ? theirs : "none", text);
    return -1;
}

double cli_merge_seconds(const struct merge_input *in)
{
    double seconds = 0;
    for (int k = 1; k <= in->count; k++)
        seconds = fmax(seconds, util_json_number(in->records[k], "seconds"));
    return seconds;
}

void cli_merge_record(cJSON *r, const struct merge_input *in)
{
    /* the device the shards rendered on, not the merge's (none): each key
     * the shards' value, or their values joined where they differ */
    static const char *const device_keys[] = {"gl_renderer", "gl_vendor", "gl_version", "gl_platform",
                                              "timing_method", "cpu", "cpu_threads"};
    for (size_t d = 0; d < ARRAY_SIZE(device_keys); d++) {
        if (!cJSON_HasObjectItem(r, device_keys[d]))  /* a record without it (tune.json) */
            continue;
        cJSON *values = cJSON_CreateArray();
        for (int k = 1; k <= in->count; k++) {
            const cJSON *v = cJSON_GetObjectItem(cJSON_GetObjectItem(in->records[k], "provenance"), device_keys[d]);
            bool seen = !v;
            for (const cJSON *e = values->child; e && !seen; e = e->next)
                seen = cJSON_Compare(e, v, true);
            if (!seen)
                cJSON_AddItemToArray(values, cJSON_Duplicate(v, true));
        }
        cJSON_DeleteItemFromObject(r, device_keys[d]);  /* the merge's own */
        if (cJSON_GetArraySize(values) == 1) {
            cJSON_AddItemToObject(r, device_keys[d], cJSON_DetachItemFromArray(values, 0));
            cJSON_Delete(values);
        } else {
            cJSON_AddItemToObject(r, device_keys[d], values);
        }
    }
    cJSON *shards = cJSON_AddArrayToObject(r, "shards");
    for (int k = 1; k <= in->count; k++) {  /* each one's identity, not its results (merged here) */
        static const char *const keys[] = {"shard", "code", "seconds", "ground_truth", "provenance"};
        cJSON *s = cJSON_CreateObject();
        cJSON_AddStringToObject(s, "folder", in->dirs[k]);
        for (size_t i = 0; i < ARRAY_SIZE(keys); i++) {
            const cJSON *v = cJSON_GetObjectItem(in->records[k], keys[i]);
            if (v)
                cJSON_AddItemToObject(s, keys[i], cJSON_Duplicate(v, 1));
        }
        cJSON_AddItemToArray(shards, s);
    }
    cJSON *merge = provenance_json(in->merge->argc, in->merge->argv, false, in->merge->timing);
    cJSON_AddItemToObject(r, "merged_by", merge);
}
