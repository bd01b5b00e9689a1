/* Protects the scene-format errors of DESIGN.md §4: each malformed scene
 * gives exactly one line naming the file and the problem, word for word, and
 * exit status 2 (SQLite's do_catchsql_test style). Each case starts from a
 * valid scene and breaks one thing. */
#include "check.h"
#include "gltf_writer.h"
#include "run_cmd.h"

#include <cjson/cJSON.h>
#include <string.h>

static const char *shadowbench;
static char dir[] = "/tmp/sb_test_loader_XXXXXX";

static void write_valid(const char *path, struct mesh_builder *m)
{
    struct gltf_scene_desc d = {
        .description = "one triangle", .shows = "loader errors",
        .camera_pos = v3(0, 3, 3), .camera_target = v3(0, 0, 0), .camera_yfov_rad = 0.8f,
        .camera_znear = 0.1f, .light_pos = v3(0, 4, 0), .light_target = v3(0, 0, 0),
        .light_width = 1, .light_height = 1,
    };
    struct mesh_builder tri = {0};
    if (!m) {
        mesh_add_triangle(&tri, v3(-1, 0, -1), v3(1, 0, -1), v3(0, 0, 1));
        m = &tri;
    }
    gltf_write(path, m, &d);
    mesh_free(&tri);
}

typedef void (*mutate_fn)(cJSON *g);

/* Writes a valid scene, applies `mutate` to its JSON (if any), and returns
 * the path. */
static char *scene_with(const char *name, mutate_fn mutate)
{
    char *path = util_printf("%s/%s.gltf", dir, name);
    write_valid(path, NULL);
    if (mutate) {
        char *text;
        size_t size;
        util_read_file(path, &text, &size);
        cJSON *g = cJSON_Parse(text);
        free(text);
        mutate(g);
        char *out = cJSON_Print(g);
        util_write_file_atomic(path, out, strlen(out));
        cJSON_free(out);
        cJSON_Delete(g);
    }
    return path;
}

static cJSON *at(cJSON *g, const char *array, int index)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(g, array), index);
}

static void no_camera(cJSON *g) { cJSON_DeleteItemFromObject(at(g, "nodes", 1), "camera"); }
static void orthographic(cJSON *g)
{
    cJSON *c = at(g, "cameras", 0);
    cJSON_ReplaceItemInObject(c, "type", cJSON_CreateString("orthographic"));
    cJSON_DeleteItemFromObject(c, "perspective");
    cJSON *o = cJSON_AddObjectToObject(c, "orthographic");
    cJSON_AddNumberToObject(o, "xmag", 1);
    cJSON_AddNumberToObject(o, "ymag", 1);
    cJSON_AddNumberToObject(o, "znear", 0.1);
    cJSON_AddNumberToObject(o, "zfar", 10);
}
static void no_light(cJSON *g) { cJSON_DeleteItemFromObject(at(g, "nodes", 2), "extras"); }
static cJSON *light(cJSON *g)
{
    return cJSON_GetObjectItem(cJSON_GetObjectItem(at(g, "nodes", 2), "extras"), "area_light");
}
static void zero_size(cJSON *g)
{
    cJSON_ReplaceItemInObject(light(g), "size", cJSON_CreateIntArray((const int[]){0, 1}, 2));
}
static void negative_radius(cJSON *g)
{
    cJSON_ReplaceItemInObject(light(g), "shape", cJSON_CreateString("disk"));
    cJSON_AddNumberToObject(light(g), "radius", -0.5);
}
static void bad_shape(cJSON *g) { cJSON_ReplaceItemInObject(light(g), "shape", cJSON_CreateString("sphere")); }
static cJSON *primitive(cJSON *g)
{
    return cJSON_GetArrayItem(cJSON_GetObjectItem(at(g, "meshes", 0), "primitives"), 0);
}
static void lines(cJSON *g) { cJSON_ReplaceItemInObject(primitive(g), "mode", cJSON_CreateNumber(1)); }
static void no_triangles(cJSON *g) { cJSON_DeleteItemFromObject(at(g, "nodes", 0), "mesh"); }
static void overrun(cJSON *g)
{
    cJSON_ReplaceItemInObject(at(g, "accessors", 0), "count", cJSON_CreateNumber(100));
    cJSON_DeleteItemFromObject(at(g, "accessors", 0), "min");
    cJSON_DeleteItemFromObject(at(g, "accessors", 0), "max");
}

/* Runs `gt` on path; the whole of stderr must be the one expected line. */
static void expect_error(const char *path, const char *problem)
{
    char *cmd = util_printf("%s gt --scene '%s' --width 16 --height 16 --gt-samples 1 --no-cache "
                            "--out %s/out", shadowbench, path, dir);
    char *want = util_printf("shadowbench: error: %s: %s\n", path, problem);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 2, "exit status %d for '%s'", status, problem);
    CHECK(strcmp(err.data, want) == 0, "\n  got:    %s  wanted: %s", err.data, want);
    strbuf_free(&err);
    free(want);
    free(cmd);
}

static void case_mutated(const char *name, mutate_fn f, const char *problem)
{
    char *path = scene_with(name, f);
    expect_error(path, problem);
    free(path);
}

static void case_mesh(const char *name, struct mesh_builder *m, const char *problem)
{
    char *path = util_printf("%s/%s.gltf", dir, name);
    write_valid(path, m);
    /* gltf_write records min/max, which are not finite for a NaN vertex;
     * drop them so the file stays valid JSON. */
    char *text;
    size_t size;
    util_read_file(path, &text, &size);
    cJSON *g = cJSON_Parse(text);
    free(text);
    cJSON_DeleteItemFromObject(at(g, "accessors", 0), "min");
    cJSON_DeleteItemFromObject(at(g, "accessors", 0), "max");
    char *out = cJSON_Print(g);
    util_write_file_atomic(path, out, strlen(out));
    cJSON_free(out);
    cJSON_Delete(g);
    expect_error(path, problem);
    free(path);
}

int main(int argc, char **argv)
{
    if (argc < 2 || !mkdtemp(dir))
        return 1;
    shadowbench = argv[1];

    /* The valid scene itself loads: the cases below differ by one thing. */
    char *ok = scene_with("valid", NULL);
    char *cmd = util_printf("%s gt --scene %s --width 16 --height 16 --gt-samples 1 --no-cache -q "
                            "--out %s/out >/dev/null", shadowbench, ok, dir);
    CHECK(system(cmd) == 0, "the unbroken scene must load");
    free(cmd);
    free(ok);

    char *missing = util_printf("%s/missing.gltf", dir);
    expect_error(missing, "cannot open: No such file or directory");
    free(missing);

    char *bad_json = util_printf("%s/bad_json.gltf", dir);
    const char *text = "{\n  \"asset\": {\"version\": \"2.0\"},\n  \"nodes\": [,]\n}\n";
    util_write_file_atomic(bad_json, text, strlen(text));
    expect_error(bad_json, "malformed JSON at line 3 (byte 45)");
    free(bad_json);

    case_mutated("overrun", overrun,
                 "malformed buffers: POSITION accessor 0 reads past the end of buffer view 0");
    case_mutated("no_camera", no_camera, "no camera: need a node with a perspective camera");
    case_mutated("orthographic", orthographic,
                 "camera 0 is orthographic: only perspective cameras are supported");
    case_mutated("no_light", no_light, "no area light: need a node whose extras hold \"area_light\"");
    case_mutated("no_triangles", no_triangles, "no triangles");
    case_mutated("lines", lines,
                 "mesh 0 primitive 0 has mode 1 (LINES): only TRIANGLES (4) is supported");
    case_mutated("zero_size", zero_size, "area light (node 2): size must be positive, got [0, 1]");
    case_mutated("negative_radius", negative_radius,
                 "area light (node 2): radius must be positive, got -0.5");
    case_mutated("bad_shape", bad_shape,
                 "area light (node 2): \"shape\" must be \"rect\" or \"disk\", got \"sphere\"");

    struct mesh_builder m = {0};
    mesh_add_triangle(&m, v3(-1, 0, -1), v3(NAN, 0, -1), v3(0, 0, 1));
    case_mesh("nan_vertex", &m, "mesh 0 primitive 0: vertex 1 is not finite");
    mesh_free(&m);

    mesh_add_triangle(&m, v3(-1, 0, -1), v3(1, 0, -1), v3(0, 0, 1));
    m.indices[2] = 7;
    case_mesh("bad_index", &m, "mesh 0 primitive 0: index 7 at position 2 is out of range (3 vertices)");
    mesh_free(&m);

    remove_tree(dir);
    return check_finish();
}
