/* same_results run|tune|stability A B: whether two output folders hold the
 * same results, timings aside (docs/scale-out.md: a merge of shards
 * against the command unsharded). run: matrix.json's cells, every metric
 * but the times (ms_*), and depth.csv, each cell's pictures and each
 * scene's ground-truth pictures byte for byte; tune: each technique of A's
 * tune.json, its record in A and B (a tuned folder), but its times (ms,
 * ms_q1, ms_q3, seconds) and where and when it ran (command_line, date);
 * stability: stability.json but its run record. Prints what differs; exit
 * 0 same, 1 different, 2 unreadable. */
#include "base/util.h"

#include <cjson/cJSON.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int differences;

static cJSON *read_json(const char *path)
{
    char *text = NULL;
    size_t size;
    cJSON *j = util_read_file(path, &text, &size) == 0 ? cJSON_Parse(text) : NULL;
    free(text);
    if (!j) {
        fprintf(stderr, "same_results: %s: not readable JSON\n", path);
        exit(2);
    }
    return j;
}

static bool timing_key(const char *k, bool run)
{
    static const char *const tune_keys[] = {"ms", "ms_q1", "ms_q3", "seconds", "command_line", "date"};
    if (run)
        return strncmp(k, "ms_", 3) == 0;
    for (size_t i = 0; i < ARRAY_SIZE(tune_keys); i++)
        if (!strcmp(k, tune_keys[i]))
            return true;
    return false;
}

/* j without its timing keys, at every depth. */
static void strip(cJSON *j, bool run)
{
    for (cJSON *c = j ? j->child : NULL, *next; c; c = next) {
        next = c->next;
        if (c->string && timing_key(c->string, run))
            cJSON_Delete(cJSON_DetachItemViaPointer(j, c));
        else
            strip(c, run);
    }
}

static void same_json(const char *a, const char *b, bool run)
{
    cJSON *x = read_json(a), *y = read_json(b);
    strip(x, run), strip(y, run);
    if (!cJSON_Compare(x, y, true)) {
        printf("differ: %s and %s\n", a, b);
        differences++;
    }
    cJSON_Delete(x), cJSON_Delete(y);
}

static void same_bytes(const char *a, const char *b)
{
    char *x = NULL, *y = NULL;
    size_t nx = 0, ny = 0;
    const int ra = util_read_file(a, &x, &nx), rb = util_read_file(b, &y, &ny);
    if (ra || rb || nx != ny || memcmp(x, y, nx) != 0) {
        printf("differ: %s and %s\n", a, b);
        differences++;
    }
    free(x), free(y);
}

int main(int argc, char **argv)
{
    if (argc != 4 || (strcmp(argv[1], "run") && strcmp(argv[1], "tune") && strcmp(argv[1], "stability"))) {
        fprintf(stderr, "usage: same_results run|tune|stability A B\n");
        return 2;
    }
    const char *a = argv[2], *b = argv[3];
    if (!strcmp(argv[1], "stability")) {
        char *x = util_printf("%s/stability.json", a), *y = util_printf("%s/stability.json", b);
        cJSON *p = read_json(x), *q = read_json(y);
        cJSON_DeleteItemFromObject(p, "run"), cJSON_DeleteItemFromObject(q, "run");
        const bool same = cJSON_GetArraySize(p) > 0 && cJSON_Compare(p, q, true);
        printf("%s and %s: %s\n", x, y, same ? "the same but their run records" : "differ");
        free(x), free(y);
        cJSON_Delete(p), cJSON_Delete(q);
        return same ? 0 : 1;
    }
    const bool run = !strcmp(argv[1], "run");
    char *pa = util_printf("%s/%s", a, run ? "matrix.json" : "tune.json");
    cJSON *index = read_json(pa);
    free(pa);
    const cJSON *item;
    int items = 0;
    if (run) {
        cJSON_ArrayForEach(item, cJSON_GetObjectItem(index, "cells")) {
            const char *scene = cJSON_GetStringValue(cJSON_GetObjectItem(item, "scene")),
                       *cell = cJSON_GetStringValue(cJSON_GetObjectItem(item, "cell"));
            static const char *const files[] = {"metrics.json", "visibility.png", "heatmap.png", "visibility.exr",
                                                "error.exr"};
            for (size_t f = 0; f < ARRAY_SIZE(files); f++) {
                char *x = util_printf("%s/%s/%s/%s", a, scene, cell, files[f]),
                     *y = util_printf("%s/%s/%s/%s", b, scene, cell, files[f]);
                if (f == 0)
                    same_json(x, y, run);
                else
                    same_bytes(x, y);
                free(x), free(y);
            }
            for (size_t f = 0; f < 2; f++) {  /* its scene's ground truth */
                static const char *const truth[] = {"groundtruth.exr", "groundtruth.png"};
                char *x = util_printf("%s/%s/%s", a, scene, truth[f]), *y = util_printf("%s/%s/%s", b, scene, truth[f]);
                same_bytes(x, y);
                free(x), free(y);
            }
            items++;
        }
        char *x = util_printf("%s/matrix.json", a), *y = util_printf("%s/matrix.json", b);
        same_json(x, y, run);
        free(x), free(y);
        x = util_printf("%s/depth.csv", a), y = util_printf("%s/depth.csv", b);
        same_bytes(x, y);
        free(x), free(y);
    } else {
        cJSON_ArrayForEach(item, cJSON_GetObjectItem(index, "techniques")) {
            char *x = util_printf("%s/%s.json", a, cJSON_GetStringValue(item)),
                 *y = util_printf("%s/%s.json", b, cJSON_GetStringValue(item));
            same_json(x, y, run);
            free(x), free(y);
            items++;
        }
    }
    cJSON_Delete(index);
    if (!items) {
        fprintf(stderr, "same_results: %s holds no %s\n", a, run ? "cell" : "technique");
        return 2;
    }
    printf("%s and %s: %d %s compared, %d differ\n", a, b, items, run ? "cells" : "tunings", differences);
    return differences ? 1 : 0;
}
