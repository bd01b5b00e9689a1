/* The receiver pass: the scene from the camera, each pixel calling a
 * technique's shadow_visibility(); writes V_tech (R32F) and the camera
 * distance (R32F) used for the ground truth's mismatch mask. Around it, the
 * screen-space stages a technique declares (docs/design.md §2,
 * docs/techniques.md): a penumbra mask before it, a denoiser after it.
 * Each program has a counting variant (docs/metrics.md), rendered to
 * score a cell and never timed, whose receiver pass also writes each
 * pixel's shadow-map fetches and whether the full filter ran. */
#ifndef SB_RECEIVER_H
#define SB_RECEIVER_H

#include "gl/gl.h"
#include "gl/scene_mesh.h"
#include "scene/scene.h"
#include "techniques/cascades.h"
#include "techniques/technique.h"

#include <stdbool.h>

/* The image sizes the receiver renders (and every command takes: --width,
 * --height; a baseline records one), in pixels. */
#define RECEIVER_MIN_SIZE 16
#define RECEIVER_MAX_SIZE 8192

/* The penumbra mask's blocks: pixels on a side. */
#define RECEIVER_MASK_BLOCK 4

/* The screen-space stages a cell's settings declare: read from the
 * parameters of these names (techniques/param_rows.h) where its technique
 * has them. */
struct receiver_stages {
    bool penumbra_mask;        /* the mask's pre-pass, then the receiver pass reads it */
    int mask_dilate_blocks;
    float mask_dilate_world;   /* 0: off; else a radius in world units, blocks at each block's distance */
    int denoise_radius_px;     /* the bilateral denoiser's; 0: none */
    float denoise_sigma_world;
    float denoise_normal_power; /* 0: position only */
};

void receiver_stages_of(const struct technique *t, const void *settings, struct receiver_stages *out);

/* A cell's programs. */
struct receiver_programs {
    GLuint receiver;  /* 0: none (a compile error, logged) */
    GLuint mask;      /* the penumbra mask's pre-pass, or 0 */
    struct receiver_stages stages;
};

/* What a counting render measured (docs/metrics.md's cost metrics). */
struct receiver_cost {
    double fetches;         /* shadow-map fetches of the frame: receiver pass and mask */
    long covered;           /* pixels with geometry */
    long expensive;         /* covered pixels that ran the technique's full filter */
};

struct receiver {
    int width, height;
    GLuint fbo, visibility, distance, depth;
    GLuint cost;            /* RGBA32F: a counting pass's fetches, full filters, shortcuts */
    struct receiver_screen *screen;  /* the stages' targets and passes, made on first use */
    struct mat4 view_proj;  /* camera: reversed Z, infinite far */
    struct vec3 camera_pos;
    struct vec3 camera_fwd; /* view depth is along it */
    struct vec3 ray_right, ray_up;  /* a pixel's ray: camera_fwd + x ray_right + y ray_up, x, y in [-1, 1] */
    float noise_frame;      /* the frame index tap noise is animated by (sm_noise_frame); 0: still */
};

int receiver_create(struct receiver *r, const struct scene *s, int width, int height);

/* Points the receiver's camera at s's camera (a scene in another pose). */
void receiver_set_camera(struct receiver *r, const struct scene *s);

/* Whether program reads the frame index (its technique's noise can be
 * animated); a program that does not is the same every frame. */
bool receiver_program_animated(GLuint program);

/* The programs of technique t with these settings (its parameters become
 * #defines) and a light of this shape (SM_LIGHT_SHAPE: the PCSS family's
 * tap pattern follows it); counting: the counting variants. On failure
 * (logged) out->receiver is 0. */
void receiver_programs_make(const struct technique *t, const void *settings, enum light_shape shape, bool counting,
                            struct receiver_programs *out);

void receiver_programs_delete(struct receiver_programs *p);

/* Makes the targets and passes p's stages need (once). Returns 0 or -1
 * (logged). */
int receiver_prepare(struct receiver *r, const struct receiver_programs *p);

/* The penumbra mask's pre-pass and its dilation, a mask layer per cascade
 * (nothing without a mask). counting: p is counting, and the pass's fetches
 * are kept for receiver_read_cost. */
void receiver_render_mask(const struct receiver *r, const struct receiver_programs *p, const struct scene_mesh *mesh,
                          const struct shadow_cascades *c, bool counting);

/* Renders V_tech: with one map, one pass; with cascades, one pass per
 * cascade with its map bound, each adding w_c V_c where its weight w_c (its
 * slice, faded over the blend band) is not 0, and the first adding 1 - the
 * sum of the weights (lit past the shadow distance). A pass runs the
 * technique only where its weight is not 0. counting: p is counting, and
 * the pass writes the cost target too. */
void receiver_render(const struct receiver *r, const struct receiver_programs *p, const struct scene_mesh *mesh,
                     const struct shadow_cascades *c, bool counting);

/* The denoiser's two passes over V_tech (nothing without one). */
void receiver_render_denoise(const struct receiver *r, const struct receiver_programs *p);

/* Reads back both targets, top row first; distance is -1 where no geometry. */
void receiver_read(const struct receiver *r, float *visibility, float *distance);

/* After a counting frame: its totals, and per pixel (top row first) 1
 * where an early-out or the mask decided the pixel without the full
 * filter, else 0 (shortcut, may be NULL). */
void receiver_read_cost(const struct receiver *r, struct receiver_cost *out, float *shortcut);

void receiver_destroy(struct receiver *r);

#endif
