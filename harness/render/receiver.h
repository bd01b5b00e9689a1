/* The receiver pass: the scene from the camera, each pixel calling a
 * technique's shadow_visibility(); writes V_tech (R32F) and the camera
 * distance (R32F) used for the ground truth's mismatch mask. */
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

struct receiver {
    int width, height;
    GLuint fbo, visibility, distance, depth;
    struct mat4 view_proj;  /* camera: reversed Z, infinite far */
    struct vec3 camera_pos;
    struct vec3 camera_fwd; /* view depth is along it */
    float noise_frame;      /* the frame index tap noise is animated by (sm_noise_frame); 0: still */
};

int receiver_create(struct receiver *r, const struct scene *s, int width, int height);

/* Points the receiver's camera at s's camera (a scene in another pose). */
void receiver_set_camera(struct receiver *r, const struct scene *s);

/* Whether program reads the frame index (its technique's noise can be
 * animated); a program that does not is the same every frame. */
bool receiver_program_animated(GLuint program);

/* The receiver program for technique t with these settings (its parameters
 * become #defines) and a light of this shape (SM_LIGHT_SHAPE: the PCSS
 * family's tap pattern follows it). Returns 0 on failure (logged). */
GLuint receiver_program(const struct technique *t, const void *settings, enum light_shape shape);

/* Renders V_tech: with one map, one pass; with cascades, one pass per
 * cascade with its map bound, each adding w_c V_c where its weight w_c (its
 * slice, faded over the blend band) is not 0, and the first adding 1 - the
 * sum of the weights (lit past the shadow distance). A pass runs the
 * technique only where its weight is not 0. */
void receiver_render(const struct receiver *r, GLuint program, const struct scene_mesh *mesh,
                     const struct shadow_cascades *c);

/* Reads back both targets, top row first; distance is -1 where no geometry. */
void receiver_read(const struct receiver *r, float *visibility, float *distance);

void receiver_destroy(struct receiver *r);

#endif
