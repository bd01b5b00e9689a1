#include "provenance.h"
#include "base/log.h"
#include "base/util.h"
#include "gl/gl_context.h"

#include <OpenEXR/openexr.h>
#include <embree3/rtcore.h>

#include <errno.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static char *command_line(int argc, char **argv)
{
    struct strbuf cmd = {0};
    for (int i = 0; i < argc; i++)
        strbuf_list_printf(&cmd, " ", "%s", argv[i]);
    char *text = util_utf8_copy(cmd.data ? cmd.data : "");
    strbuf_free(&cmd);
    return text;
}

static char *utc_date(void)
{
    char date[64];
    time_t now = time(NULL);
    strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", gmtime(&now));
    return xstrdup(date);
}

/* The paths whose changes change what is rendered or scored. */
static const char source_paths[] = "harness techniques shaders scenes engines CMakeLists.txt";

enum source_state provenance_source_state(char *what, size_t size)
{
    /* git's own words on failure (2>&1), its status last */
    char *cmd = util_printf("git -C '%s' status --porcelain --untracked-files=all -- %s 2>&1; echo \"rc=$?\"",
                            SB_SOURCE_DIR, source_paths);
    FILE *p = popen(cmd, "r");
    free(cmd);
    snprintf(what, size, "%s", p ? "" : strerror(errno));
    char line[1024], first[512] = "";
    int rc = -1;
    bool changed = false;
    while (p && fgets(line, sizeof line, p)) {
        line[strcspn(line, "\n")] = '\0';
        if (strncmp(line, "rc=", 3) == 0) {
            rc = atoi(line + 3);
        } else {
            if (!first[0])
                snprintf(first, sizeof first, "%.*s", (int)sizeof first - 1, line);
            changed = changed || strlen(line) > 3;
        }
    }
    if (p)
        pclose(p);
    if (rc == 0 && changed)
        snprintf(what, size, "%s", first + 3);  /* "XY path": the first path changed */
    else if (rc != 0 && p)
        snprintf(what, size, "%s", rc == 127 ? "git is not installed" : first[0] ? first : "git failed");
    return rc == 0 ? (changed ? SOURCE_CHANGED : SOURCE_CLEAN)
           : rc == 128 && strstr(first, "not a git repository") ? SOURCE_NOT_GIT : SOURCE_UNKNOWN;
}

const char *provenance_source_text(enum source_state s)
{
    return s == SOURCE_CLEAN     ? "committed"
           : s == SOURCE_CHANGED ? "uncommitted changes to code that renders or scores"
           : s == SOURCE_NOT_GIT ? "not a git checkout"
                                 : "unknown: git failed";
}

/* `git describe --always` of the source tree, "-dirty" where its code
 * has changes (state): a results file a tuning has just rewritten
 * (results/tuned/) is not the code. "unknown" without git; malloc'ed. */
static char *git_describe(enum source_state state)
{
    char buf[128] = "unknown";
    char *cmd = util_printf("git -C '%s' describe --always 2>/dev/null", SB_SOURCE_DIR);
    FILE *p = popen(cmd, "r");
    free(cmd);
    if (p) {
        if (!fgets(buf, sizeof buf, p))
            strcpy(buf, "unknown");
        pclose(p);
    }
    buf[strcspn(buf, "\n")] = '\0';
    return util_printf("%s%s", buf, strcmp(buf, "unknown") != 0 && state == SOURCE_CHANGED ? "-dirty" : "");
}

/* The hash of what cmd prints; 0 when it fails. */
static uint64_t hash_output(const char *cmd)
{
    FILE *p = popen(cmd, "r");
    uint64_t h = UTIL_HASH_INIT;
    char buf[65536];
    for (size_t n; p && (n = fread(buf, 1, sizeof buf, p)) > 0;)
        h = util_hash(h, buf, n);
    return p && pclose(p) == 0 ? h : 0;
}

static char *code_now(void)
{
    char head[64] = "", what[512];
    const enum source_state state = provenance_source_state(what, sizeof what);
    char *cmd = util_printf("git -C '%s' rev-parse HEAD 2>/dev/null", SB_SOURCE_DIR);
    FILE *p = state == SOURCE_CLEAN || state == SOURCE_CHANGED ? popen(cmd, "r") : NULL;
    free(cmd);
    if (p) {
        if (!fgets(head, sizeof head, p))
            head[0] = '\0';
        pclose(p);
    }
    head[strcspn(head, "\n")] = '\0';
    if (!head[0]) {  /* no commit to name it: the program itself */
        char *exe = NULL;
        size_t size = 0;
        const uint64_t h = util_read_file("/proc/self/exe", &exe, &size) == 0 ? util_hash(UTIL_HASH_INIT, exe, size) : 0;
        free(exe);
        return util_printf("shadowbench %s, executable %016llx", SB_VERSION, (unsigned long long)h);
    }
    if (state == SOURCE_CLEAN)
        return util_printf("git %s", head);
    cmd = util_printf("cd '%s' && git diff HEAD --binary -- %s && git ls-files -o --exclude-standard -z -- %s | "
                      "xargs -0r cat --", SB_SOURCE_DIR, source_paths, source_paths);
    const uint64_t changes = hash_output(cmd);
    free(cmd);
    if (!changes)  /* git failed: nothing names the changes */
        return util_printf("git %s +changes unknown", head);
    return util_printf("git %s +changes %016llx", head, (unsigned long long)changes);
}

char *provenance_code_id(void)
{
    static char *id;  /* the tree as it was when first asked: the code this process loaded */
    if (!id)
        id = code_now();
    return xstrdup(id);
}

static char *cpu_model(void)
{
    char line[512];
    FILE *f = fopen("/proc/cpuinfo", "r");
    char *model = NULL;
    while (f && !model && fgets(line, sizeof line, f))
        if (strncmp(line, "model name", 10) == 0 && strchr(line, ':')) {
            char *v = strchr(line, ':') + 2;
            v[strcspn(v, "\n")] = '\0';
            model = xstrdup(v);
        }
    if (f)
        fclose(f);
    return model ? model : xstrdup("unknown");
}

cJSON *provenance_json(int argc, char **argv, bool timed, enum stage_timing timing)
{
    cJSON *r = cJSON_CreateObject();
    char changed[512];
    const enum source_state state = provenance_source_state(changed, sizeof changed);
    static bool warned;
    if (state == SOURCE_UNKNOWN && !warned)  /* said once: every record of the process would say it */
        log_warn("git failed on the source tree %s (%s): what is recorded cannot name the code it came from",
                 SB_SOURCE_DIR, changed);
    warned = warned || state == SOURCE_UNKNOWN;
    char *cmd = command_line(argc, argv), *git = git_describe(state), *cpu = cpu_model(), *date = utc_date();
    cJSON_AddStringToObject(r, "command_line", cmd);
    cJSON_AddStringToObject(r, "shadowbench_version", SB_VERSION);
    cJSON_AddStringToObject(r, "git_describe", git);
    cJSON_AddStringToObject(r, "source_tree", provenance_source_text(state));
    cJSON_AddStringToObject(r, "gl_renderer", gl_context_renderer());
    cJSON_AddStringToObject(r, "gl_vendor", gl_context_vendor());
    cJSON_AddStringToObject(r, "gl_version", gl_context_version());
    cJSON_AddStringToObject(r, "gl_platform", gl_context_platform());
    cJSON_AddStringToObject(r, "timing_method",
                            timed ? stage_timing_text(timing) : "none (this command times nothing)");
    cJSON_AddStringToObject(r, "embree_version", RTC_VERSION_STRING);
    cJSON_AddStringToObject(r, "openexr_version", OPENEXR_VERSION_STRING);
    cJSON_AddStringToObject(r, "cpu", cpu);
    cJSON_AddNumberToObject(r, "cpu_threads", (double)sysconf(_SC_NPROCESSORS_ONLN));
    cJSON_AddStringToObject(r, "date", date);
    free(cmd), free(git), free(cpu), free(date);
    return r;
}
