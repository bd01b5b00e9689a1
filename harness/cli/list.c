/* shadowbench list: every technique with its parameters, every shipped
 * scene with what it shows. */
#include "cli.h"
#include "scene/catalog.h"
#include "techniques/params.h"

#include <stdio.h>

int list_main(const struct options *o)
{
    (void)o;
    printf("techniques (set a parameter with --set <technique>.<parameter>=<value>):\n\n");
    for (const struct technique *const *t = technique_list; *t; t++) {
        printf("  %-10s %s\n", (*t)->name, (*t)->summary);
        params_print(*t, stdout);
        printf("\n");
    }
    char **paths;
    int n = catalog_shipped(&paths);
    if (n < 0)
        return EXIT_CHECK_FAILED;
    printf("scenes (use with --scene <name>):\n\n");
    int status = EXIT_OK;
    for (int i = 0; i < n; i++) {
        struct scene s;
        if (scene_load(paths[i], &s) != 0) {
            status = EXIT_CHECK_FAILED;
            continue;
        }
        printf("  %s\n    %s\n    shows: %s\n    %zu triangles, %s light\n\n", s.name, s.description,
               *s.shows ? s.shows : "-", s.triangle_count, light_shape_names[s.light.shape]);
        scene_free(&s);
    }
    catalog_free(paths, n);
    return status;
}
