#include "scene.h"

#include <stdlib.h>
#include <string.h>

const char *const light_shape_names[LIGHT_SHAPE_COUNT] = {
#define X(id, name) name,
    LIGHT_SHAPES(X)
#undef X
};

void scene_free(struct scene *s)
{
    free(s->path);
    free(s->name);
    free(s->description);
    free(s->shows);
    free(s->positions);
    free(s->normals);
    free(s->indices);
    for (size_t i = 0; i < s->node_count; i++)
        free(s->nodes[i].name);
    free(s->nodes);
    for (int i = 0; i < s->motion_count; i++)
        free(s->motions[i]);
    free(s->motions);
    memset(s, 0, sizeof *s);
}

float scene_extent(const struct scene *s)
{
    return v3_length(v3_sub(s->bounds_max, s->bounds_min));
}
