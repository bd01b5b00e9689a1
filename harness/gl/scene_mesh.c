#include "scene_mesh.h"

#include <string.h>

static GLuint upload(GLenum target, const void *data, size_t size, const char *label)
{
    GLuint b;
    glGenBuffers(1, &b);
    glBindBuffer(target, b);
    glBufferData(target, (GLsizeiptr)size, data, GL_STATIC_DRAW);
    gl_label(GL_BUFFER, b, label);
    return b;
}

void scene_mesh_upload(const struct scene *s, struct scene_mesh *m)
{
    memset(m, 0, sizeof *m);
    glGenVertexArrays(1, &m->vao);
    glBindVertexArray(m->vao);
    gl_label(GL_VERTEX_ARRAY, m->vao, s->name);
    m->positions = upload(GL_ARRAY_BUFFER, s->positions, s->vertex_count * 12, "scene positions");
    glVertexAttribPointer(SCENE_MESH_POSITION, 3, GL_FLOAT, GL_FALSE, 12, NULL);
    glEnableVertexAttribArray(SCENE_MESH_POSITION);
    m->normals = upload(GL_ARRAY_BUFFER, s->normals, s->vertex_count * 12, "scene normals");
    glVertexAttribPointer(SCENE_MESH_NORMAL, 3, GL_FLOAT, GL_FALSE, 12, NULL);
    glEnableVertexAttribArray(SCENE_MESH_NORMAL);
    m->indices = upload(GL_ELEMENT_ARRAY_BUFFER, s->indices, s->triangle_count * 12, "scene indices");
    m->index_count = (GLsizei)(s->triangle_count * 3);
    glBindVertexArray(0);
}

void scene_mesh_update_positions(const struct scene *s, struct scene_mesh *m)
{
    /* Respecified rather than glBufferSubData'd: Mesa's debug output warns
     * of a GL_STATIC_DRAW buffer updated in place, and static is right for
     * every other use (a caster moves only in `stability`). */
    glBindBuffer(GL_ARRAY_BUFFER, m->positions);
    glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(s->vertex_count * 12), s->positions, GL_STATIC_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, 0);
}

void scene_mesh_draw(const struct scene_mesh *m)
{
    glBindVertexArray(m->vao);
    glDrawElements(GL_TRIANGLES, m->index_count, GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
}

void scene_mesh_destroy(struct scene_mesh *m)
{
    GLuint buffers[3] = {m->positions, m->normals, m->indices};
    glDeleteBuffers(3, buffers);
    if (m->vao)
        glDeleteVertexArrays(1, &m->vao);
    memset(m, 0, sizeof *m);
}
