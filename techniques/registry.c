/* Every technique the harness knows, in the order `list` and the matrix
 * show them. Adding one: techniques/<name>.c (ending in its descriptor,
 * TECHNIQUE(<name>, ...)), shaders/<name>.glsl, and X(<name>) here; an
 * engine's mode: its ENGINE_TECHNIQUE in techniques/<engine>.c, its
 * handling in engines/<engine>/adapter.js, and X(<name>) in ENGINES; a
 * preset: its TECHNIQUE in techniques/<engine>.c with .preset_of and
 * .preset_source, its shader, and X(<name>) in PRESETS. */
#include "technique.h"
#include "base/util.h"
#include "scene/light_frustum.h"

#include <string.h>

#define TECHNIQUES(X) X(hard) X(pcf) X(pcss) X(vsm) X(savsm) X(pcss_savsm) X(evsm) X(msm) X(msm_soft) X(vssm) \
    PRESETS(X) ENGINES(X)
/* Presets (docs/presets.md): shadowbench's shaders of the filters engines
 * ship, one file per engine (techniques/<engine>.c; Filament's
 * filament_presets.c, beside its engine cell's), run only when named. */
#define PRESETS(X)                                                        \
    X(bevy_gaussian) X(bevy_temporal) X(bevy_pcss)                        \
    X(filament_pcf_glsl) X(filament_dpcf_glsl) X(filament_pcss_glsl)     \
    X(godot_pcf) X(godot_pcss) X(hdrp_pcf) X(hdrp_pcss) X(ue_smrt)
/* Engine cells (docs/engines.md), after shadowbench's own: one file per
 * engine (techniques/<engine>.c), one descriptor per mode. */
#define ENGINES(X)                                                                                \
    X(three_basic) X(three_pcf) X(three_vsm)                                                      \
    X(babylon_hard) X(babylon_poisson) X(babylon_pcf) X(babylon_pcss)                             \
    X(playcanvas_pcf1) X(playcanvas_pcf3) X(playcanvas_pcf5) X(playcanvas_vsm) X(playcanvas_pcss) \
    X(filament_pcf)

#define X(name) extern const struct technique technique_##name;
TECHNIQUES(X)
#undef X

const struct technique *const technique_list[] = {
#define X(name) &technique_##name,
    TECHNIQUES(X)
#undef X
    NULL,
};

_Static_assert(sizeof technique_list / sizeof technique_list[0] - 1 <= TECHNIQUE_COUNT_MAX,
               "more techniques than arrays kept per technique hold: raise TECHNIQUE_COUNT_MAX");

const char *const sat_format_names[] = {
#define X(id, name) name,
    SAT_FORMATS(X)
#undef X
    NULL,
};

const char *const tap_pattern_names[] = {
#define X(id, name) name,
    TAP_PATTERNS(X)
#undef X
    NULL,
};

const char *const tap_rotation_names[] = {
#define X(id, name) name,
    TAP_ROTATIONS(X)
#undef X
    NULL,
};

const char *const engine_side_names[] = {"double", "engine", NULL};

const struct technique *technique_find(const char *name)
{
    for (const struct technique *const *t = technique_list; *t; t++)
        if (strcmp((*t)->name, name) == 0)
            return *t;
    return NULL;
}

int technique_index(const struct technique *t)
{
    int i = 0;
    while (technique_list[i] && technique_list[i] != t)
        i++;
    return i;
}

bool technique_in(const struct technique *const *list, int n, const struct technique *t)
{
    for (int i = 0; i < n; i++)
        if (list[i] == t)
            return true;
    return false;
}

void technique_names(struct strbuf *out, const char *sep)
{
    for (const struct technique *const *t = technique_list; *t; t++)
        strbuf_list_printf(out, sep, "%s", (*t)->name);
}

void technique_request(const struct technique *t, const void *settings, const struct request_context *c,
                       struct shadowmap_request *r)
{
    memset(r, 0, sizeof *r);
    r->products = t->needs;
    if (t->request)
        t->request(settings, c, r);
    r->products |= SM_DEPTH;
}

void sat_request_search_box(struct sat_request *r, int format, float light_size_scale,
                            const struct request_context *c)
{
    r->format = (enum sat_format)format;
    r->max_box_texels = light_frustum_search_box_texels(c->frustum, light_size_scale, c->map_size_texels);
}

const struct technique_preset *technique_preset_find(const struct technique *t, const char *name)
{
    for (const struct technique_preset *p = t->presets; p && p->name; p++)
        if (strcmp(p->name, name) == 0)
            return p;
    return NULL;
}
