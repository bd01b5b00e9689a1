/* The closed-form parallel-planes scene (tools/scene_library.h) written to a
 * file, with a light of any width: the shipped parallel_planes scenes are
 * light_width 1. */
#ifndef SB_PARALLEL_PLANES_H
#define SB_PARALLEL_PLANES_H

#include "check.h"
#include "scene_library.h"

static inline void write_parallel_planes(const char *path, float light_width, bool disk)
{
    struct mesh_builder m = {0};
    struct gltf_scene_desc d;
    scene_parallel_planes(&m, &d, light_width, disk);
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

#endif
