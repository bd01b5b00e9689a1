/* A scene's triangles on the GPU: one VAO (location 0 position, 1 normal)
 * drawn by the shadow-map passes and the receiver pass alike. */
#ifndef SB_SCENE_MESH_H
#define SB_SCENE_MESH_H

#include "gl.h"
#include "scene/scene.h"

/* Vertex attribute locations (GLSL: SM_ATTRIB_POSITION, SM_ATTRIB_NORMAL). */
enum { SCENE_MESH_POSITION = 0, SCENE_MESH_NORMAL = 1 };

struct scene_mesh {
    GLuint vao, positions, normals, indices;
    GLsizei index_count;
};

void scene_mesh_upload(const struct scene *s, struct scene_mesh *m);
/* Replaces the positions with s's (the same vertex count): a node moved. */
void scene_mesh_update_positions(const struct scene *s, struct scene_mesh *m);
void scene_mesh_draw(const struct scene_mesh *m);
void scene_mesh_destroy(struct scene_mesh *m);

#endif
