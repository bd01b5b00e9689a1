#include "catalog.h"
#include "light_frustum.h"
#include "base/log.h"
#include "base/util.h"

#include <dirent.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

static bool is_gltf(const char *name)
{
    size_t n = strlen(name);
    return (n > 5 && strcmp(name + n - 5, ".gltf") == 0) || (n > 4 && strcmp(name + n - 4, ".glb") == 0);
}

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

static const char *scenes_dir(void)
{
    return util_find_dir(NULL, "SHADOWBENCH_SCENES", "scenes", "README.md");
}

int catalog_shipped(char ***paths)
{
    const char *dir = scenes_dir();
    DIR *d = dir ? opendir(dir) : NULL;
    if (!d)
        return -1;
    int n = 0;
    char **list = NULL;
    for (struct dirent *e; (e = readdir(d));) {
        if (!is_gltf(e->d_name))
            continue;
        list = xrealloc(list, sizeof *list * (size_t)(n + 1));
        list[n++] = util_printf("%s/%s", dir, e->d_name);
    }
    closedir(d);
    qsort(list, (size_t)n, sizeof *list, cmp_str);
    *paths = list;
    return n;
}

char *catalog_resolve(const char *arg)
{
    if (strchr(arg, '/') || is_gltf(arg))
        return xstrdup(arg);  /* a path: the loader reports if it is unreadable */
    char **paths;
    int n = catalog_shipped(&paths);
    if (n < 0)
        return NULL;
    char *found = NULL;
    struct strbuf names = {0};
    for (int i = 0; i < n; i++) {
        const char *base = strrchr(paths[i], '/') + 1;
        size_t stem = strcspn(base, ".");
        if (!found && strlen(arg) == stem && strncmp(base, arg, stem) == 0)
            found = xstrdup(paths[i]);
        strbuf_list_printf(&names, ", ", "%.*s", (int)stem, base);
    }
    if (!found)
        log_error("unknown scene '%s' (shipped: %s)", arg, names.data ? names.data : "none");
    strbuf_free(&names);
    catalog_free(paths, n);
    return found;
}

void catalog_free(char **paths, int count)
{
    for (int i = 0; i < count; i++)
        free(paths[i]);
    free(paths);
}

int catalog_check_name(const struct scene *s, const char *const *reserved)
{
    const char *n = s->name;
    bool control = false, bidi = false;
    unsigned cp;
    for (const char *p = n; *p;) {
        p += util_utf8_next(p, &cp);
        control |= cp < 32 || cp == 127 || cp == '/';
        bidi |= util_bidi_control(cp);
    }
    bool taken = false;
    for (const char *const *r = reserved; r && *r; r++)
        taken |= strcmp(n, *r) == 0;
    const bool long_name = strlen(n) > 200;  /* with "_tradeoff.svg" and the like, under 255 bytes */
    const bool utf8 = util_valid_utf8(n);
    if (!*n || n[0] == '.' || control || bidi || taken || long_name || !utf8) {
        log_error("%s: its name (the file's stem) cannot name its output folder: %s", s->path,
                  !*n || n[0] == '.' ? "it is empty or starts with '.'"
                  : control           ? "it holds a control character"
                  : bidi              ? "it holds a bidirectional formatting character (it would show reordered)"
                  : long_name         ? "it is longer than 200 bytes"
                  : !utf8             ? "it is not valid UTF-8"
                                      : "a run's own file has that name");
        return -1;
    }
    return 0;
}

int catalog_load(const char *const *names, int n, const char *const *reserved, struct scene *scenes, int max,
                 int *count)
{
    char **paths = NULL;
    *count = 0;
    if (n == 0) {
        n = catalog_shipped(&paths);
        if (n <= 0) {
            if (n == 0)
                log_error("no shipped scenes found");
            return -1;
        }
    } else {
        paths = xcalloc((size_t)n, sizeof *paths);
        for (int i = 0; i < n; i++)
            if (!(paths[i] = catalog_resolve(names[i]))) {
                catalog_free(paths, n);
                return -1;
            }
    }
    int rc = 0;
    if (n > max) {
        log_error("%d scenes: at most %d in one command", n, max);
        rc = -1;
    }
    for (int i = 0; i < n && !rc; i++) {
        rc = scene_load(paths[i], &scenes[i]);
        if (!rc)
            (*count)++;
        struct light_frustum f;
        if (!rc && (catalog_check_name(&scenes[i], reserved) != 0 || light_frustum_fit(&scenes[i], 1.0f, &f) != 0))
            rc = -1;
        if (rc)
            continue;
        /* Outputs go to <out>/<scene name>: two scenes may not share one. */
        for (int j = 0; j < i && !rc; j++)
            if (strcmp(scenes[j].name, scenes[i].name) == 0) {
                log_error("%s: its name '%s' is taken by %s (outputs are per scene name)",
                          scenes[i].path, scenes[i].name, scenes[j].path);
                rc = -1;
            }
    }
    catalog_free(paths, n);
    return rc;
}
