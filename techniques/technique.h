/* The technique interface. A technique is techniques/<name>.c (a parameter
 * table and one const descriptor) plus shaders/<name>.glsl (one function,
 * float shadow_visibility(ShadowInput s)). The harness reaches techniques
 * only through registry.c; it parses, range-checks and records parameters
 * from the table, and each parameter reaches the shader as a #define named
 * <TECHNIQUE>_<PARAM> (e.g. HARD_CONSTANT_BIAS). */
#ifndef SB_TECHNIQUE_H
#define SB_TECHNIQUE_H

#include <stddef.h>

/* Shadow-map products (DESIGN.md §1, §5), requested by flags. The shared
 * layer renders each requested product once per light pose. */
enum shadowmap_product {
    SM_DEPTH = 1u << 0,        /* hardware depth, D32F, reversed Z */
    SM_MOMENTS = 1u << 1,      /* linear depth d and d², RG32F (next issue) */
    SM_MOMENTS_SAT = 1u << 2,  /* summed-area table of the moments (next issue) */
};

enum param_type {
    PARAM_FLOAT,  /* member is a float */
    PARAM_INT,    /* member is an int */
    PARAM_BOOL,   /* member is an int, 0 or 1; given as true/false/1/0 */
    PARAM_ENUM,   /* member is an int, the index into choices */
};

struct technique_param {
    const char *name;             /* as in --set <technique>.<name>=<value> */
    const char *help;             /* one line: meaning and unit */
    size_t offset;                /* of the member in the settings struct */
    enum param_type type;
    double def, min, max;         /* PARAM_ENUM: indices into choices */
    const char *const *choices;   /* PARAM_ENUM: NULL-terminated names */
};

struct technique {
    const char *name;
    const char *summary;                   /* one line for `list` */
    unsigned needs;                        /* SM_* products it samples */
    const struct technique_param *params;  /* ends with { .name = NULL } */
    size_t settings_size;                  /* of the struct the params point into */
    const char *shader;                    /* in shaders/, defines shadow_visibility */
};

/* NULL-terminated, in registry order. */
extern const struct technique *const technique_list[];

/* The technique called name, or NULL. */
const struct technique *technique_find(const char *name);

#endif
