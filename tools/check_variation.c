/* How far two recordings of the same baselines differ: for each cell of A
 * (<scene>/<cell>.json and .png) also in B, every metric's difference and
 * the share of pixels that moved by more than BASELINE_PIXEL_THRESHOLD; prints
 * the largest of each over all cells, and where. tools/check-variation
 * records the baselines under llvmpipe's variations and runs this, to set
 * the tolerances of score/baseline.h.
 * Usage: check_variation DIR_A DIR_B */
#include "base/image.h"
#include "base/util.h"
#include "score/baseline.h"

#include <cjson/cJSON.h>
#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_METRICS 32

struct worst {
    char name[64], where[256];
    double value;
};

static cJSON *read_json(const char *path)
{
    char *text;
    size_t size;
    if (util_read_file(path, &text, &size) != 0)
        return NULL;
    cJSON *j = cJSON_ParseWithLength(text, size);
    free(text);
    return j;
}

static void note(struct worst *w, int *count, const char *name, double value, const char *where)
{
    int i = 0;
    while (i < *count && strcmp(w[i].name, name) != 0)
        i++;
    if (i == *count) {
        if (*count == MAX_METRICS)
            return;
        snprintf(w[i].name, sizeof w[i].name, "%s", name);
        w[i].value = -1.0;
        (*count)++;
    }
    if (value > w[i].value) {
        w[i].value = value;
        snprintf(w[i].where, sizeof w[i].where, "%s", where);
    }
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: check_variation DIR_A DIR_B\n");
        return 2;
    }
    struct worst w[MAX_METRICS];
    int count = 0, cells = 0;
    double moved_worst = 0.0;
    char moved_where[256] = "-";
    struct dirent **scenes;
    const int n = scandir(argv[1], &scenes, NULL, alphasort);
    for (int s = 0; s < n; s++) {
        char *dir = util_printf("%s/%s", argv[1], scenes[s]->d_name);
        struct dirent **files;
        const int m = scenes[s]->d_name[0] == '.' ? -1 : scandir(dir, &files, NULL, alphasort);
        for (int f = 0; f < m; f++) {
            const char *name = files[f]->d_name;
            const size_t len = strlen(name);
            if (len > 5 && strcmp(name + len - 5, ".json") == 0) {
                char *where = util_printf("%s/%.*s", scenes[s]->d_name, (int)(len - 5), name);
                char *pa = util_printf("%s/%s.json", argv[1], where), *pb = util_printf("%s/%s.json", argv[2], where);
                cJSON *a = read_json(pa), *b = read_json(pb);
                const cJSON *ma = cJSON_GetObjectItemCaseSensitive(a, "metrics"), *mb = cJSON_GetObjectItemCaseSensitive(b, "metrics");
                const cJSON *sa = cJSON_GetObjectItemCaseSensitive(a, "settings");
                const int width = (int)cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(sa, "width"));
                const int height = (int)cJSON_GetNumberValue(cJSON_GetObjectItemCaseSensitive(sa, "height"));
                const cJSON *x;
                cJSON_ArrayForEach(x, ma) {
                    const cJSON *y = cJSON_GetObjectItemCaseSensitive(mb, x->string);
                    if (cJSON_IsNumber(x) && cJSON_IsNumber(y))
                        note(w, &count, x->string, fabs(x->valuedouble - y->valuedouble), where);
                }
                char *ia = util_printf("%s/%s.png", argv[1], where), *ib = util_printf("%s/%s.png", argv[2], where);
                uint16_t *va, *vb;
                if (a && b && image_read_png16(ia, width, height, &va) == 0 &&
                    image_read_png16(ib, width, height, &vb) == 0) {
                    size_t moved = 0;
                    for (int i = 0; i < width * height; i++)
                        moved += fabs(((double)va[i] - (double)vb[i]) / 65535.0) > BASELINE_PIXEL_THRESHOLD;
                    const double share = (double)moved / ((double)width * height);
                    if (share > moved_worst) {
                        moved_worst = share;
                        snprintf(moved_where, sizeof moved_where, "%s", where);
                    }
                    free(va), free(vb);
                    cells++;
                }
                cJSON_Delete(a), cJSON_Delete(b);
                free(where), free(pa), free(pb), free(ia), free(ib);
            }
            free(files[f]);
        }
        if (m >= 0)
            free(files);
        free(dir);
        free(scenes[s]);
    }
    if (n >= 0)
        free(scenes);
    printf("%d cells compared\n", cells);
    for (int i = 0; i < count; i++)
        printf("  %-16s largest difference %.3g (%s)\n", w[i].name, w[i].value, w[i].where);
    printf("  pixels moved by more than %g: at most %.3f %% of a cell (%s)\n", BASELINE_PIXEL_THRESHOLD,
           100.0 * moved_worst, moved_where);
    return cells ? 0 : 1;
}
