/* The closed-form scene of DESIGN.md §6 for tests: a light of width w at
 * height PP_H_LIGHT faces down onto a receiver at y = 0; an occluder
 * half-plane (x < 0) at y = PP_H_BLOCK has its straight edge along z. The
 * camera sits below the occluder, looking at the receiver across the edge. */
#ifndef SB_PARALLEL_PLANES_H
#define SB_PARALLEL_PLANES_H

#include "check.h"
#include "gltf_writer.h"

#include <stdbool.h>

#define PP_H_LIGHT 4.0f
#define PP_H_BLOCK 2.0f

static inline void write_parallel_planes(const char *path, float light_width, bool disk)
{
    struct mesh_builder m = {0};
    mesh_add_quad(&m, v3(-6, 0, -6), v3(0, 0, 12), v3(12, 0, 0));           /* receiver */
    mesh_add_quad(&m, v3(-8, PP_H_BLOCK, -8), v3(0, 0, 16), v3(8, 0, 0));   /* x < 0 */
    struct gltf_scene_desc d = {
        .description = "parallel planes (test)", .shows = "closed form",
        .camera_pos = v3(0.0f, 1.2f, 3.0f), .camera_target = v3(0.0f, 0.0f, 0.0f),
        .camera_yfov_rad = 0.5f, .camera_znear = 0.05f,
        .light_pos = v3(0, PP_H_LIGHT, 0), .light_target = v3(0, 0, 0),
        .light_disk = disk, .light_width = light_width, .light_height = light_width,
        .light_radius = 0.5f * light_width,
    };
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

#endif
