/* Protects the scene-format errors of docs/design.md §4: each malformed scene
 * gives exactly one line naming the file and the problem, word for word, and
 * exit status 2 (SQLite's do_catchsql_test style). Each case starts from a
 * valid scene and breaks one thing. */
#include "check.h"
#include "gltf_writer.h"
#include "run_cmd.h"

#include <cjson/cJSON.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* Encoded geometry (KHR_mesh_quantization, EXT_meshopt_compression,
 * KHR_draco_mesh_compression): a quantized type without its extension, and
 * data its decoder refuses. */
static void uses_extension(cJSON *g, const char *name)
{
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "extensionsUsed"), cJSON_CreateString(name));
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "extensionsRequired"), cJSON_CreateString(name));
}
static void short_positions(cJSON *g) { cJSON_ReplaceItemInObject(at(g, "accessors", 0), "componentType", cJSON_CreateNumber(5122)); }
/* Buffer view 0 (the positions, 36 bytes) said to be meshopt data: floats are no meshopt header. */
static void meshopt_view(cJSON *g, const char *mode)
{
    uses_extension(g, "EXT_meshopt_compression");
    cJSON *e = cJSON_AddObjectToObject(cJSON_AddObjectToObject(at(g, "bufferViews", 0), "extensions"),
                                       "EXT_meshopt_compression");
    cJSON_AddNumberToObject(e, "buffer", 0);
    cJSON_AddNumberToObject(e, "byteLength", 36);
    cJSON_AddNumberToObject(e, "byteStride", 12);
    cJSON_AddNumberToObject(e, "count", 3);
    cJSON_AddStringToObject(e, "mode", mode);
}
static void meshopt_garbage(cJSON *g) { meshopt_view(g, "ATTRIBUTES"); }
static void meshopt_indices(cJSON *g, int stride, double count)
{
    meshopt_view(g, "TRIANGLES");
    cJSON *e = cJSON_GetObjectItem(cJSON_GetObjectItem(at(g, "bufferViews", 0), "extensions"), "EXT_meshopt_compression");
    cJSON_ReplaceItemInObject(e, "byteStride", cJSON_CreateNumber(stride));
    cJSON_ReplaceItemInObject(e, "count", cJSON_CreateNumber(count));
}
static void meshopt_stride(cJSON *g) { meshopt_indices(g, 12, 3); }
static void meshopt_partial(cJSON *g) { meshopt_indices(g, 2, 4); }
static void meshopt_huge(cJSON *g) { meshopt_indices(g, 4, 2147483646.0); }
static void meshopt_mode(cJSON *g) { meshopt_view(g, "POINTS"); }

/* Hostile values (issue 12): overflowing sizes, shared children, values
 * the renderers cannot hold, wrong JSON types that tinygltf would replace
 * by defaults. */
static void huge_count(cJSON *g)
{
    overrun(g);
    cJSON_ReplaceItemInObject(at(g, "accessors", 0), "count", cJSON_CreateNumber(2147483647.0));
}
static void wrapping_offset(cJSON *g)
{
    cJSON_AddNumberToObject(at(g, "bufferViews", 0), "byteOffset", 18446744073709551608.0);
}
static void short_stride(cJSON *g) { cJSON_AddNumberToObject(at(g, "bufferViews", 0), "byteStride", 4); }
static void two_parents(cJSON *g)
{
    cJSON_AddItemToObject(at(g, "nodes", 1), "children", cJSON_CreateIntArray((const int[]){0}, 1));
    cJSON_AddItemToObject(at(g, "nodes", 2), "children", cJSON_CreateIntArray((const int[]){0}, 1));
}
static void huge_light(cJSON *g)
{
    cJSON_ReplaceItemInObject(light(g), "size", cJSON_CreateDoubleArray((const double[]){5e18, 1}, 2));
}
static void overflowing_light(cJSON *g)
{
    cJSON_ReplaceItemInObject(light(g), "size", cJSON_CreateDoubleArray((const double[]){1e39, 1}, 2));
}
static void vanishing_light(cJSON *g)
{
    cJSON_ReplaceItemInObject(light(g), "size", cJSON_CreateDoubleArray((const double[]){1e-50, 1}, 2));
}
static void far_camera(cJSON *g)
{
    cJSON *m = cJSON_GetObjectItem(at(g, "nodes", 1), "matrix");
    cJSON_ReplaceItemInArray(m, 12, cJSON_CreateNumber(3e18));
}
static cJSON *perspective(cJSON *g) { return cJSON_GetObjectItem(at(g, "cameras", 0), "perspective"); }
static void pi_yfov(cJSON *g) { cJSON_ReplaceItemInObject(perspective(g), "yfov", cJSON_CreateNumber(3.14159265358979)); }
static void tiny_znear(cJSON *g) { cJSON_ReplaceItemInObject(perspective(g), "znear", cJSON_CreateNumber(1e-50)); }
static void string_matrix(cJSON *g)
{
    const char *const a[16] = {"a", "0", "0", "0", "0", "1", "0", "0", "0", "0", "1", "0", "0", "0", "0", "1"};
    cJSON_ReplaceItemInObject(at(g, "nodes", 1), "matrix", cJSON_CreateStringArray(a, 16));
}
static void short_matrix(cJSON *g)
{
    cJSON_ReplaceItemInObject(at(g, "nodes", 1), "matrix", cJSON_CreateIntArray((const int[]){1, 0, 0}, 3));
}
static void zero_rotation(cJSON *g)
{
    cJSON_AddItemToObject(at(g, "nodes", 0), "rotation", cJSON_CreateIntArray((const int[]){0, 0, 0, 0}, 4));
}
static void string_mode(cJSON *g) { cJSON_ReplaceItemInObject(primitive(g), "mode", cJSON_CreateString("4")); }
static void twice_mode(cJSON *g) { cJSON_AddStringToObject(primitive(g), "mode", "4"); }
static void huge_mesh(cJSON *g) { cJSON_ReplaceItemInObject(at(g, "nodes", 0), "mesh", cJSON_CreateNumber(1099511627776.0)); }
static void no_yfov(cJSON *g) { cJSON_DeleteItemFromObject(perspective(g), "yfov"); }
static void folder_uri(cJSON *g) { cJSON_ReplaceItemInObject(at(g, "buffers", 0), "uri", cJSON_CreateString(".")); }
static void device_uri(cJSON *g) { cJSON_ReplaceItemInObject(at(g, "buffers", 0), "uri", cJSON_CreateString("../../dev/zero")); }
static void short_buffer(cJSON *g)
{
    cJSON *b = at(g, "buffers", 0);
    cJSON_ReplaceItemInObject(b, "byteLength", cJSON_CreateNumber(cJSON_GetObjectItem(b, "byteLength")->valuedouble + 1000));
}
static void overflowing_matrix(cJSON *g)
{
    cJSON_ReplaceItemInArray(cJSON_GetObjectItem(at(g, "nodes", 1), "matrix"), 0, cJSON_CreateNumber(1e39));
}
static void fifo_uri(cJSON *g) { cJSON_ReplaceItemInObject(at(g, "buffers", 0), "uri", cJSON_CreateString("fifo.bin")); }
static void encoded_fifo_uri(cJSON *g)
{
    cJSON_ReplaceItemInObject(at(g, "buffers", 0), "uri", cJSON_CreateString("fifo%2Ebin"));
}
static void image_fifo(cJSON *g)
{
    cJSON *image = cJSON_CreateObject();
    cJSON_AddStringToObject(image, "uri", "fifo.bin");
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "images"), image);
}
/* A fifth hostile pass: what glTF defines and shadowbench would get wrong
 * without a word (deformations, a matrix beside TRS, a projective matrix),
 * indices and types that do not hold, and geometry multiplied by reuse. */
static void morph_targets(cJSON *g)
{
    cJSON *target = cJSON_CreateObject();
    cJSON_AddNumberToObject(target, "POSITION", 0);
    cJSON_AddItemToArray(cJSON_AddArrayToObject(primitive(g), "targets"), target);
}
static void skinned(cJSON *g) { cJSON_AddNumberToObject(at(g, "nodes", 0), "skin", 0); }
static void matrix_and_trs(cJSON *g)
{
    cJSON_AddItemToObject(at(g, "nodes", 1), "translation", cJSON_CreateIntArray((const int[]){0, 0, 0}, 3));
}
static void projective(cJSON *g)
{
    cJSON_ReplaceItemInArray(cJSON_GetObjectItem(at(g, "nodes", 1), "matrix"), 3, cJSON_CreateNumber(0.5));
}
static void min_version(cJSON *g) { cJSON_AddStringToObject(cJSON_GetObjectItem(g, "asset"), "minVersion", "2.5"); }
static void no_scenes(cJSON *g) { cJSON_DeleteItemFromObject(g, "scenes"); }
static void camera_99(cJSON *g) { cJSON_AddNumberToObject(at(g, "nodes", 0), "camera", 99); }
static void texcoord_99(cJSON *g)
{
    cJSON_AddNumberToObject(cJSON_GetObjectItem(primitive(g), "attributes"), "TEXCOORD_0", 99);
}
static void strided_indices(cJSON *g) { cJSON_AddNumberToObject(at(g, "bufferViews", 1), "byteStride", 4); }
static void text_zfar(cJSON *g) { cJSON_AddStringToObject(perspective(g), "zfar", "far"); }
static void text_normalized(cJSON *g) { cJSON_AddStringToObject(at(g, "accessors", 0), "normalized", "yes"); }
static void number_description(cJSON *g)
{
    cJSON *meta = cJSON_GetObjectItem(cJSON_GetObjectItem(at(g, "scenes", 0), "extras"), "shadowbench");
    cJSON_ReplaceItemInObject(meta, "description", cJSON_CreateNumber(5));
}
static void number_name(cJSON *g) { cJSON_ReplaceItemInObject(at(g, "nodes", 0), "name", cJSON_CreateNumber(5)); }
static void motions_object(cJSON *g)
{
    cJSON *meta = cJSON_GetObjectItem(cJSON_GetObjectItem(at(g, "scenes", 0), "extras"), "shadowbench");
    cJSON_AddObjectToObject(meta, "motions");
}
static void motions_number(cJSON *g)
{
    cJSON *meta = cJSON_GetObjectItem(cJSON_GetObjectItem(at(g, "scenes", 0), "extras"), "shadowbench");
    cJSON_AddItemToObject(meta, "motions", cJSON_CreateIntArray((const int[]){1}, 1));
}
/* Column 1 of a node's matrix (its Y axis) scaled by f. */
static void scale_y(cJSON *g, int node, double f)
{
    cJSON *m = cJSON_GetObjectItem(at(g, "nodes", node), "matrix");
    for (int i = 4; i < 7; i++)
        cJSON_ReplaceItemInArray(m, i, cJSON_CreateNumber(cJSON_GetArrayItem(m, i)->valuedouble * f));
}
static void flat_light(cJSON *g) { scale_y(g, 2, 0); }
static void mirrored_camera(cJSON *g) { scale_y(g, 1, -1); }
/* The camera turned half a turn about its Y axis: it sees nothing. */
static void camera_away(cJSON *g)
{
    cJSON *m = cJSON_GetObjectItem(at(g, "nodes", 1), "matrix");
    for (int i = 0; i < 11; i++)
        if (i < 3 || (i >= 8 && i < 11))
            cJSON_ReplaceItemInArray(m, i, cJSON_CreateNumber(-cJSON_GetArrayItem(m, i)->valuedouble));
}
/* 101 nodes x 100 primitives x the 1000-triangle mesh: 10.1 M triangles
 * from a 60 KB file. */
static void amplified(cJSON *g)
{
    cJSON *prims = cJSON_GetObjectItem(at(g, "meshes", 0), "primitives");
    for (int i = 1; i < 100; i++)
        cJSON_AddItemToArray(prims, cJSON_Duplicate(cJSON_GetArrayItem(prims, 0), true));
    cJSON *roots = cJSON_GetObjectItem(at(g, "scenes", 0), "nodes");
    for (int i = 0; i < 100; i++) {
        cJSON *n = cJSON_CreateObject();
        cJSON_AddNumberToObject(n, "mesh", 0);
        cJSON_AddItemToArray(cJSON_GetObjectItem(g, "nodes"), n);
        cJSON_AddItemToArray(roots, cJSON_CreateNumber(3 + i));
    }
}

/* A file of 2000 bytes beside the scene, for a buffer of 48. */
static void long_file(cJSON *g, const char *uri)
{
    char *path = util_printf("%s/long.bin", dir), zeros[2000] = {0};
    util_write_file_atomic(path, zeros, sizeof zeros);
    free(path);
    cJSON_ReplaceItemInObject(at(g, "buffers", 0), "uri", cJSON_CreateString(uri));
}
static void long_uri(cJSON *g) { long_file(g, "long.bin"); }
static void rooted_uri(cJSON *g) { long_file(g, "/long.bin"); }
static void huge_image(cJSON *g)
{
    cJSON *image = cJSON_CreateObject();
    cJSON_AddStringToObject(image, "uri", "huge.png");
    cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "images"), image);
}
static void no_asset(cJSON *g) { cJSON_DeleteItemFromObject(g, "asset"); }
static void missing_normal(cJSON *g)
{
    cJSON_AddNumberToObject(cJSON_GetObjectItem(primitive(g), "attributes"), "NORMAL", 9);
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

/* A valid scene whose text has `from` replaced by `to` (once): for what a
 * JSON library would not write, such as 4.0 for 4. */
static void case_text(const char *name, const char *from, const char *to, const char *problem)
{
    char *path = scene_with(name, NULL), *text;
    size_t size;
    util_read_file(path, &text, &size);
    char *at = strstr(text, from);
    CHECK(at != NULL, "%s: '%s' not in the valid scene", name, from);
    if (at) {
        char *edited = util_printf("%.*s%s%s", (int)(at - text), text, to, at + strlen(from));
        util_write_file_atomic(path, edited, strlen(edited));
        free(edited);
    }
    free(text);
    expect_error(path, problem);
    free(path);
}

/* The sun (KHR_lights_punctual, docs/design.md §4) at node `node` in place
 * of the area light, its light `type` with extras.angular_diameter_deg
 * `angle` (NULL: none). */
static void put_sun(cJSON *g, int node, const char *type, cJSON *angle)
{
    static const char ext[] = "KHR_lights_punctual";
    cJSON_DeleteItemFromObject(at(g, "nodes", 2), "extras");
    if (!cJSON_GetObjectItem(g, "extensionsUsed"))
        cJSON_AddItemToArray(cJSON_AddArrayToObject(g, "extensionsUsed"), cJSON_CreateString(ext));
    cJSON *light = cJSON_CreateObject();
    cJSON_AddStringToObject(light, "type", type);
    if (!strcmp(type, "spot"))  /* glTF requires it of a spot light */
        cJSON_AddObjectToObject(light, "spot");
    if (angle)
        cJSON_AddItemToObject(cJSON_AddObjectToObject(light, "extras"), "angular_diameter_deg", angle);
    cJSON *root = cJSON_GetObjectItem(g, "extensions");
    if (!root)
        cJSON_AddItemToArray(cJSON_AddArrayToObject(cJSON_AddObjectToObject(cJSON_AddObjectToObject(g, "extensions"),
                                                                            ext), "lights"), light);
    else
        cJSON_Delete(light);
    cJSON_AddNumberToObject(cJSON_AddObjectToObject(cJSON_AddObjectToObject(at(g, "nodes", node), "extensions"), ext),
                            "light", 0);
}
static void sun(cJSON *g) { put_sun(g, 2, "directional", cJSON_CreateNumber(0.53)); }
static void sun_no_angle(cJSON *g) { put_sun(g, 2, "directional", NULL); }
static void sun_zero(cJSON *g) { put_sun(g, 2, "directional", cJSON_CreateNumber(0)); }
static void sun_negative(cJSON *g) { put_sun(g, 2, "directional", cJSON_CreateNumber(-1)); }
static void sun_too_wide(cJSON *g) { put_sun(g, 2, "directional", cJSON_CreateNumber(30.5)); }
static void sun_string(cJSON *g) { put_sun(g, 2, "directional", cJSON_CreateString("0.53")); }
static void point_light(cJSON *g) { put_sun(g, 2, "point", NULL); }
static void spot_light(cJSON *g) { put_sun(g, 2, "spot", NULL); }
static void two_suns(cJSON *g)
{
    put_sun(g, 2, "directional", cJSON_CreateNumber(0.53));
    put_sun(g, 1, "directional", NULL);  /* the same light again, at the camera's node */
}
static void sun_and_area(cJSON *g)
{
    cJSON *area = cJSON_Duplicate(cJSON_GetObjectItem(at(g, "nodes", 2), "extras"), 1);
    put_sun(g, 1, "directional", cJSON_CreateNumber(0.53));
    cJSON_AddItemToObject(at(g, "nodes", 2), "extras", area);
}
static void sun_unlisted(cJSON *g)
{
    sun(g);
    cJSON_DeleteItemFromObject(g, "extensionsUsed");
}

static void cycle(cJSON *g)
{
    cJSON_DeleteItemFromObject(g, "scenes");
    cJSON_DeleteItemFromObject(g, "scene");
    cJSON *a = cJSON_CreateObject(), *b = cJSON_CreateObject();
    cJSON_AddItemToObject(a, "children", cJSON_CreateIntArray((const int[]){4}, 1));
    cJSON_AddItemToObject(b, "children", cJSON_CreateIntArray((const int[]){3}, 1));
    cJSON_AddItemToArray(cJSON_GetObjectItem(g, "nodes"), a);
    cJSON_AddItemToArray(cJSON_GetObjectItem(g, "nodes"), b);
}
static void required_extension(cJSON *g)
{
    /* instancing would multiply the geometry; the decoded encodings come first */
    const char *const names[] = {"KHR_mesh_quantization", "EXT_mesh_gpu_instancing"};
    cJSON_AddItemToObject(g, "extensionsRequired", cJSON_CreateStringArray(names, 2));
}
static void scenes_object(cJSON *g) { cJSON_ReplaceItemInObject(g, "scenes", cJSON_CreateObject()); }
static void no_attributes(cJSON *g)
{
    cJSON *p = cJSON_CreateObject();
    cJSON_AddNumberToObject(p, "mode", 4);
    cJSON_AddItemToArray(cJSON_GetObjectItem(at(g, "meshes", 0), "primitives"), p);
}
static void denormal_yfov(cJSON *g) { cJSON_ReplaceItemInObject(perspective(g), "yfov", cJSON_CreateNumber(1e-45)); }

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
    case_mutated("no_light", no_light, "no light: need a node whose extras hold \"area_light\", or a "
                                       "KHR_lights_punctual directional light (the sun)");
    {   /* the sun in place of the area light loads */
        char *path = scene_with("sun", sun);
        char *load = util_printf("%s gt --scene %s --width 16 --height 16 --gt-samples 4 --no-cache -q "
                                 "--out %s/out >/dev/null", shadowbench, path, dir);
        CHECK(system(load) == 0, "a scene lit by the sun must load");
        free(load), free(path);
    }
    case_mutated("sun_no_angle", sun_no_angle, "sun (node 2): light 0 has no extras.angular_diameter_deg (the sun's "
                                               "angular diameter in degrees, e.g. 0.53)");
    case_mutated("sun_zero", sun_zero, "sun (node 2): angular_diameter_deg must be in (0, 30], got 0");
    case_mutated("sun_negative", sun_negative, "sun (node 2): angular_diameter_deg must be in (0, 30], got -1");
    case_mutated("sun_too_wide", sun_too_wide, "sun (node 2): angular_diameter_deg must be in (0, 30], got 30.5");
    case_mutated("sun_string", sun_string, "sun (node 2): angular_diameter_deg must be a number");
    case_mutated("point_light", point_light, "light 0 (node 2) is a point light: shadowbench measures an area light "
                                             "or the sun (a directional light)");
    case_mutated("spot_light", spot_light, "light 0 (node 2) is a spot light: shadowbench measures an area light "
                                           "or the sun (a directional light)");
    case_mutated("two_suns", two_suns, "two suns (nodes 1 and 2): a scene has one light");
    case_mutated("sun_and_area", sun_and_area, "two lights (an area light at node 2, a sun at node 1): a scene has "
                                               "one light");
    case_mutated("sun_unlisted", sun_unlisted, "the scene uses KHR_lights_punctual but does not list it in "
                                               "extensionsUsed (glTF requires it)");
    case_mutated("no_triangles", no_triangles, "no triangles");
    case_mutated("lines", lines,
                 "mesh 0 primitive 0 has mode 1 (LINES): only TRIANGLES (4) is supported");
    case_mutated("zero_size", zero_size, "area light (node 2): size must be positive, got [0, 1]");
    case_mutated("negative_radius", negative_radius,
                 "area light (node 2): radius must be positive, got -0.5");
    case_mutated("bad_shape", bad_shape,
                 "area light (node 2): \"shape\" must be \"rect\" or \"disk\", got \"sphere\"");

    case_mutated("huge_count", huge_count,
                 "malformed buffers: POSITION accessor 0 reads past the end of buffer view 0");
    case_mutated("wrapping_offset", wrapping_offset,
                 "malformed glTF: bufferViews[0].byteOffset must be a whole number in [0, 2^53]");
    case_mutated("short_stride", short_stride,
                 "malformed buffers: buffer view 0 has byteStride 4, less than the 12-byte elements of "
                 "POSITION accessor 0");
    case_mutated("two_parents", two_parents,
                 "malformed glTF: node 0 has more than one parent (glTF forbids it)");
    case_mutated("huge_light", huge_light,
                 "area light (node 2): size must be in [1e-06, 1e+08] as floats, got [5e+18, 1]");
    case_mutated("overflowing_light", overflowing_light,
                 "area light (node 2): size must be in [1e-06, 1e+08] as floats, got [1e+39, 1]");
    case_mutated("vanishing_light", vanishing_light,
                 "area light (node 2): size must be in [1e-06, 1e+08] as floats, got [1e-50, 1]");
    case_mutated("far_camera", far_camera,
                 "camera 0: its position (3e+18, 3, 3) lies beyond 1e+08 world units");
    case_mutated("pi_yfov", pi_yfov, "camera 0: yfov must be in [1e-4, pi) as a float, got 3.14159265358979");
    case_mutated("tiny_znear", tiny_znear, "camera 0: znear must be in [1e-06, 1e+08] as a float, got 1e-50");
    case_mutated("string_matrix", string_matrix, "malformed glTF: nodes[1].matrix must be 16 finite numbers of an affine transform (bottom row 0 0 0 1)");
    case_mutated("short_matrix", short_matrix, "malformed glTF: nodes[1].matrix must be 16 finite numbers of an affine transform (bottom row 0 0 0 1)");
    case_mutated("zero_rotation", zero_rotation,
                 "malformed glTF: nodes[0].rotation must be a unit quaternion (4 numbers)");
    case_mutated("string_mode", string_mode,
                 "malformed glTF: meshes[0].primitives[0].mode must be a number 0..6");
    case_mutated("twice_mode", twice_mode, "malformed JSON: the key \"mode\" appears twice in one object");
    case_mutated("huge_mesh", huge_mesh, "malformed glTF: nodes[0].mesh must be an index");
    case_mutated("no_yfov", no_yfov, "malformed glTF: cameras[0].perspective needs numbers yfov and znear");
    case_mutated("folder_uri", folder_uri, "malformed buffers: buffers[0].uri '.' is not a regular file");
    case_mutated("device_uri", device_uri, "malformed buffers: buffers[0].uri '../../dev/zero' is not a regular file");
    case_mutated("short_buffer", short_buffer, "malformed buffers: buffers[0] holds 48 bytes, its byteLength says 1048");
    case_mutated("overflowing_matrix", overflowing_matrix,
                 "node 1: its transform overflows a float (a value beyond 3.40282e+38)");
    case_mutated("no_asset", no_asset, "malformed glTF: needs \"asset\": {\"version\": \"2.0\"}");
    case_text("float_mode", "\"mode\":\t4", "\"mode\":\t1.0",
              "malformed glTF: meshes[0].primitives[0].mode is 1 in the file but was read as 4 (write whole "
              "numbers without a fraction or an exponent)");
    {   /* text after the document: where it starts */
        char *path = scene_with("trailing_text", NULL), *text;
        size_t size;
        util_read_file(path, &text, &size);
        while (size && strchr(" \t\r\n", text[size - 1]))
            size--;
        int line = 1;
        for (size_t i = 0; i < size; i++)
            line += text[i] == '\n';
        char *edited = util_printf("%.*s xyz", (int)size, text);
        util_write_file_atomic(path, edited, strlen(edited));
        char *problem = util_printf("malformed JSON at line %d (byte %zu): text after the document", line, size + 1);
        expect_error(path, problem);
        free(problem), free(edited), free(text), free(path);
    }
    case_mutated("cycle", cycle, "malformed glTF: node 3 is its own ancestor (a cycle)");
    case_mutated("short_positions", short_positions, "mesh 0 primitive 0: POSITION must be FLOAT VEC3");
    case_mutated("meshopt_garbage", meshopt_garbage, "malformed buffers: buffer view 0 (EXT_meshopt_compression) does "
                                                     "not decode (meshoptimizer's error -1)");
    case_mutated("meshopt_stride", meshopt_stride, "malformed glTF: buffer view 0 (EXT_meshopt_compression): byteStride "
                                                   "12 does not suit mode TRIANGLES");
    case_mutated("meshopt_partial", meshopt_partial, "malformed glTF: buffer view 0 (EXT_meshopt_compression): 4 "
                                                     "indices is not a whole number of triangles");
    case_mutated("meshopt_huge", meshopt_huge, "buffer view 0 (EXT_meshopt_compression): 2147483646 elements, more than "
                                               "a scene may hold (30000000)");
    case_mutated("meshopt_mode", meshopt_mode, "malformed glTF: buffer view 0 (EXT_meshopt_compression): mode must be "
                                               "ATTRIBUTES, TRIANGLES or INDICES, got \"POINTS\"");
    case_mutated("required_extension", required_extension,
                 "the scene requires the extension EXT_mesh_gpu_instancing, which shadowbench does not support");
    case_mutated("scenes_object", scenes_object, "malformed glTF: \"scenes\" must be an array");
    case_mutated("no_attributes", no_attributes,
                 "malformed glTF: meshes[0].primitives[1] needs \"attributes\" with a POSITION");
    case_mutated("denormal_yfov", denormal_yfov,
                 "camera 0: yfov must be in [1e-4, pi) as a float, got 9.9999999999999998e-46");
    case_mutated("missing_normal", missing_normal, "mesh 0 primitive 0: NORMAL accessor 9 does not exist");

    /* Not regular files: a FIFO would block a reader; /dev/null is a device. */
    char *fifo = util_printf("%s/fifo.gltf", dir);
    CHECK(mkfifo(fifo, 0600) == 0, "mkfifo %s", fifo);
    expect_error(fifo, "cannot open: not a regular file");
    free(fifo);
    expect_error("/dev/null", "cannot open: not a regular file");

    /* A buffer that is a FIFO: refused, not waited on. */
    char *fifo_bin = util_printf("%s/fifo.bin", dir);
    CHECK(mkfifo(fifo_bin, 0600) == 0, "mkfifo %s", fifo_bin);
    free(fifo_bin);
    case_mutated("fifo_uri", fifo_uri, "malformed buffers: buffers[0].uri 'fifo.bin' is not a regular file");
    /* The same FIFO behind percent-encoding, as tinygltf decodes it. */
    case_mutated("encoded_fifo_uri", encoded_fifo_uri,
                 "malformed buffers: buffers[0].uri 'fifo%2Ebin' is not a regular file");
    /* A key with a newline, twice: still one line. */
    case_text("newline_key", "\"asset\":\t{", "\"asset\":\t{\"x\\ny\": 1, \"x\\ny\": 2, ",
              "malformed JSON: the key \"x?y\" appears twice in one object");

    /* An image naming the FIFO: images are ignored, and never opened or
     * waited on; the scene loads. */
    char *img = scene_with("image_fifo", image_fifo);
    char *img_cmd = util_printf("timeout 60 %s gt --scene %s --width 16 --height 16 --gt-samples 1 --no-cache -q "
                                "--out %s/out >/dev/null", shadowbench, img, dir);
    CHECK(system(img_cmd) == 0, "a scene whose image is a FIFO must load, without waiting");
    free(img_cmd), free(img);

    /* An image naming a 4 GiB file (sparse): never read (tinygltf would read
     * it whole, then hand it to the image loader that ignores it). The
     * children's peak memory stays far below the file's size. */
    char *huge = util_printf("%s/huge.png", dir);
    FILE *f = fopen(huge, "wb");
    CHECK(f && ftruncate(fileno(f), (off_t)4 << 30) == 0, "a sparse %s", huge);
    if (f)
        fclose(f);
    img = scene_with("huge_image", huge_image);
    img_cmd = util_printf("%s gt --scene %s --width 16 --height 16 --gt-samples 1 --no-cache -q --out %s/out "
                          ">/dev/null", shadowbench, img, dir);
    CHECK(system(img_cmd) == 0, "a scene whose image is a 4 GiB file must load");
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    CHECK(ru.ru_maxrss < 1024 * 1024, "a child's peak memory was %ld KiB: the image was read", ru.ru_maxrss);
    remove(huge);
    free(img_cmd), free(img), free(huge);

    /* A buffer file longer than its byteLength: refused before it is read
     * (tinygltf reads it whole first); a uri starting with '/' is, as
     * tinygltf joins it, relative to the scene's folder. */
    case_mutated("long_uri", long_uri, "malformed buffers: buffers[0].uri 'long.bin' holds 2000 bytes, its byteLength says 48");
    case_mutated("rooted_uri", rooted_uri,
                 "malformed buffers: buffers[0].uri '/long.bin' holds 2000 bytes, its byteLength says 48");

    case_mutated("morph_targets", morph_targets, "mesh 0 primitive 0 has morph targets: shadowbench does not "
                 "deform meshes, so its geometry would differ from the file's");
    case_mutated("skinned", skinned, "nodes[0] has a skin or morph weights: shadowbench does not deform meshes, so "
                 "its geometry would differ from the file's");
    case_mutated("matrix_and_trs", matrix_and_trs, "malformed glTF: nodes[1] has both a matrix and "
                 "translation/rotation/scale (glTF allows one or the other)");
    case_mutated("projective", projective, "malformed glTF: nodes[1].matrix must be 16 finite numbers of an affine "
                 "transform (bottom row 0 0 0 1)");
    case_mutated("min_version", min_version, "the scene needs glTF 2.5 or later: shadowbench reads glTF 2.0");
    case_mutated("no_scenes", no_scenes, "malformed glTF: default scene 0 does not exist");
    case_mutated("camera_99", camera_99, "malformed glTF: node 0 names camera 99, which does not exist");
    case_mutated("texcoord_99", texcoord_99, "mesh 0 primitive 0: TEXCOORD_0 accessor 99 does not exist");
    case_mutated("strided_indices", strided_indices, "mesh 0 primitive 0: buffer view 1 of the indices has a "
                 "byteStride (glTF forbids it)");
    case_mutated("text_zfar", text_zfar, "malformed glTF: cameras[0].perspective.zfar must be a positive number");
    case_mutated("text_normalized", text_normalized, "malformed glTF: accessors[0].normalized must be true or false");
    case_mutated("number_description", number_description,
                 "malformed glTF: extras.shadowbench.description must be a string of UTF-8 text");
    case_mutated("number_name", number_name, "malformed glTF: nodes[0].name must be a string of UTF-8 text (what a "
                 "caster motion names)");
    case_mutated("motions_object", motions_object,
                 "malformed glTF: extras.shadowbench.motions must be an array of at most 16 strings");
    case_mutated("motions_number", motions_number,
                 "malformed glTF: extras.shadowbench.motions must hold strings of UTF-8 text, 1 to 200 bytes "
                 "(motions as `shadowbench stability --motion` takes them)");
    {   /* an escaped NUL would cut the text short where cJSON reads it */
        char *path = scene_with("nul_description", NULL), *text;
        size_t size;
        util_read_file(path, &text, &size);
        const char *at = strstr(text, "\"one triangle\"");
        char *edited = util_printf("%.*s\"one\\u0000triangle\"%s", (int)(at - text), text, at + 14);
        util_write_file_atomic(path, edited, strlen(edited));
        char *problem = util_printf("malformed JSON: a string holds \\u0000 (a NUL character) at byte %zu",
                                    (size_t)(at - text) + 4);
        expect_error(path, problem);
        free(problem), free(edited), free(text), free(path);
    }
    case_mutated("flat_light", flat_light, "area light (node 2): the node has a degenerate or mirrored transform "
                 "(a zero axis, or a negative scale)");
    case_mutated("mirrored_camera", mirrored_camera, "camera 0: its node has a degenerate or mirrored transform "
                 "(a zero axis, or a negative scale)");
    {
        struct mesh_builder big = {0};
        for (int i = 0; i < 1000; i++)
            mesh_add_triangle(&big, v3(-1, 0, -1), v3(1, 0, -1), v3(0, 0, 1));
        char *path = util_printf("%s/amplified.gltf", dir);
        write_valid(path, &big);
        mesh_free(&big);
        char *text;
        size_t size;
        util_read_file(path, &text, &size);
        cJSON *g = cJSON_Parse(text);
        free(text);
        amplified(g);
        char *out = cJSON_Print(g);
        util_write_file_atomic(path, out, strlen(out));
        cJSON_free(out), cJSON_Delete(g);
        expect_error(path, "the scene instantiates more than 10000000 triangles (shadowbench's limit; a mesh counts "
                           "once per node that uses it)");
        free(path);
    }
    {   /* nothing to score: gt says so and exits 1, no NaN noise floor */
        char *path = scene_with("camera_away", camera_away);
        char *away = util_printf("%s gt --scene %s --width 16 --height 16 --gt-samples 1 --no-cache --out %s/out",
                                 shadowbench, path, dir);
        struct strbuf err = {0}, out = {0};
        int status = run_cmd(away, &err, &out);
        char *want = util_printf("shadowbench: error: %s: no pixel to score: the camera sees no surface inside the "
                                 "light's frustum that sees the light above its horizon\n", path);
        CHECK(status == 1 && err.data && strstr(err.data, want) && !(out.data && strstr(out.data, "nan")),
              "gt on a scene with nothing to score: exit %d, %s", status, err.data);
        strbuf_free(&err), strbuf_free(&out);
        free(want), free(away), free(path);
    }

    /* A GLB whose JSON chunk is padded with NULs (the format pads with spaces). */
    {
        char *nul_glb = util_printf("%s/nul_padded.glb", dir);
        const char json[] = "{\"asset\":{\"version\":\"2.0\"}}\0\0";  /* 28 + 2 (+ the literal's own NUL) */
        char bytes[20 + 32] = {'g', 'l', 'T', 'F', 2, 0, 0, 0, 52, 0, 0, 0, 32, 0, 0, 0, 'J', 'S', 'O', 'N'};
        memcpy(bytes + 20, json, 30);
        memcpy(bytes + 50, "\0\0", 2);
        util_write_file_atomic(nul_glb, bytes, sizeof bytes);
        expect_error(nul_glb, "malformed GLB: its JSON chunk holds a NUL byte");
        free(nul_glb);
    }

    /* A GLB of another version. */
    char *glb = util_printf("%s/v1.glb", dir);
    const char header[20] = {'g', 'l', 'T', 'F', 1, 0, 0, 0, 20, 0, 0, 0, 0, 0, 0, 0, 'J', 'S', 'O', 'N'};
    util_write_file_atomic(glb, header, sizeof header);
    expect_error(glb, "GLB version 1: only version 2 is supported");
    free(glb);

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
