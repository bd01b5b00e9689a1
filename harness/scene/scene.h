/* A scene as the harness sees it (docs/design.md §4): world-space triangles, one
 * perspective camera, one light (an area light or the sun). Loaded from glTF by scene_gltf.cpp, the
 * only C++ in the project; everything downstream is C. */
#ifndef SB_SCENE_H
#define SB_SCENE_H

#include "vecmath.h"

#include <math.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/* X(ID, name): the light's shapes (docs/design.md §4): two area lights and
 * the sun, a directional light with an angular size; GLSL sees SM_LIGHT_<ID>. */
#define LIGHT_SHAPES(X) X(RECT, "rect") X(DISK, "disk") X(SUN, "sun")

enum light_shape {
#define X(id, name) LIGHT_##id,
    LIGHT_SHAPES(X)
#undef X
    LIGHT_SHAPE_COUNT
};

/* Their spellings in a scene file, by enum value. */
extern const char *const light_shape_names[LIGHT_SHAPE_COUNT];

struct scene_light {
    enum light_shape shape;
    float width, height;  /* rect: full size along x, y (world units) */
    float radius;         /* disk (world units) */
    float half_angle;     /* sun: half its angular diameter (radians), in (0, 15 deg] */
    struct vec3 pos;      /* centre; the sun's node position, which nothing measures */
    struct vec3 x, y, z;  /* orthonormal; emits towards -z, one side only (the sun lies along +z) */
};

/* The sun's solid angle over 2 pi, 1 - cos(half_angle), as 2 sin^2(half/2):
 * in float, cos rounds to 1 at the real sun's size (0.27 deg). */
static inline double light_sun_cap(float half_angle)
{
    double s = sin(0.5 * (double)half_angle);
    return 2 * s * s;
}

struct scene_camera {
    struct vec3 pos;
    struct vec3 x, y, z;  /* orthonormal; looks along -z, y up */
    float yfov_rad;       /* vertical field of view */
    float znear;          /* > 0 (world units) */
};

/* A glTF node with vertices in it or under it: its vertices and its
 * descendants' are positions[first_vertex ..][vertex_count]. What a caster
 * motion (`shadowbench stability`) moves. */
struct scene_node {
    char *name;           /* the node's "name", or "" */
    size_t first_vertex, vertex_count;
};

/* The most motions a scene may define (extras.shadowbench.motions). */
#define SCENE_MAX_MOTIONS 16

struct scene {
    char *path;
    char *name;           /* file stem, e.g. "floating_box_sphere" */
    char *description;    /* extras.shadowbench.description or "" */
    char *shows;          /* extras.shadowbench.shows or "" */
    float *positions;     /* xyz per vertex, world space */
    float *normals;       /* xyz per vertex, world space, unit length */
    uint32_t *indices;    /* 3 per triangle */
    size_t vertex_count, triangle_count;
    struct scene_camera camera;
    struct scene_light light;
    struct scene_node *nodes;   /* post-order: a node after its descendants */
    size_t node_count;
    char **motions;       /* extras.shadowbench.motions: stability's motions of this scene */
    int motion_count;
    struct vec3 bounds_min, bounds_max;
    uint64_t hash;        /* of the file's bytes and every loaded array */
};

/* The renderers' range (docs/design.md §4): every coordinate (vertices, the
 * camera's and the light's positions) within +-SCENE_MAX_COORD world units,
 * and lengths (the light's size, znear) at least SCENE_MIN_LENGTH, as
 * floats. Beyond them Embree's and GL's float arithmetic fails (Embree
 * aborts on ~1e18). */
#define SCENE_MAX_COORD 1e8f
#define SCENE_MIN_LENGTH 1e-6f
/* The most triangles a scene may instantiate (three times as many vertices):
 * 140 times the bunny, 1-2 GB with Embree's BVH, loaded in seconds. */
#define SCENE_MAX_TRIANGLES 10000000

/* Loads path into *s. On failure logs one line "<path>: <problem>" and
 * returns a negative value (-ENOMEM: the memory ran out, not a fault of
 * the file); *s is then empty (scene_free is still safe). */
int scene_load(const char *path, struct scene *s);
void scene_free(struct scene *s);

/* Length of the bounding box diagonal: the scene's size for epsilons. */
float scene_extent(const struct scene *s);

#ifdef __cplusplus
}
#endif

#endif
