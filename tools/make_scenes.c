/* Writes every shipped scene (tools/scene_library.c) into a folder.
 * Usage: make_scenes <scenes folder>. The stanford_bunny scene reads its mesh
 * from Debian's glmark2-data package (tools/setup installs it). */
#include "scene_library.h"
#include "base/log.h"

#include <stdio.h>

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: make_scenes <scenes folder>\n");
        return 2;
    }
    int failed = 0;
    for (const struct scene_recipe *r = scene_recipes; r->name; r++) {
        int rc = scene_recipe_write(r, argv[1]);
        printf("%s/%s.gltf%s\n", argv[1], r->name, rc ? ": FAILED" : "");
        failed |= rc != 0;
    }
    return failed;
}
