/* Every technique the harness knows. Adding one: techniques/<name>.c,
 * shaders/<name>.glsl, and one line in each list below. */
#include "technique.h"

#include <string.h>

extern const struct technique technique_hard;

const struct technique *const technique_list[] = {
    &technique_hard,
    NULL,
};

const struct technique *technique_find(const char *name)
{
    for (const struct technique *const *t = technique_list; *t; t++)
        if (strcmp((*t)->name, name) == 0)
            return *t;
    return NULL;
}
