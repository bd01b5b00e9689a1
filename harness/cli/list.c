/* shadowbench list: every technique with its parameters, every shipped
 * scene with what it shows. */
#include "cli.h"
#include "scene/catalog.h"
#include "techniques/params.h"

#include <math.h>
#include <stdio.h>

int list_main(const struct options *o)
{
    (void)o;
    printf("techniques (set a parameter with --set <technique>.<parameter>=<value>):\n\n");
    for (const struct technique *const *t = technique_list; *t; t++) {
        printf("  %-10s %s\n", (*t)->name, (*t)->summary);
        if (technique_is_engine(*t))  /* docs/engines.md */
            printf("    engine cell: rendered by npm %s in headless Chromium (engines/%s/; run only when named: "
                   "--technique %s, or engines)\n", (*t)->engine_package, (*t)->engine, (*t)->engine);
        if (technique_is_preset(*t))  /* docs/presets.md */
            printf("    preset: %s's shipped filter, following %s (techniques/ header: what was confirmed, what "
                   "is approximated); run only when named: --technique %s, or presets\n", (*t)->preset_of,
                   (*t)->preset_source, (*t)->preset_of);
        params_print(*t, stdout);
        for (const struct technique_preset *p = (*t)->presets; p && p->name; p++)
            printf("%s    %s@%-22s %s\n      = %s\n", p == (*t)->presets ? "    presets (cells of the default run):\n" : "",
                   (*t)->name, p->name, p->summary, p->params);
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
        char sun[64] = "";
        if (s.light.shape == LIGHT_SUN)
            snprintf(sun, sizeof sun, ", %.3g degrees across", 2 * s.light.half_angle * 180 / M_PI);
        printf("  %s\n    %s\n    shows: %s\n    %zu triangles, %s light%s\n\n", s.name, s.description,
               *s.shows ? s.shows : "-", s.triangle_count, light_shape_names[s.light.shape], sun);
        scene_free(&s);
    }
    catalog_free(paths, n);
    return status;
}
