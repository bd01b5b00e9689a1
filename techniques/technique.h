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
 * layer renders each requested product once per light pose. Every product
 * is derived from the depth pass, which is always rendered. */
enum shadowmap_product {
    SM_DEPTH = 1u << 0,        /* hardware depth, D32F, reversed Z */
    SM_MOMENTS = 1u << 1,      /* linear depth d and d², RG32F, prefiltered, mipmapped */
    SM_MOMENTS_SAT = 1u << 2,  /* summed-area table of (d, d²), storage buffer */
};

/* Precision of the summed-area table (the `sat_format` parameter). */
enum sat_format {
    SAT_FP32,           /* plain float sums of d, d² */
    SAT_FP32_CENTERED,  /* float sums of d - 0.5, (d - 0.5)²: smaller sums */
    SAT_INT32,          /* fixed point in uint32, exact differences by wrap-around */
};

/* Their parameter spellings, by enum value, NULL-terminated. */
extern const char *const sat_format_names[];

/* What one technique asks of the shared layer: products and their options.
 * Two cells with equal requests share the products; a different request
 * (e.g. another blur radius) re-renders them. Zero means default. */
struct shadowmap_request {
    unsigned products;             /* SM_* flags */
    int moments_blur_radius_texels;/* SM_MOMENTS: separable Gaussian, sigma = radius / 2; 0 = none */
    enum sat_format sat_format;    /* SM_MOMENTS_SAT */
    float sat_max_box_texels;      /* SM_MOMENTS_SAT, SAT_INT32: widest box side the technique
                                      reads; sets the fixed-point scale so no box sum overflows */
};

struct light_frustum;  /* scene/light_frustum.h */

enum param_type {
    PARAM_FLOAT,  /* member is a float */
    PARAM_INT,    /* member is an int; with choices, one of those numbers */
    PARAM_BOOL,   /* member is an int, 0 or 1; given as true/false/1/0 */
    PARAM_ENUM,   /* member is an int, the index into choices */
};

struct technique_param {
    const char *name;             /* as in --set <technique>.<name>=<value> */
    const char *help;             /* one line: meaning and unit */
    size_t offset;                /* of the member in the settings struct */
    enum param_type type;
    double def, min, max;         /* PARAM_ENUM: indices into choices */
    const char *const *choices;   /* PARAM_ENUM: NULL-terminated names; PARAM_INT: the
                                     allowed values as text, or NULL for any in range */
};

struct technique {
    const char *name;
    const char *summary;                   /* one line for `list` */
    unsigned needs;                        /* SM_* products it samples */
    const struct technique_param *params;  /* ends with { .name = NULL } */
    size_t settings_size;                  /* of the struct the params point into */
    const char *shader;                    /* in shaders/, defines shadow_visibility */

    /* Optional. The request for these settings; without it, .needs with
     * default options. f is the scene's light frustum. */
    void (*request)(const void *settings, const struct light_frustum *f, int map_size_texels,
                    struct shadowmap_request *r);
    /* Optional. Rules across parameters that a range cannot state: returns
     * 0, or -1 with a one-line reason in why. */
    int (*check)(const void *settings, char *why, size_t why_size);
};

/* t's request for these settings (calls t->request, or uses t->needs). */
void technique_request(const struct technique *t, const void *settings,
                       const struct light_frustum *f, int map_size_texels,
                       struct shadowmap_request *r);

/* NULL-terminated, in registry order. */
extern const struct technique *const technique_list[];

/* The technique called name, or NULL. */
const struct technique *technique_find(const char *name);

#endif
