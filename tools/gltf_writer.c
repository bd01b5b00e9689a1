#include "gltf_writer.h"
#include "base/log.h"
#include "base/util.h"

#include <cjson/cJSON.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The new capacity when an array of n elements is full (n a power of two,
 * or 0): doubling; else 0, it has room. */
static size_t grow(size_t n)
{
    return (n & (n - 1)) == 0 ? (n ? 2 * n : 1) : 0;
}

uint32_t mesh_add_vertex(struct mesh_builder *m, struct vec3 p)
{
    size_t cap = grow(m->vertex_count);
    if (cap)
        m->positions = xrealloc(m->positions, sizeof(float) * 3 * cap);
    memcpy(&m->positions[3 * m->vertex_count], &p, sizeof p);
    return (uint32_t)m->vertex_count++;
}

void mesh_add_index(struct mesh_builder *m, uint32_t i)
{
    size_t cap = grow(m->index_count);
    if (cap)
        m->indices = xrealloc(m->indices, sizeof(uint32_t) * cap);
    m->indices[m->index_count++] = i;
}

void mesh_add_triangle(struct mesh_builder *m, struct vec3 a, struct vec3 b, struct vec3 c)
{
    mesh_add_index(m, mesh_add_vertex(m, a));
    mesh_add_index(m, mesh_add_vertex(m, b));
    mesh_add_index(m, mesh_add_vertex(m, c));
}

void mesh_add_quad(struct mesh_builder *m, struct vec3 corner, struct vec3 u, struct vec3 v)
{
    uint32_t a = mesh_add_vertex(m, corner), b = mesh_add_vertex(m, v3_add(corner, u)),
             c = mesh_add_vertex(m, v3_add(v3_add(corner, u), v)), d = mesh_add_vertex(m, v3_add(corner, v));
    const uint32_t tris[6] = {a, b, c, a, c, d};
    for (int i = 0; i < 6; i++)
        mesh_add_index(m, tris[i]);
}

void mesh_add_box(struct mesh_builder *m, struct vec3 lo, struct vec3 hi)
{
    struct vec3 d = v3_sub(hi, lo), ex = v3(d.x, 0, 0), ey = v3(0, d.y, 0), ez = v3(0, 0, d.z);
    mesh_add_quad(m, lo, ey, ex);                                /* -z */
    mesh_add_quad(m, v3_add(lo, ez), ex, ey);                    /* +z */
    mesh_add_quad(m, lo, ez, ey);                                /* -x */
    mesh_add_quad(m, v3_add(lo, ex), ey, ez);                    /* +x */
    mesh_add_quad(m, lo, ex, ez);                                /* -y */
    mesh_add_quad(m, v3_add(lo, ey), ez, ex);                    /* +y */
}

void mesh_add_sphere(struct mesh_builder *m, struct vec3 c, float r, int segments)
{
    const int rings = segments / 2;
    uint32_t base = (uint32_t)m->vertex_count;
    for (int i = 0; i <= rings; i++) {
        float th = (float)M_PI * (float)i / (float)rings;
        for (int j = 0; j <= segments; j++) {
            float ph = 2.0f * (float)M_PI * (float)j / (float)segments;
            mesh_add_vertex(m, v3_add(c, v3(r * sinf(th) * cosf(ph), r * cosf(th), r * sinf(th) * sinf(ph))));
        }
    }
    for (int i = 0; i < rings; i++)
        for (int j = 0; j < segments; j++) {
            uint32_t a = base + (uint32_t)(i * (segments + 1) + j), b = a + (uint32_t)segments + 1;
            if (i > 0) /* no degenerate triangles at the poles */
                mesh_add_index(m, a), mesh_add_index(m, a + 1), mesh_add_index(m, b);
            if (i < rings - 1)
                mesh_add_index(m, a + 1), mesh_add_index(m, b + 1), mesh_add_index(m, b);
        }
}

void mesh_add_torus(struct mesh_builder *m, struct vec3 c, float major, float minor, int major_segments,
                    int minor_segments)
{
    uint32_t base = (uint32_t)m->vertex_count;
    for (int i = 0; i <= major_segments; i++) {
        float ph = 2.0f * (float)M_PI * (float)i / (float)major_segments;
        for (int j = 0; j <= minor_segments; j++) {
            float th = 2.0f * (float)M_PI * (float)j / (float)minor_segments;
            float r = major + minor * cosf(th);
            mesh_add_vertex(m, v3_add(c, v3(r * cosf(ph), minor * sinf(th), r * sinf(ph))));
        }
    }
    for (int i = 0; i < major_segments; i++)
        for (int j = 0; j < minor_segments; j++) {
            uint32_t a = base + (uint32_t)(i * (minor_segments + 1) + j), b = a + (uint32_t)minor_segments + 1;
            mesh_add_index(m, a), mesh_add_index(m, a + 1), mesh_add_index(m, b + 1);
            mesh_add_index(m, a), mesh_add_index(m, b + 1), mesh_add_index(m, b);
        }
}

void mesh_free(struct mesh_builder *m)
{
    free(m->positions);
    free(m->indices);
    memset(m, 0, sizeof *m);
}

static char *base64(const unsigned char *p, size_t n)
{
    static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *out = xmalloc(4 * ((n + 2) / 3) + 1), *o = out;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) |
                     (i + 2 < n ? p[i + 2] : 0);
        *o++ = t[v >> 18 & 63];
        *o++ = t[v >> 12 & 63];
        *o++ = i + 1 < n ? t[v >> 6 & 63] : '=';
        *o++ = i + 2 < n ? t[v & 63] : '=';
    }
    *o = '\0';
    return out;
}

/* Node matrix of a frame at `pos` whose -Z looks at `target`. */
static cJSON *look_at_matrix(struct vec3 pos, struct vec3 target)
{
    struct vec3 z = v3_normalize(v3_sub(pos, target));
    struct vec3 up = fabsf(z.y) > 0.99f ? v3(0, 0, -1) : v3(0, 1, 0);
    struct vec3 x = v3_normalize(v3_cross(up, z)), y = v3_cross(z, x);
    const double m[16] = {x.x, x.y, x.z, 0, y.x, y.y, y.z, 0, z.x, z.y, z.z, 0, pos.x, pos.y, pos.z, 1};
    return cJSON_CreateDoubleArray(m, 16);
}

void mesh_begin_part(struct mesh_builder *m, const char *name)
{
    if (m->part_count == MESH_MAX_PARTS) {
        log_error("gltf_writer: more than %d parts", MESH_MAX_PARTS);
        abort();  /* a recipe's mistake, not input */
    }
    m->parts[m->part_count++] = (struct mesh_part){name, m->vertex_count, m->index_count};
}

/* An accessor of buffer view `view`, from offset_bytes (0: none written),
 * count elements of a component type and type (glTF's numbers, names). */
static cJSON *accessor(int view, size_t offset_bytes, int component_type, size_t count, const char *type)
{
    cJSON *a = cJSON_CreateObject();
    cJSON_AddNumberToObject(a, "bufferView", view);
    if (offset_bytes)
        cJSON_AddNumberToObject(a, "byteOffset", (double)offset_bytes);
    cJSON_AddNumberToObject(a, "componentType", component_type);
    cJSON_AddNumberToObject(a, "count", (double)count);
    cJSON_AddStringToObject(a, "type", type);
    return a;
}

int gltf_write(const char *path, const struct mesh_builder *m, const struct gltf_scene_desc *d)
{
    /* The parts: what came before the first named one is "geometry". */
    struct mesh_part parts[MESH_MAX_PARTS + 1];
    int n = 0;
    if (!m->part_count || m->parts[0].first_vertex > 0 || m->parts[0].first_index > 0)
        parts[n++] = (struct mesh_part){"geometry", 0, 0};
    for (int i = 0; i < m->part_count; i++)
        parts[n++] = m->parts[i];
    size_t first_vertex[MESH_MAX_PARTS + 2], first_index[MESH_MAX_PARTS + 2];
    for (int i = 0; i < n; i++)
        first_vertex[i] = parts[i].first_vertex, first_index[i] = parts[i].first_index;
    first_vertex[n] = m->vertex_count, first_index[n] = m->index_count;

    /* Indices are relative to their part's vertices, which they must stay
     * within when there are parts (one part is written as given: the
     * loader's tests write bad indices on purpose). */
    size_t pos_bytes = m->vertex_count * 12, idx_bytes = m->index_count * 4;
    unsigned char *buf = xmalloc(pos_bytes + idx_bytes);
    memcpy(buf, m->positions, pos_bytes);
    for (int i = 0; i < n; i++)
        for (size_t k = first_index[i]; k < first_index[i + 1]; k++) {
            const uint32_t v = m->indices[k];
            if (n > 1 && (v < first_vertex[i] || v >= first_vertex[i + 1])) {
                log_error("%s: part %s indexes vertex %u, which is not its own", path, parts[i].name, v);
                free(buf);
                return -1;
            }
            const uint32_t rel = v - (uint32_t)first_vertex[i];
            memcpy(buf + pos_bytes + 4 * k, &rel, 4);
        }
    char *b64 = base64(buf, pos_bytes + idx_bytes);
    char *uri = util_printf("data:application/octet-stream;base64,%s", b64);
    free(b64);
    free(buf);

    cJSON *g = cJSON_CreateObject();
    cJSON *asset = cJSON_AddObjectToObject(g, "asset");
    cJSON_AddStringToObject(asset, "version", "2.0");
    cJSON_AddStringToObject(asset, "generator", "shadowbench tools/gltf_writer.c");
    cJSON_AddNumberToObject(g, "scene", 0);
    cJSON *scene = cJSON_CreateObject();
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "scenes"), scene);
    int roots[MESH_MAX_PARTS + 3];
    for (int i = 0; i < n + 2; i++)
        roots[i] = i;
    cJSON_AddItemToObject(scene, "nodes", cJSON_CreateIntArray(roots, n + 2));
    cJSON *meta = cJSON_AddObjectToObject(cJSON_AddObjectToObject(scene, "extras"), "shadowbench");
    cJSON_AddStringToObject(meta, "description", d->description);
    cJSON_AddStringToObject(meta, "shows", d->shows);
    if (d->motions) {
        cJSON *motions = cJSON_AddArrayToObject(meta, "motions");
        for (const char *const *mo = d->motions; *mo; mo++)
            cJSON_AddItemToArray(motions, cJSON_CreateString(*mo));
    }

    cJSON *nodes = cJSON_AddArrayToObject(g, "nodes");
    for (int i = 0; i < n; i++) {
        cJSON *node = cJSON_CreateObject();
        cJSON_AddStringToObject(node, "name", parts[i].name);
        cJSON_AddNumberToObject(node, "mesh", i);
        cJSON_AddItemToArray(nodes, node);
    }
    cJSON *n_cam = cJSON_CreateObject(), *n_light = cJSON_CreateObject();
    cJSON_AddStringToObject(n_cam, "name", "camera");
    cJSON_AddNumberToObject(n_cam, "camera", 0);
    cJSON_AddItemToObject(n_cam, "matrix", look_at_matrix(d->camera_pos, d->camera_target));
    cJSON_AddStringToObject(n_light, "name", d->sun_angular_diameter_deg > 0 ? "sun" : "area light");
    cJSON_AddItemToObject(n_light, "matrix", look_at_matrix(d->light_pos, d->light_target));
    if (d->sun_angular_diameter_deg > 0) {  /* glTF's own light, which three.js, Babylon.js and Blender read */
        static const char ext[] = "KHR_lights_punctual";
        cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "extensionsUsed"), cJSON_CreateString(ext));
        cJSON *sun = cJSON_CreateObject();
        cJSON_AddStringToObject(sun, "name", "sun");
        cJSON_AddStringToObject(sun, "type", "directional");
        cJSON_AddNumberToObject(cJSON_AddObjectToObject(sun, "extras"), "angular_diameter_deg",
                                d->sun_angular_diameter_deg);
        cJSON *lights = cJSON_AddArrayToObject(cJSON_AddObjectToObject(cJSON_AddObjectToObject(g, "extensions"), ext),
                                               "lights");
        cJSON_AddItemToArray(lights, sun);
        cJSON_AddNumberToObject(cJSON_AddObjectToObject(cJSON_AddObjectToObject(n_light, "extensions"), ext),
                                "light", 0);
    } else {
        cJSON *al = cJSON_AddObjectToObject(cJSON_AddObjectToObject(n_light, "extras"), "area_light");
        cJSON_AddStringToObject(al, "shape", light_shape_names[d->light_disk ? LIGHT_DISK : LIGHT_RECT]);
        if (d->light_disk)
            cJSON_AddNumberToObject(al, "radius", d->light_radius);
        else
            cJSON_AddItemToObject(al, "size", cJSON_CreateFloatArray((const float[]){d->light_width, d->light_height}, 2));
    }
    cJSON_AddItemToArray(nodes, n_cam);
    cJSON_AddItemToArray(nodes, n_light);

    cJSON *cam = cJSON_CreateObject();
    cJSON_AddStringToObject(cam, "type", "perspective");
    cJSON *persp = cJSON_AddObjectToObject(cam, "perspective");
    cJSON_AddNumberToObject(persp, "yfov", d->camera_yfov_rad);
    cJSON_AddNumberToObject(persp, "znear", d->camera_znear);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "cameras"), cam);

    cJSON *meshes = cJSON_AddArrayToObject(g, "meshes");
    for (int i = 0; i < n; i++) {
        cJSON *prim = cJSON_CreateObject();
        cJSON_AddNumberToObject(cJSON_AddObjectToObject(prim, "attributes"), "POSITION", 2 * i);
        cJSON_AddNumberToObject(prim, "indices", 2 * i + 1);
        cJSON_AddNumberToObject(prim, "mode", 4);
        cJSON *mesh = cJSON_CreateObject();
        cJSON_AddItemToArray(cJSON_AddArrayToObject(mesh, "primitives"), prim);
        cJSON_AddItemToArray(meshes, mesh);
    }

    cJSON *acc = cJSON_AddArrayToObject(g, "accessors");
    for (int i = 0; i < n; i++) {
        float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (size_t k = 3 * first_vertex[i]; k < 3 * first_vertex[i + 1]; k++) {
            lo[k % 3] = fminf(lo[k % 3], m->positions[k]);
            hi[k % 3] = fmaxf(hi[k % 3], m->positions[k]);
        }
        cJSON *positions = accessor(0, 12 * first_vertex[i], 5126, first_vertex[i + 1] - first_vertex[i], "VEC3");
        cJSON_AddItemToObject(positions, "min", cJSON_CreateFloatArray(lo, 3));
        cJSON_AddItemToObject(positions, "max", cJSON_CreateFloatArray(hi, 3));
        cJSON_AddItemToArray(acc, positions);
        cJSON_AddItemToArray(acc, accessor(1, 4 * first_index[i], 5125, first_index[i + 1] - first_index[i], "SCALAR"));
    }

    cJSON *views = cJSON_AddArrayToObject(g, "bufferViews");
    cJSON *v0 = cJSON_CreateObject(), *v1 = cJSON_CreateObject();
    cJSON_AddNumberToObject(v0, "buffer", 0);
    cJSON_AddNumberToObject(v0, "byteLength", (double)pos_bytes);
    if (n > 1)  /* glTF 2.0: a vertex view that two accessors share must state its stride */
        cJSON_AddNumberToObject(v0, "byteStride", 12);
    cJSON_AddNumberToObject(v0, "target", 34962);
    cJSON_AddNumberToObject(v1, "buffer", 0);
    cJSON_AddNumberToObject(v1, "byteOffset", (double)pos_bytes);
    cJSON_AddNumberToObject(v1, "byteLength", (double)idx_bytes);
    cJSON_AddNumberToObject(v1, "target", 34963);
    cJSON_AddItemToArray(views, v0);
    cJSON_AddItemToArray(views, v1);

    cJSON *b = cJSON_CreateObject();
    cJSON_AddNumberToObject(b, "byteLength", (double)(pos_bytes + idx_bytes));
    cJSON_AddStringToObject(b, "uri", uri);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "buffers"), b);
    free(uri);

    char *text = cJSON_Print(g);
    int rc = util_write_file_atomic(path, text, strlen(text));
    cJSON_free(text);
    cJSON_Delete(g);
    return rc ? -1 : 0;
}
