/* The technique interface. A technique is techniques/<name>.c (a parameter
 * table and one const descriptor) plus shaders/<name>.glsl (one function,
 * float shadow_visibility(ShadowInput s)). The harness reaches techniques
 * only through registry.c; it parses, range-checks and records parameters
 * from the table, and each parameter reaches the shader as a #define named
 * <TECHNIQUE>_<PARAM> (e.g. HARD_CONSTANT_BIAS). */
#ifndef SB_TECHNIQUE_H
#define SB_TECHNIQUE_H

#include <math.h>
#include <stdbool.h>
#include <stddef.h>

/* Shadow-map products (docs/design.md §1, §5): X(ID, name). Each is a row of the
 * shared layer's table (techniques/shadowmap.c: its storage, its sampler,
 * its passes; bindings and GLSL declarations follow from the row) plus its
 * shaders. For scoring, the layer renders each requested product once per
 * light pose and set of options, shared by the cells that agree; a timed
 * frame renders its cell's products afresh. Every product is derived from
 * the depth pass, which is always rendered: the depth pass is timed as
 * ms_shadowmap, every other product as ms_filter_prep. */
#define SM_PRODUCTS(X)                                                                  \
    X(DEPTH, "depth")             /* hardware depth, D32F, reversed Z */                \
    X(MOMENTS, "moments")         /* linear depth d and d², RG32F, filtered, mipmapped */ \
    X(MOMENTS_SAT, "moments_sat") /* summed-area table of (d, d²), storage buffer */        \
    X(EVSM, "evsm")               /* warped moments (e^{c+ w}, e^{2c+ w}, -e^{-c- w}, e^{-2c- w}) of \
                                     w = 2d - 1, RGBA32F, filtered, mipmapped */             \
    X(MSM, "msm")                 /* four moments (w, w², w³, w⁴) of w = 2d - 1, RGBA32F,      \
                                     filtered, mipmapped */                                  \
    X(MSM_SAT, "msm_sat")         /* summed-area table of (w, w², w³, w⁴), storage buffer */

enum {
#define X(id, name) SM_PRODUCT_##id,
    SM_PRODUCTS(X)
#undef X
    SM_PRODUCT_COUNT
};

/* A product as a request flag: SM_DEPTH, SM_MOMENTS, ... */
enum shadowmap_product_flag {
#define X(id, name) SM_##id = 1u << SM_PRODUCT_##id,
    SM_PRODUCTS(X)
#undef X
};

/* Precision of a summed-area table (the `sat_format` parameter): X(ID,
 * name). GLSL sees SM_SAT_<ID>. */
#define SAT_FORMATS(X)                                                                   \
    X(FP32, "fp32")                   /* plain float sums of the moments */               \
    X(FP32_CENTERED, "fp32_centered") /* moments_sat only: float sums of d - 0.5,         \
                                         (d - 0.5)²: smaller sums (msm_sat's w is centred) */ \
    X(INT32, "int32")                 /* fixed point in uint32, exact differences by wrap */

enum sat_format {
#define X(id, name) SAT_##id,
    SAT_FORMATS(X)
#undef X
};

/* Their parameter spellings, by enum value, NULL-terminated. */
extern const char *const sat_format_names[];

/* Tap layouts of the PCF family's loops (the `pattern` parameter): X(ID,
 * name). Each is a set over the light's shape: [-1, 1]^2 for a rect light,
 * the unit disk for a disk light and the sun, one mapped onto the other by
 * Shirley and Chiu's concentric map, which keeps area (shadow_taps.glsl).
 * GLSL sees SM_PATTERN_<ID>. */
#define TAP_PATTERNS(X)                                                                  \
    X(POISSON, "poisson") /* progressive best-candidate set (tools/sample_patterns.c) */ \
    X(GRID, "grid")       /* n x n cell centres of the square (seed 003's 7 x 7) */      \
    X(VOGEL, "vogel")     /* golden-angle spiral in the disk (Vogel 1979) */              \
    X(UNIFORM_DISK, "uniform_disk") /* independent uniform points in the disk (seed 002's \
                                       GAMES202 uniformDiskSamples): no spreading */

enum tap_pattern {
#define X(id, name) TAP_PATTERN_##id,
    TAP_PATTERNS(X)
#undef X
};

/* Per-pixel noise that rotates (disk) or shifts (square) a pattern (the
 * `rotation` parameter): X(ID, name). GLSL sees SM_ROTATION_<ID>. */
#define TAP_ROTATIONS(X)                                                                 \
    X(NONE, "none")       /* the same taps at every pixel: banding */                    \
    X(HASH, "hash")       /* white noise, an integer hash of the pixel (and frame) */    \
    X(IGN, "ign")         /* interleaved gradient noise (Jimenez 2014) of the pixel */   \
    X(IGN_2X2, "ign_2x2") /* the same of its 2 x 2 block: one rotation a block (seed 003) */ \
    X(BLUE_NOISE, "blue_noise") /* a tileable void-and-cluster texture (tools/blue_noise.c) */

enum tap_rotation {
#define X(id, name) TAP_ROTATION_##id,
    TAP_ROTATIONS(X)
#undef X
};

/* The blue-noise texture's side, pixels: shaders/blue_noise.png holds a
 * tile a channel, stacked (tools/blue_noise.c). */
#define TAP_BLUE_NOISE_SIDE 64

/* Their parameter spellings, by enum value, NULL-terminated. */
extern const char *const tap_pattern_names[];
extern const char *const tap_rotation_names[];
/* An engine cell's shadow_side: double (both faces drawn into the map,
 * shadowbench's own choice), engine (the engine's default culling). */
extern const char *const engine_side_names[];

/* The moments product's widest Gaussian prefilter (GLSL: SM_MAX_BLUR_RADIUS). */
#define SM_MAX_BLUR_RADIUS_TEXELS 32

/* The largest exponent of the evsm product's warps:
 * its second moment e^{2c w} reaches e^{2c} at w = 1, and fp32 holds up to
 * e^{88.72} (FLT_MAX), so c < 44.36; 42 leaves the filter's rounding room.
 * The product refuses a larger one (the parameters' ranges stop there). */
#define SM_EVSM_MAX_EXPONENT 42.0f

/* The bias per fixed-point step that keeps the Hankel matrix of an int32
 * msm_sat box's rounded moments positive definite (msm_quantisation_bias
 * in shaders/msm_common.glsl derives it: sufficient from 7.094 on, taken
 * just above). GLSL sees SM_MSM_QUANTISATION_FACTOR. */
#define SM_MSM_QUANTISATION_FACTOR 7.1

/* What one technique asks of the shared layer: products and their options,
 * a block per product that has any. Two cells whose requests agree on a
 * product share it; a different option (another blur radius) re-renders it.
 * Zero means default. */
struct shadowmap_request {
    unsigned products;  /* SM_* flags */
    struct {
        int blur_radius_texels;  /* separable Gaussian, sigma = radius / 2, [0, SM_MAX_BLUR_RADIUS_TEXELS]; 0 = none */
    } moments;
    struct sat_request {
        enum sat_format format;
        float max_box_texels;    /* SAT_INT32: widest box side the technique reads; sets the
                                    fixed-point scale so that no box sum overflows */
    } moments_sat, msm_sat;      /* each its own slot of the block: both may be in one request */
    struct {
        float positive, negative;  /* the warps' exponents c+, c-, (0, SM_EVSM_MAX_EXPONENT] */
        int blur_radius_texels;    /* as the moments' */
    } evsm;
    struct {
        int blur_radius_texels;    /* as the moments' */
    } msm;
};

/* The tap counts a tap-based technique may use (PARAM_TAPS). The parameter
 * choices, the shaders' SM_UNROLL_<n> expansions and the length of the
 * sample tables (tools/sample_patterns.c) all come from this list. */
#define TAP_COUNTS(X) X(16) X(25) X(32) X(49) X(64) X(100) X(128)

/* The largest of them: the size of a union of one array per count. */
union tap_count_max {
#define X(n) char taps_##n[n];
    TAP_COUNTS(X)
#undef X
};
#define TAP_COUNT_MAX ((int)sizeof(union tap_count_max))

/* The list as data, in its order (techniques/params.c). */
enum {
    TAP_COUNT_KINDS = 0
#define X(n) + 1
    TAP_COUNTS(X)
#undef X
};
extern const int tap_counts[TAP_COUNT_KINDS];

struct light_frustum;  /* scene/light_frustum.h */

enum param_type {
    PARAM_FLOAT,  /* member is a float */
    PARAM_INT,    /* member is an int in [min, max] */
    PARAM_BOOL,   /* member is an int, 0 or 1; given as true/false/1/0 */
    PARAM_ENUM,   /* member is an int, the index into choices */
    PARAM_TAPS,   /* member is an int, one of TAP_COUNTS: the taps of one loop of depth-map
                     fetches (`bench` measures the fetch limit from these) */
};

struct technique_param {
    const char *name;             /* as in --set <technique>.<name>=<value> */
    const char *help;             /* one line: meaning and unit */
    size_t offset;                /* of the member in the settings struct */
    enum param_type type;
    double def;                   /* PARAM_ENUM: an index into choices */
    double min, max;              /* PARAM_FLOAT and PARAM_INT only; the others take their
                                     values from a list (bool: 0 and 1) */
    const char *const *choices;   /* PARAM_ENUM only: NULL-terminated names */
    const double *tune;           /* the values `tune` explores, ending with NAN (PARAM_ENUM:
                                     indices); TUNE_CHOICES: every choice (bool, enum, taps);
                                     NULL: not tuned, kept at its default */
};

/* A parameter's tune values: .tune = TUNE(1, 2, 4). */
#define TUNE(...) ((const double[]){__VA_ARGS__, NAN})
extern const double TUNE_CHOICES[];

/* The regression cells a technique declares on one shipped scene (STYLE.md
 * item 6d): each its parameters away from their defaults, on a scene where
 * they act. `shadowbench check` renders each against its baseline, and
 * fails when a parameter is set away from its default by none of its
 * technique's cells, or when setting one back changes no pixel
 * (pipeline/regression.h). */
#define TECHNIQUE_CELLS_PER_SCENE 8
struct technique_cell {
    const char *scene;  /* a shipped scene's name */
    const char *params[TECHNIQUE_CELLS_PER_SCENE];  /* as a cell's name spells them
                                                       ("pattern=grid,samples=25"); NULL ends */
};

/* A named setting a technique ships with (e.g. seed 003's steps as
 * pcss@grid7x7 ... pcss@seed003): a cell of the default run and of the
 * check on every scene, named <technique>@<name>. */
struct technique_preset {
    const char *name;     /* after the '@': not a parameter=value list, not "tuned" */
    const char *params;   /* its parameters away from the defaults, as a cell's name spells them */
    const char *summary;  /* one line: what it is, for list and the report */
};

/* What a request is made for: the scene's light frustum and the map's size. */
struct request_context {
    const struct light_frustum *frustum;
    int map_size_texels;
};

struct technique {
    const char *name;
    const char *summary;                   /* one line for `list` */
    unsigned needs;                        /* SM_* products it samples */
    const struct technique_param *params;  /* ends with { .name = NULL } */
    size_t settings_size;                  /* of the struct the params point into */
    const char *shader;                    /* in shaders/, defines shadow_visibility; NULL for an engine */
    /* An engine cell's (docs/engines.md): the adapter in engines/<engine>/
     * that renders it with a real engine's own shadow code, which takes
     * the technique's name and parameters as that engine's settings; its
     * version as the adapter pins it. NULL for shadowbench's own. */
    const char *engine;
    const char *engine_package;            /* the npm package, for list and the docs */
    /* A preset's (docs/presets.md): shadowbench's own shader, re-implementing
     * the filter an engine ships, as that engine sets it; its file's header
     * says what was confirmed against the engine's source and what is
     * approximated. preset_of: the engine's short name (a --technique
     * group: hdrp, godot, bevy, filament, ue); preset_source: the public
     * source it follows, repository, version and file. NULL for the rest. */
    const char *preset_of;
    const char *preset_source;

    /* Optional. The request for these settings; without it, .needs with
     * default options. */
    void (*request)(const void *settings, const struct request_context *c, struct shadowmap_request *r);
    /* Optional. Rules across parameters that a range cannot state: returns
     * 0, or -1 with a one-line reason in why. */
    int (*check)(const void *settings, char *why, size_t why_size);
    /* Its regression cells, scene by scene, ending with {NULL}. */
    const struct technique_cell *regression;
    /* Optional: its presets, ending with {NULL}. */
    const struct technique_preset *presets;
    /* Optional: the relative disagreement between its camera distance and
     * the ray tracer's above which the scored mask calls a pixel a
     * silhouette mismatch, where its renderer measurably cannot meet the
     * harness's (0: METRICS_DEPTH_TOLERANCE, metrics_depth_tolerance in
     * score/metrics.h); it applies off the truth's silhouettes only. State
     * the measurement next to the value. */
    float depth_tolerance;
};

/* t's preset called name, or NULL. */
const struct technique_preset *technique_preset_find(const struct technique *t, const char *name);

/* The descriptor that ends techniques/<name>.c: its name, its parameter
 * table <name>_params, its settings struct <name>_settings and its shader
 * shaders/<name>.glsl all follow from the name, written once; the rest are
 * named fields: TECHNIQUE(pcf, .needs = SM_DEPTH, .summary = "...", ...). */
#define TECHNIQUE(name_, ...)                                                                     \
    const struct technique technique_##name_ = {.name = #name_, .params = name_##_params,         \
                                                .settings_size = sizeof(struct name_##_settings), \
                                                .shader = #name_ ".glsl", __VA_ARGS__}

/* An engine cell's descriptor: techniques/<engine>.c holds one per mode,
 * ENGINE_TECHNIQUE(three_pcf, three, "three", .summary = "..."): its
 * parameter table and settings struct follow from the name; no shader. */
#define ENGINE_TECHNIQUE(name_, engine_, package_, ...)                                          \
    const struct technique technique_##name_ = {.name = #name_, .params = name_##_params,         \
                                                .settings_size = sizeof(struct name_##_settings), \
                                                .engine = #engine_, .engine_package = package_,   \
                                                __VA_ARGS__}

static inline bool technique_is_engine(const struct technique *t) { return t->engine != NULL; }
static inline bool technique_is_preset(const struct technique *t) { return t->preset_of != NULL; }
/* Run only when named (--technique): engine cells and presets. */
static inline bool technique_named_only(const struct technique *t)
{
    return technique_is_engine(t) || technique_is_preset(t);
}

/* t's request for these settings (calls t->request, or uses t->needs). */
void technique_request(const struct technique *t, const void *settings, const struct request_context *c,
                       struct shadowmap_request *r);

/* The SAT request of a technique whose widest box is its blocker search
 * (pcss_savsm, vssm, msm_soft): format, and the search box at the far
 * plane as the widest box read, which sets int32's fixed-point scale. */
void sat_request_search_box(struct sat_request *r, int format, float light_size_scale,
                            const struct request_context *c);

/* NULL-terminated, in registry order. */
extern const struct technique *const technique_list[];

/* The technique called name, or NULL. */
const struct technique *technique_find(const char *name);

/* t's index in technique_list: what settings are kept by, a technique's
 * colour in every chart. */
int technique_index(const struct technique *t);

/* Whether t is among list[0..n-1] (a selection of techniques). */
bool technique_in(const struct technique *const *list, int n, const struct technique *t);

/* The most techniques the registry holds: the size of every array kept
 * per technique_list index (registry.c asserts it). */
#define TECHNIQUE_COUNT_MAX 64

/* The most techniques one selection holds (--technique; the study's, the
 * viewer's lists): all of them. */
#define TECHNIQUE_SELECTION_MAX TECHNIQUE_COUNT_MAX

struct strbuf;  /* base/util.h */

/* Appends every technique's name, in registry order, separated by sep. */
void technique_names(struct strbuf *out, const char *sep);

#endif
