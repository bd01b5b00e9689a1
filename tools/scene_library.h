/* The geometry, camera and light of every shipped scene, built in code so
 * that this file (with scene_library.c) is their provenance. make_scenes
 * writes them into scenes/; the tests build the same scenes, or variants of
 * the parametrised ones, on the fly. */
#ifndef SB_SCENE_LIBRARY_H
#define SB_SCENE_LIBRARY_H

#include "gltf_writer.h"

#include <stdbool.h>

/* Parallel planes (the closed form of docs/design.md §6): a light of width
 * light_width at height PP_H_LIGHT faces down onto a receiver at y = 0; an
 * occluder half-plane (x < 0) at y = PP_H_BLOCK has its straight edge along
 * z. The camera sits below the occluder, looking at the receiver across the
 * edge. disk: a disk light of diameter light_width instead of a square. */
#define PP_H_LIGHT 4.0f
#define PP_H_BLOCK 2.0f
void scene_parallel_planes(struct mesh_builder *m, struct gltf_scene_desc *d, float light_width,
                           bool disk);

/* The real sun's angular diameter in the shipped sun scenes (degrees;
 * Blender's default sun is 0.526, Unreal's 0.5357). */
#define SCENE_SUN_DEG 0.53

/* The sun's parallel planes (the closed form of docs/design.md §6): the sun
 * straight above a receiver at y = 0, an occluder half-plane (x < 0) at
 * y = PP_H_BLOCK; the camera frames the penumbra, whose width is
 * scene_sun_penumbra_width, at any angle. Its nodes: "ground", "plate". */
void scene_sun_parallel_planes(struct mesh_builder *m, struct gltf_scene_desc *d, double angular_diameter_deg);
float scene_sun_penumbra_width(double angular_diameter_deg);

/* Where make_scenes reads the real-world mesh: the Stanford Bunny as Debian's
 * glmark2-data package ships it (69 666 triangles). */
#define SCENE_BUNNY_OBJ "/usr/share/glmark2/models/bunny.obj"

struct scene_recipe {
    const char *name;  /* the file stem: scenes/<name>.gltf */
    /* Fills m and d. Returns 0, or -1 after logging (an input file missing). */
    int (*build)(struct mesh_builder *m, struct gltf_scene_desc *d);
};

/* Every shipped scene, NULL-terminated. */
extern const struct scene_recipe scene_recipes[];

/* Builds recipe r and writes it to <dir>/<name>.gltf. Returns 0 or -1. */
int scene_recipe_write(const struct scene_recipe *r, const char *dir);

#endif
