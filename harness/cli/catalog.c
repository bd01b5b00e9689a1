#include "catalog.h"
#include "base/log.h"
#include "base/util.h"

#include <dirent.h>
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
