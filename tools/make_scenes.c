/* Writes the shipped scenes into scenes/. Each isolates one phenomenon
 * (DESIGN.md §3); the geometry is built here so its provenance is this file.
 * Usage: make_scenes <scenes folder> */
#include "gltf_writer.h"
#include "log.h"
#include "util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

/* A unit box and a sphere floating at different heights over a ground
 * plane, under a 1.2 x 1.2 rect light 6 units up: two penumbrae of
 * different widths (the higher sphere's is wider) on a flat receiver. */
static int floating_box_sphere(const char *dir)
{
    struct mesh_builder m = {0};
    mesh_add_quad(&m, v3(-6, 0, -6), v3(0, 0, 12), v3(12, 0, 0));  /* ground, y = 0, normal +y */
    mesh_add_box(&m, v3(-2.0f, 1.0f, -0.5f), v3(-1.0f, 2.0f, 0.5f));
    mesh_add_sphere(&m, v3(1.5f, 2.6f, 0.0f), 0.6f, 48);
    struct gltf_scene_desc d = {
        .description = "A box (bottom 1 above the ground) and a sphere (bottom 2 above) over a "
                       "ground plane under a 1.2 x 1.2 rect light.",
        .shows = "penumbra width growing with the blocker-receiver distance; the basic "
                 "end-to-end case",
        .camera_pos = v3(0.0f, 7.0f, 8.5f),
        .camera_target = v3(0.0f, 0.5f, 0.0f),
        .camera_yfov_rad = 0.75f,
        .camera_znear = 0.1f,
        .light_pos = v3(0.5f, 6.0f, 0.0f),
        .light_target = v3(0.5f, 0.0f, 0.0f),
        .light_width = 1.2f,
        .light_height = 1.2f,
    };
    char *path = util_printf("%s/floating_box_sphere.gltf", dir);
    int rc = gltf_write(path, &m, &d);
    printf("%s\n", path);
    free(path);
    mesh_free(&m);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: make_scenes <scenes folder>\n");
        return 2;
    }
    return floating_box_sphere(argv[1]) ? 1 : 0;
}
