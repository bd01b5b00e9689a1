/* Every technique the harness knows. Adding one: techniques/<name>.c,
 * shaders/<name>.glsl, and one line in each list below. */
#include "technique.h"

#include <string.h>

extern const struct technique technique_hard;
extern const struct technique technique_pcf;
extern const struct technique technique_pcss;
extern const struct technique technique_vsm;
extern const struct technique technique_savsm;
extern const struct technique technique_pcss_savsm;

const struct technique *const technique_list[] = {
    &technique_hard,
    &technique_pcf,
    &technique_pcss,
    &technique_vsm,
    &technique_savsm,
    &technique_pcss_savsm,
    NULL,
};

const char *const sat_format_names[] = {
#define X(id, name) name,
    SAT_FORMATS(X)
#undef X
    NULL,
};

const struct technique *technique_find(const char *name)
{
    for (const struct technique *const *t = technique_list; *t; t++)
        if (strcmp((*t)->name, name) == 0)
            return *t;
    return NULL;
}

void technique_request(const struct technique *t, const void *settings,
                       const struct light_frustum *f, int map_size_texels,
                       struct shadowmap_request *r)
{
    memset(r, 0, sizeof *r);
    r->products = t->needs;
    if (t->request)
        t->request(settings, f, map_size_texels, r);
    r->products |= SM_DEPTH;
}
