// glTF 2.0 -> struct scene (docs/design.md §4), the project's only C++: tinygltf
// parses, this file validates and flattens into world-space triangles and
// hands C a plain struct. Every problem is reported once, as
// "<file>: <problem>", and nothing partially loaded is returned.

#include <tiny_gltf.h>
#include <draco/compression/decode.h>
#include <meshoptimizer.h>

#include <cjson/cJSON.h>

#include <cerrno>
#include <sys/stat.h>
#include <cfloat>
#include <cstdint>
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <new>
#include <set>
#include <string>
#include <vector>

extern "C" {
#include "scene.h"
#include "base/log.h"
#include "base/util.h"
}

// The global operator new, replaced for one thing: the size of an
// allocation that fails, so that a scene too large for the memory at hand
// is one line saying how much was needed (scene_load) and a runtime error,
// not "malformed". It allocates and fails as the library's does (without a
// new-handler, which nothing here installs). Every plain, array and
// nothrow form is replaced, each delete freeing what its new allocated (a
// sanitizer's own forms would not match them); the aligned forms stay the
// library's, matched among themselves.
static thread_local std::size_t failed_allocation;

static void *allocate(std::size_t size)
{
    if (void *p = std::malloc(size ? size : 1))
        return p;
    failed_allocation = size;
    throw std::bad_alloc();
}

void *operator new(std::size_t size) { return allocate(size); }
void *operator new[](std::size_t size) { return allocate(size); }
void *operator new(std::size_t size, const std::nothrow_t &) noexcept { return std::malloc(size ? size : 1); }
void *operator new[](std::size_t size, const std::nothrow_t &) noexcept { return std::malloc(size ? size : 1); }
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"  // free is the match of the malloc above
void operator delete(void *p) noexcept { std::free(p); }
void operator delete[](void *p) noexcept { std::free(p); }
void operator delete(void *p, std::size_t) noexcept { std::free(p); }
void operator delete[](void *p, std::size_t) noexcept { std::free(p); }
void operator delete(void *p, const std::nothrow_t &) noexcept { std::free(p); }
void operator delete[](void *p, const std::nothrow_t &) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace {

struct load_error {
    std::string what;
};

[[noreturn]] void fail(const std::string &what) { throw load_error{what}; }

// The required extensions the loader decodes (docs/scene-format.md).
const char *const quantization_ext = "KHR_mesh_quantization", *const meshopt_ext = "EXT_meshopt_compression",
                  *const draco_ext = "KHR_draco_mesh_compression";
const char *const decoded_extensions[] = {quantization_ext, meshopt_ext, draco_ext};

std::string fmt(const char *f, ...) __attribute__((format(printf, 1, 2)));
std::string fmt(const char *f, ...)
{
    char buf[512];
    va_list ap;
    va_start(ap, f);
    vsnprintf(buf, sizeof buf, f, ap);
    va_end(ap);
    return buf;
}

const char *mode_name(int mode)
{
    static const char *const names[] = {"POINTS", "LINES", "LINE_LOOP", "LINE_STRIP",
                                        "TRIANGLES", "TRIANGLE_STRIP", "TRIANGLE_FAN"};
    return mode >= 0 && mode < 7 ? names[mode] : "unknown";
}

// Column-major 4x4 of a node: its matrix, or T * R * S.
struct mat4 node_local(const tinygltf::Node &n)
{
    struct mat4 m = m4_identity();
    if (n.matrix.size() == 16) {
        for (int i = 0; i < 16; i++)
            m.m[i] = (float)n.matrix[i];
        return m;
    }
    double q[4] = {0, 0, 0, 1}, s[3] = {1, 1, 1}, t[3] = {0, 0, 0};
    if (n.rotation.size() == 4)
        for (int i = 0; i < 4; i++) q[i] = n.rotation[i];
    if (n.scale.size() == 3)
        for (int i = 0; i < 3; i++) s[i] = n.scale[i];
    if (n.translation.size() == 3)
        for (int i = 0; i < 3; i++) t[i] = n.translation[i];
    double x = q[0], y = q[1], z = q[2], w = q[3];
    double r[9] = {1 - 2 * (y * y + z * z), 2 * (x * y + z * w), 2 * (x * z - y * w),
                   2 * (x * y - z * w), 1 - 2 * (x * x + z * z), 2 * (y * z + x * w),
                   2 * (x * z + y * w), 2 * (y * z - x * w), 1 - 2 * (x * x + y * y)};
    for (int c = 0; c < 3; c++)
        for (int row = 0; row < 3; row++)
            m.m[c * 4 + row] = (float)(r[c * 3 + row] * s[c]);
    for (int i = 0; i < 3; i++)
        m.m[12 + i] = (float)t[i];
    return m;
}

// Orthonormal frame of a node's world matrix (scale removed): origin and
// axes, z rebuilt first so that -z (the emit / look direction) is exact.
bool node_frame(struct mat4 m, struct vec3 *o, struct vec3 *x, struct vec3 *y, struct vec3 *z)
{
    struct vec3 cx = v3(m.m[0], m.m[1], m.m[2]), cz = v3(m.m[8], m.m[9], m.m[10]);
    *o = v3(m.m[12], m.m[13], m.m[14]);
    *z = v3_normalize(cz);
    *x = v3_normalize(v3_sub(cx, v3_scale(*z, v3_dot(cx, *z))));
    *y = v3_cross(*z, *x);
    // The node's own Y axis must agree: zero, or mirrored (a negative
    // determinant), it would be replaced here without a word.
    const struct vec3 cy = v3(m.m[4], m.m[5], m.m[6]);
    return std::isfinite(v3_dot(*x, *x) + v3_dot(*z, *z) + v3_dot(*o, *o) + v3_dot(cy, cy)) &&
           v3_length(*x) > 0.5f && v3_length(*z) > 0.5f && v3_dot(cy, *y) > 1e-6f * v3_length(cy) &&
           v3_length(cy) > 0;
}

class loader {
public:
    loader(const tinygltf::Model &model, const std::map<std::pair<int, int>, int> &draco_indices)
        : m(model), draco_indices(draco_indices) {}

    std::vector<float> pos, nrm;
    std::vector<uint32_t> idx;
    struct node_range { std::string name; size_t first_vertex, vertex_count; };
    std::vector<node_range> ranges;  // every node with vertices under it
    bool have_camera = false, have_light = false;
    int area_node = -1, sun_node = -1;  // the first node of each kind of light
    struct scene_camera camera = {};
    struct scene_light light = {};

    void run()
    {
        std::vector<int> roots;
        if (!m.scenes.empty()) {
            int si = m.defaultScene >= 0 ? m.defaultScene : 0;
            if (si >= (int)m.scenes.size())
                fail(fmt("malformed glTF: default scene %d does not exist", si));
            roots = m.scenes[si].nodes;
        } else {  // no scenes: every node that is nobody's child is a root
            if (m.defaultScene >= 0)
                fail(fmt("malformed glTF: default scene %d does not exist", m.defaultScene));
            std::vector<bool> child(m.nodes.size());
            for (const auto &n : m.nodes)
                for (int c : n.children)
                    if (c >= 0 && c < (int)child.size()) child[c] = true;
            for (size_t i = 0; i < child.size(); i++)
                if (!child[i]) roots.push_back((int)i);
        }
        // glTF: a node has at most one parent, and a scene lists roots, each
        // once. A node reached twice would be traversed twice, and a chain
        // of double children exponentially often.
        std::vector<int> parents(m.nodes.size());
        for (size_t i = 0; i < m.nodes.size(); i++)
            for (int c : m.nodes[i].children) {
                if (c < 0 || c >= (int)m.nodes.size())
                    fail(fmt("malformed glTF: node %zu names child %d, which does not exist", i, c));
                if (++parents[c] > 1)
                    fail(fmt("malformed glTF: node %d has more than one parent (glTF forbids it)", c));
            }
        // With one parent each, a node whose chain of parents comes back to
        // it is on a cycle (unreachable from any root, so never visited).
        // Each node's chain is walked once: a walk stops at a node an
        // earlier walk finished, and a node seen twice in one walk closes a
        // cycle.
        std::vector<int> parent(m.nodes.size(), -1), walk(m.nodes.size(), -1);
        for (size_t i = 0; i < m.nodes.size(); i++)
            for (int c : m.nodes[i].children)
                parent[c] = (int)i;
        for (size_t i = 0; i < m.nodes.size(); i++) {
            for (int p = (int)i; p >= 0 && walk[p] != -2; p = parent[p]) {
                if (walk[p] == (int)i)
                    fail(fmt("malformed glTF: node %d is its own ancestor (a cycle)", p));
                walk[p] = (int)i;
            }
            for (int p = (int)i; p >= 0 && walk[p] == (int)i; p = parent[p])
                walk[p] = -2;  // finished: no cycle above it
        }
        std::vector<bool> listed(m.nodes.size());
        for (int r : roots) {
            if (r < 0 || r >= (int)m.nodes.size())
                fail(fmt("malformed glTF: node %d does not exist", r));
            if (listed[r] || parents[r])
                fail(fmt("malformed glTF: node %d is listed as a root %s", r,
                         listed[r] ? "twice" : "but has a parent"));
            listed[r] = true;
        }
        // A mesh counts once per node that uses it: a small file can name
        // far more geometry than it holds. Counted before any is made.
        size_t triangles = 0;
        for (int r : roots)
            count(r, 0, &triangles);
        for (int r : roots)
            visit(r, m4_identity(), 0);
    }

private:
    const tinygltf::Model &m;
    const std::map<std::pair<int, int>, int> &draco_indices;  // take_draco_indices

    // A light's size: positive and below the coordinates' limit, as a float.
    static bool usable_length(float v) { return v >= SCENE_MIN_LENGTH && v <= SCENE_MAX_COORD; }

    static void check_position(struct vec3 p, const std::string &what)
    {
        if (!(fabsf(p.x) <= SCENE_MAX_COORD && fabsf(p.y) <= SCENE_MAX_COORD && fabsf(p.z) <= SCENE_MAX_COORD))
            fail(fmt("%s: its position (%g, %g, %g) lies beyond %g world units", what.c_str(), (double)p.x,
                     (double)p.y, (double)p.z, (double)SCENE_MAX_COORD));
    }

    void count(int ni, int depth, size_t *triangles)
    {
        if (depth > 64)
            fail(fmt("node %d is nested more than 64 deep (shadowbench's limit)", ni));
        const tinygltf::Node &n = m.nodes[ni];
        if (n.mesh >= 0 && n.mesh < (int)m.meshes.size())
            for (const auto &p : m.meshes[n.mesh].primitives) {
                auto pa = p.attributes.find("POSITION");
                const auto draco = draco_indices.find({n.mesh, (int)(&p - m.meshes[n.mesh].primitives.data())});
                const int ai = draco != draco_indices.end() ? draco->second  // taken out for tinygltf
                               : p.indices >= 0 ? p.indices : pa != p.attributes.end() ? pa->second : -1;
                if (ai >= 0 && ai < (int)m.accessors.size() &&
                    (*triangles += m.accessors[ai].count / 3) > SCENE_MAX_TRIANGLES)
                    fail(fmt("the scene instantiates more than %d triangles (shadowbench's limit; a mesh counts "
                             "once per node that uses it)", SCENE_MAX_TRIANGLES));
            }
        for (int c : n.children)
            count(c, depth + 1, triangles);
    }

    void visit(int ni, struct mat4 parent, int depth)
    {
        if (ni < 0 || ni >= (int)m.nodes.size())
            fail(fmt("malformed glTF: node %d does not exist", ni));
        if (depth > 64)
            fail(fmt("node %d is nested more than 64 deep (shadowbench's limit)", ni));
        const tinygltf::Node &n = m.nodes[ni];
        struct mat4 world = m4_mul(parent, node_local(n));
        for (int i = 0; i < 16; i++)
            if (!std::isfinite(world.m[i]))
                fail(fmt("node %d: its transform overflows a float (a value beyond %g)", ni, (double)FLT_MAX));
        if (n.camera >= (int)m.cameras.size())
            fail(fmt("malformed glTF: node %d names camera %d, which does not exist", ni, n.camera));
        if (n.camera >= 0 && !have_camera)
            take_camera(n.camera, world);
        if (n.extras.IsObject() && n.extras.Has("area_light")) {
            if (sun_node >= 0)
                two_lights(ni, sun_node);
            if (!have_light)
                take_light(ni, n.extras.Get("area_light"), world);
            if (area_node < 0)
                area_node = ni;
        }
        auto punctual = n.extensions.find("KHR_lights_punctual");
        if (punctual != n.extensions.end())
            take_sun(ni, punctual->second, world);
        const size_t first_vertex = pos.size() / 3;
        if (n.mesh >= 0) {
            if (n.mesh >= (int)m.meshes.size())
                fail(fmt("malformed glTF: node %d names mesh %d, which does not exist", ni, n.mesh));
            const tinygltf::Mesh &mesh = m.meshes[n.mesh];
            for (size_t p = 0; p < mesh.primitives.size(); p++)
                take_primitive(n.mesh, (int)p, mesh.primitives[p], world);
        }
        for (int c : n.children)
            visit(c, world, depth + 1);
        // A node's vertices and its descendants' are contiguous: it is
        // visited once (one parent, each root listed once).
        if (pos.size() / 3 > first_vertex)
            ranges.push_back({n.name, first_vertex, pos.size() / 3 - first_vertex});
    }

    void take_camera(int ci, struct mat4 world)
    {
        if (ci >= (int)m.cameras.size())
            fail(fmt("malformed glTF: camera %d does not exist", ci));
        const tinygltf::Camera &c = m.cameras[ci];
        if (c.type != "perspective")
            fail(fmt("camera %d is %s: only perspective cameras are supported", ci,
                     c.type.empty() ? "untyped" : c.type.c_str()));
        // Checked as the floats they become.
        const float yfov = (float)c.perspective.yfov, znear = (float)c.perspective.znear;
        if (!(yfov >= 1e-4f && yfov < (float)M_PI))
            fail(fmt("camera %d: yfov must be in [1e-4, pi) as a float, got %.17g", ci, c.perspective.yfov));
        if (!(znear >= SCENE_MIN_LENGTH && znear <= SCENE_MAX_COORD))
            fail(fmt("camera %d: znear must be in [%g, %g] as a float, got %g", ci, (double)SCENE_MIN_LENGTH,
                     (double)SCENE_MAX_COORD, c.perspective.znear));
        check_position(v3(world.m[12], world.m[13], world.m[14]), fmt("camera %d", ci));
        if (!node_frame(world, &camera.pos, &camera.x, &camera.y, &camera.z))
            fail(fmt("camera %d: its node has a degenerate or mirrored transform (a zero axis, or a negative "
                     "scale)", ci));
        camera.yfov_rad = yfov;
        camera.znear = znear;
        have_camera = true;
    }

    void take_light(int ni, const tinygltf::Value &l, struct mat4 world)
    {
        const char *where = "area light";
        const char *rect = light_shape_names[LIGHT_RECT], *disk = light_shape_names[LIGHT_DISK];
        if (!l.IsObject() || !l.Has("shape") || !l.Get("shape").IsString())
            fail(fmt("%s (node %d): \"shape\" must be \"%s\" or \"%s\"", where, ni, rect, disk));
        std::string shape = l.Get("shape").Get<std::string>();
        if (shape == rect) {
            const tinygltf::Value &s = l.Get("size");
            if (!s.IsArray() || s.ArrayLen() != 2 || !s.Get(0).IsNumber() || !s.Get(1).IsNumber())
                fail(fmt("%s (node %d): \"size\" must be an array of two numbers", where, ni));
            double w = s.Get(0).GetNumberAsDouble(), h = s.Get(1).GetNumberAsDouble();
            if (!(w > 0 && h > 0))
                fail(fmt("%s (node %d): size must be positive, got [%g, %g]", where, ni, w, h));
            if (!usable_length((float)w) || !usable_length((float)h))
                fail(fmt("%s (node %d): size must be in [%g, %g] as floats, got [%g, %g]", where, ni,
                         (double)SCENE_MIN_LENGTH, (double)SCENE_MAX_COORD, w, h));
            light.shape = LIGHT_RECT;
            light.width = (float)w;
            light.height = (float)h;
        } else if (shape == disk) {
            const tinygltf::Value &r = l.Get("radius");
            if (!r.IsNumber())
                fail(fmt("%s (node %d): \"radius\" must be a number", where, ni));
            double rad = r.GetNumberAsDouble();
            if (!(rad > 0))
                fail(fmt("%s (node %d): radius must be positive, got %g", where, ni, rad));
            if (!usable_length((float)rad))
                fail(fmt("%s (node %d): radius must be in [%g, %g] as a float, got %g", where, ni,
                         (double)SCENE_MIN_LENGTH, (double)SCENE_MAX_COORD, rad));
            light.shape = LIGHT_DISK;
            light.radius = (float)rad;
            light.width = light.height = (float)(2 * rad);
        } else {
            std::string shown = shape.substr(0, 64);  // a NUL inside would cut it short
            std::replace(shown.begin(), shown.end(), '\0', '?');
            fail(fmt("%s (node %d): \"shape\" must be \"%s\" or \"%s\", got \"%s\"", where, ni,
                     rect, disk, shown.c_str()));
        }
        check_position(v3(world.m[12], world.m[13], world.m[14]), fmt("%s (node %d)", where, ni));
        if (!node_frame(world, &light.pos, &light.x, &light.y, &light.z))
            fail(fmt("%s (node %d): the node has a degenerate or mirrored transform (a zero axis, or a negative "
                     "scale)", where, ni));
        have_light = true;
    }

    // The sun (docs/design.md §4): a KHR_lights_punctual directional light
    // with extras.angular_diameter_deg, shining along the node's local -Z.
    // The only light then: one sun, no area light.
    void take_sun(int ni, const tinygltf::Value &e, struct mat4 world)
    {
        if (!e.IsObject() || !e.Has("light") || !e.Get("light").IsInt())
            fail(fmt("malformed glTF: nodes[%d].extensions.KHR_lights_punctual.light must be an index", ni));
        const int li = e.Get("light").Get<int>();
        if (li < 0 || li >= (int)m.lights.size())
            fail(fmt("malformed glTF: node %d names light %d, which does not exist", ni, li));
        const tinygltf::Light &l = m.lights[li];
        if (l.type != "directional")
            fail(fmt("light %d (node %d) is a %.32s light: shadowbench measures an area light or the sun (a "
                     "directional light)", li, ni, l.type.c_str()));
        if (sun_node >= 0)
            fail(fmt("two suns (nodes %d and %d): a scene has one light", sun_node, ni));
        if (area_node >= 0)
            two_lights(area_node, ni);
        const tinygltf::Value &x = l.extras;
        if (!x.IsObject() || !x.Has("angular_diameter_deg"))
            fail(fmt("sun (node %d): light %d has no extras.angular_diameter_deg (the sun's angular diameter in "
                     "degrees, e.g. 0.53)", ni, li));
        const tinygltf::Value &a = x.Get("angular_diameter_deg");
        if (!a.IsNumber())
            fail(fmt("sun (node %d): angular_diameter_deg must be a number", ni));
        const double deg = a.GetNumberAsDouble();
        if (!(deg > 0 && deg <= 30))
            fail(fmt("sun (node %d): angular_diameter_deg must be in (0, 30], got %g", ni, deg));
        check_position(v3(world.m[12], world.m[13], world.m[14]), fmt("sun (node %d)", ni));
        struct scene_light sun = {};
        if (!node_frame(world, &sun.pos, &sun.x, &sun.y, &sun.z))
            fail(fmt("sun (node %d): the node has a degenerate or mirrored transform (a zero axis, or a negative "
                     "scale)", ni));
        sun.shape = LIGHT_SUN;
        sun.half_angle = (float)(0.5 * deg * M_PI / 180);
        light = sun;
        have_light = true;
        sun_node = ni;
    }

    [[noreturn]] static void two_lights(int area, int sun)
    {
        fail(fmt("two lights (an area light at node %d, a sun at node %d): a scene has one light", area, sun));
    }

    // Bounds-checked view of an accessor's elements.
    struct span {
        const unsigned char *base;
        size_t stride, count;
    };
    struct bytes {
        const unsigned char *data;
        size_t size;
    };

    std::map<int, std::vector<unsigned char>> decoded;  // EXT_meshopt_compression's views, by index

    // The bytes of buffer view `view`, bounds-checked: its buffer's, or
    // what its EXT_meshopt_compression data decodes to.
    bytes view_bytes(int view)
    {
        const tinygltf::BufferView &bv = m.bufferViews[view];
        auto ext = bv.extensions.find(meshopt_ext);
        if (ext != bv.extensions.end())
            return meshopt_view(view, ext->second);
        if (bv.buffer < 0 || bv.buffer >= (int)m.buffers.size())
            fail(fmt("malformed buffers: buffer view %d names buffer %d, which does not exist", view, bv.buffer));
        const tinygltf::Buffer &b = m.buffers[bv.buffer];
        size_t view_end;  // every sum and product checked: a wrapped one would pass the bound
        if (__builtin_add_overflow(bv.byteOffset, bv.byteLength, &view_end) || view_end > b.data.size())
            fail(fmt("malformed buffers: buffer view %d (offset %zu, %zu bytes) reaches past the end of "
                     "buffer %d (%zu bytes)", view, bv.byteOffset, bv.byteLength, bv.buffer, b.data.size()));
        return bytes{b.data.data() + bv.byteOffset, bv.byteLength};
    }

    // A buffer view of EXT_meshopt_compression: count elements of byteStride
    // bytes in mode ATTRIBUTES (vertices), TRIANGLES or INDICES, decoded by
    // meshoptimizer from byteLength bytes at byteOffset of buffer, then its
    // filter undone; decoded once.
    bytes meshopt_view(int view, const tinygltf::Value &e)
    {
        auto done = decoded.find(view);
        if (done != decoded.end())
            return bytes{done->second.data(), done->second.size()};
        const std::string where = fmt("buffer view %d (%s)", view, meshopt_ext);
        if (!e.IsObject())
            fail(fmt("malformed glTF: %s must be an object", where.c_str()));
        auto whole = [&](const char *key, bool required) {
            if (!e.Has(key)) {
                if (required)
                    fail(fmt("malformed glTF: %s needs %s", where.c_str(), key));
                return 0.0;
            }
            const tinygltf::Value &v = e.Get(key);
            const double x = v.IsNumber() ? v.GetNumberAsDouble() : -1;
            if (!(x >= 0 && x <= 0x7fffffff && x == floor(x)))
                fail(fmt("malformed glTF: %s: %s must be a whole number below 2^31", where.c_str(), key));
            return x;
        };
        auto word = [&](const char *key, const char *absent) {
            if (!e.Has(key) && absent)
                return std::string(absent);
            if (!e.Get(key).IsString())
                fail(fmt("malformed glTF: %s: %s must be a string", where.c_str(), key));
            return e.Get(key).Get<std::string>().substr(0, 32);
        };
        const int buffer = (int)whole("buffer", true);
        const size_t offset = (size_t)whole("byteOffset", false), length = (size_t)whole("byteLength", true);
        const size_t stride = (size_t)whole("byteStride", true), count = (size_t)whole("count", true);
        const std::string mode = word("mode", nullptr), filter = word("filter", "NONE");
        if (buffer >= (int)m.buffers.size())
            fail(fmt("malformed buffers: %s names buffer %d, which does not exist", where.c_str(), buffer));
        const tinygltf::Buffer &b = m.buffers[buffer];
        if (offset + length > b.data.size())
            fail(fmt("malformed buffers: %s: its %zu bytes at %zu reach past the end of buffer %d (%zu bytes)",
                     where.c_str(), length, offset, buffer, b.data.size()));
        const bool vertices = mode == "ATTRIBUTES";
        if (!vertices && mode != "TRIANGLES" && mode != "INDICES")
            fail(fmt("malformed glTF: %s: mode must be ATTRIBUTES, TRIANGLES or INDICES, got \"%s\"", where.c_str(),
                     mode.c_str()));
        if (vertices ? stride == 0 || stride > 256 || stride % 4 : stride != 2 && stride != 4)
            fail(fmt("malformed glTF: %s: byteStride %zu does not suit mode %s", where.c_str(), stride, mode.c_str()));
        if (count > 3 * (size_t)SCENE_MAX_TRIANGLES)  // before anything is allocated for it
            fail(fmt("%s: %zu elements, more than a scene may hold (%d)", where.c_str(), count,
                     3 * SCENE_MAX_TRIANGLES));
        if (mode == "TRIANGLES" && count % 3)
            fail(fmt("malformed glTF: %s: %zu indices is not a whole number of triangles", where.c_str(), count));
        if ((double)count * (double)stride != (double)m.bufferViews[view].byteLength)
            fail(fmt("malformed buffers: %s decodes to %zu x %zu bytes, not the view's byteLength %zu", where.c_str(),
                     count, stride, m.bufferViews[view].byteLength));
        std::vector<unsigned char> out(count * stride);
        const unsigned char *src = b.data.data() + offset;
        const int rc = vertices ? meshopt_decodeVertexBuffer(out.data(), count, stride, src, length)
                       : mode == "TRIANGLES" ? meshopt_decodeIndexBuffer(out.data(), count, stride, src, length)
                                             : meshopt_decodeIndexSequence(out.data(), count, stride, src, length);
        if (rc != 0)
            fail(fmt("malformed buffers: %s does not decode (meshoptimizer's error %d)", where.c_str(), rc));
        const bool octahedral = filter == "OCTAHEDRAL", quaternion = filter == "QUATERNION",
                   exponential = filter == "EXPONENTIAL";
        if (filter != "NONE" && !(vertices && ((octahedral && (stride == 4 || stride == 8)) ||
                                               (quaternion && stride == 8) || exponential)))
            fail(fmt("malformed glTF: %s: filter \"%s\" does not suit mode %s and byteStride %zu", where.c_str(),
                     filter.c_str(), mode.c_str(), stride));
        if (octahedral)
            meshopt_decodeFilterOct(out.data(), count, stride);
        else if (quaternion)
            meshopt_decodeFilterQuat(out.data(), count, stride);
        else if (exponential)
            meshopt_decodeFilterExp(out.data(), count, stride);
        std::vector<unsigned char> &kept = decoded[view] = std::move(out);
        return bytes{kept.data(), kept.size()};
    }

    span accessor_span(int ai, const char *what, int mi, int pi, size_t elem_size)
    {
        if (ai < 0 || ai >= (int)m.accessors.size())
            fail(fmt("mesh %d primitive %d: %s accessor %d does not exist", mi, pi, what, ai));
        const tinygltf::Accessor &a = m.accessors[ai];
        if (a.sparse.isSparse)
            fail(fmt("mesh %d primitive %d: %s accessor %d is sparse, which is not supported", mi, pi,
                     what, ai));
        if (a.bufferView < 0 || a.bufferView >= (int)m.bufferViews.size())
            fail(fmt("mesh %d primitive %d: %s accessor %d has no buffer view", mi, pi, what, ai));
        const tinygltf::BufferView &bv = m.bufferViews[a.bufferView];
        const bytes view = view_bytes(a.bufferView);
        if (bv.byteStride && bv.byteStride < elem_size)
            fail(fmt("malformed buffers: buffer view %d has byteStride %zu, less than the %zu-byte "
                     "elements of %s accessor %d", a.bufferView, bv.byteStride, elem_size, what, ai));
        size_t stride = bv.byteStride ? bv.byteStride : elem_size, end = 0;
        if (a.count && (__builtin_mul_overflow(stride, a.count - 1, &end) ||
                        __builtin_add_overflow(end, a.byteOffset, &end) ||
                        __builtin_add_overflow(end, elem_size, &end)))
            end = SIZE_MAX;
        if (end > view.size)
            fail(fmt("malformed buffers: %s accessor %d reads past the end of buffer view %d", what,
                     ai, a.bufferView));
        return span{view.data + a.byteOffset, stride, a.count};
    }

    bool uses(const char *extension) const
    {
        return std::find(m.extensionsUsed.begin(), m.extensionsUsed.end(), extension) != m.extensionsUsed.end();
    }

    // A VEC3 attribute as floats: FLOAT, or with KHR_mesh_quantization the
    // integer types it allows (normalized: divided by the type's largest
    // value, -1 at least; or as they are), which the node's transform takes
    // back to the mesh's size. out: 3 floats per element.
    void read_vec3(int ai, const char *what, int mi, int pi, std::vector<float> &out)
    {
        const tinygltf::Accessor &a = m.accessors.at(ai);
        const int c = a.componentType;
        const size_t size = c == TINYGLTF_COMPONENT_TYPE_FLOAT ? 4
                            : c == TINYGLTF_COMPONENT_TYPE_BYTE || c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE ? 1
                            : c == TINYGLTF_COMPONENT_TYPE_SHORT || c == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                                                                                                               : 0;
        if (a.type != TINYGLTF_TYPE_VEC3 || !size || (size < 4 && !uses(quantization_ext)))
            fail(fmt("mesh %d primitive %d: %s must be FLOAT VEC3", mi, pi, what));
        const span s = accessor_span(ai, what, mi, pi, 3 * size);
        out.resize(3 * s.count);
        for (size_t v = 0; v < s.count; v++)
            for (int k = 0; k < 3; k++) {
                const unsigned char *e = s.base + v * s.stride + k * size;
                float f;
                switch (c) {
                case TINYGLTF_COMPONENT_TYPE_FLOAT: memcpy(&f, e, 4); break;
                case TINYGLTF_COMPONENT_TYPE_BYTE: f = (float)(int8_t)e[0]; break;
                case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: f = (float)e[0]; break;
                case TINYGLTF_COMPONENT_TYPE_SHORT: f = (float)(int16_t)(e[0] | e[1] << 8); break;
                default: f = (float)(uint16_t)(e[0] | e[1] << 8); break;
                }
                if (a.normalized && size < 4) {  // glTF: max(c / (2^(b-1) - 1), -1), or c / (2^b - 1)
                    const bool is_signed = c == TINYGLTF_COMPONENT_TYPE_BYTE || c == TINYGLTF_COMPONENT_TYPE_SHORT;
                    f = std::max(f / (float)((is_signed ? 1u << (8 * size - 1) : 1u << 8 * size) - 1), -1.0f);
                }
                out[3 * v + k] = f;
            }
    }

    // A primitive as the file holds it, in the node's space: positions (and
    // normals, or none) 3 floats a vertex, indices 3 a triangle.
    struct primitive_data {
        std::vector<float> positions, normals;
        std::vector<uint32_t> indices;
    };

    void read_accessors(int mi, int pi, const tinygltf::Primitive &p, primitive_data &d)
    {
        read_vec3(p.attributes.at("POSITION"), "POSITION", mi, pi, d.positions);
        const size_t nv = d.positions.size() / 3;
        if (p.indices >= 0) {
            if (p.indices >= (int)m.accessors.size())
                fail(fmt("mesh %d primitive %d: index accessor %d does not exist", mi, pi, p.indices));
            const tinygltf::Accessor &a = m.accessors[p.indices];
            size_t es = a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                        : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                        : a.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                    : 0;
            if (!es || a.type != TINYGLTF_TYPE_SCALAR)
                fail(fmt("mesh %d primitive %d: indices must be unsigned SCALAR", mi, pi));
            const int view = a.bufferView;
            if (view >= 0 && view < (int)m.bufferViews.size() && m.bufferViews[view].byteStride)
                fail(fmt("mesh %d primitive %d: buffer view %d of the indices has a byteStride (glTF forbids it)",
                         mi, pi, view));
            span is = accessor_span(p.indices, "index", mi, pi, es);
            if (is.count % 3)
                fail(fmt("mesh %d primitive %d: %zu indices is not a whole number of triangles", mi,
                         pi, is.count));
            d.indices.resize(is.count);
            for (size_t i = 0; i < is.count; i++) {
                const unsigned char *e = is.base + i * is.stride;
                d.indices[i] = es == 1 ? e[0] : es == 2 ? (uint32_t)(e[0] | e[1] << 8)
                                                        : (uint32_t)e[0] | (uint32_t)e[1] << 8 |
                                                              (uint32_t)e[2] << 16 | (uint32_t)e[3] << 24;
            }
        } else {
            if (nv % 3)
                fail(fmt("mesh %d primitive %d: %zu vertices without indices is not a whole number "
                         "of triangles", mi, pi, nv));
            d.indices.resize(nv);
            for (size_t v = 0; v < nv; v++)
                d.indices[v] = (uint32_t)v;
        }
        auto na = p.attributes.find("NORMAL");
        if (na != p.attributes.end())
            read_vec3(na->second, "NORMAL", mi, pi, d.normals);
    }

    // A primitive of KHR_draco_mesh_compression: its bufferView decoded by
    // Draco, POSITION (and NORMAL) the attributes its ids name, as floats
    // (Draco undoes its own quantization), and the faces' corners.
    void read_draco(int mi, int pi, const tinygltf::Primitive &p, const tinygltf::Value &e, primitive_data &d)
    {
        const std::string where = fmt("mesh %d primitive %d (%s)", mi, pi, draco_ext);
        const tinygltf::Value &bv = e.Get("bufferView"), &ids = e.Get("attributes");
        if (!e.IsObject() || !bv.IsInt() || bv.Get<int>() < 0 || bv.Get<int>() >= (int)m.bufferViews.size())
            fail(fmt("malformed glTF: %s: bufferView must name a buffer view", where.c_str()));
        if (!ids.IsObject() || !ids.Has("POSITION") || !ids.Get("POSITION").IsInt())
            fail(fmt("malformed glTF: %s: attributes must give POSITION's id", where.c_str()));
        const bytes data = view_bytes(bv.Get<int>());
        draco::DecoderBuffer in;
        in.Init((const char *)data.data, data.size);
        draco::Decoder decoder;
        auto decoded_mesh = decoder.DecodeMeshFromBuffer(&in);
        if (!decoded_mesh.ok())
            fail(fmt("malformed buffers: %s does not decode: %.120s", where.c_str(),
                     decoded_mesh.status().error_msg()));
        const draco::Mesh &mesh = *decoded_mesh.value();
        if (mesh.num_faces() > (uint32_t)SCENE_MAX_TRIANGLES)
            fail(fmt("%s: its data holds %u triangles, more than a scene may (%d)", where.c_str(), mesh.num_faces(),
                     SCENE_MAX_TRIANGLES));
        auto attribute = [&](const char *name, std::vector<float> &out) {
            const draco::PointAttribute *att = mesh.GetAttributeByUniqueId((uint32_t)ids.Get(name).Get<int>());
            if (!att || att->num_components() != 3)
                fail(fmt("malformed buffers: %s: its data has no 3-component attribute %d for %s", where.c_str(),
                         ids.Get(name).Get<int>(), name));
            const auto ai = p.attributes.find(name);
            if (ai != p.attributes.end() && m.accessors[ai->second].count != mesh.num_points())
                fail(fmt("malformed buffers: %s: %s accessor %d counts %zu, its data %u points", where.c_str(), name,
                         ai->second, m.accessors[ai->second].count, mesh.num_points()));
            out.resize(3 * (size_t)mesh.num_points());
            for (draco::PointIndex i(0); i < mesh.num_points(); ++i)
                if (!att->ConvertValue<float>(att->mapped_index(i), 3, &out[3 * i.value()]))
                    fail(fmt("malformed buffers: %s: %s of point %u does not convert", where.c_str(), name,
                             i.value()));
        };
        attribute("POSITION", d.positions);
        if (ids.Has("NORMAL") && ids.Get("NORMAL").IsInt())
            attribute("NORMAL", d.normals);
        const auto indices = draco_indices.find({mi, pi});
        if (indices != draco_indices.end() &&
            (indices->second >= (int)m.accessors.size() || m.accessors[indices->second].count != 3 * (size_t)mesh.num_faces()))
            fail(fmt("malformed buffers: %s: its data holds %u faces, not what index accessor %d counts", where.c_str(),
                     mesh.num_faces(), indices->second));
        d.indices.resize(3 * (size_t)mesh.num_faces());
        for (draco::FaceIndex f(0); f < mesh.num_faces(); ++f)
            for (int k = 0; k < 3; k++)
                d.indices[3 * f.value() + k] = mesh.face(f)[k].value();
    }

    void take_primitive(int mi, int pi, const tinygltf::Primitive &p, struct mat4 world)
    {
        if (p.mode != -1 && p.mode != TINYGLTF_MODE_TRIANGLES)
            fail(fmt("mesh %d primitive %d has mode %d (%s): only TRIANGLES (4) is supported", mi, pi,
                     p.mode, mode_name(p.mode)));
        auto pa = p.attributes.find("POSITION");
        if (pa == p.attributes.end())
            fail(fmt("mesh %d primitive %d has no POSITION attribute", mi, pi));
        if (pa->second < 0 || pa->second >= (int)m.accessors.size())
            fail(fmt("mesh %d primitive %d: POSITION accessor %d does not exist", mi, pi, pa->second));
        for (const auto &attribute : p.attributes)  // ignored ones too: the file must be whole
            if (attribute.second < 0 || attribute.second >= (int)m.accessors.size())
                fail(fmt("mesh %d primitive %d: %s accessor %d does not exist", mi, pi, attribute.first.c_str(),
                         attribute.second));
        if (!p.targets.empty())
            fail(fmt("mesh %d primitive %d has morph targets: shadowbench does not deform meshes, so its "
                     "geometry would differ from the file's", mi, pi));
        auto na = p.attributes.find("NORMAL");
        if (na != p.attributes.end() && (na->second < 0 || na->second >= (int)m.accessors.size()))
            fail(fmt("mesh %d primitive %d: NORMAL accessor %d does not exist", mi, pi, na->second));
        primitive_data d;
        auto draco = p.extensions.find(draco_ext);
        if (draco != p.extensions.end())
            read_draco(mi, pi, p, draco->second, d);
        else
            read_accessors(mi, pi, p, d);
        size_t base = pos.size() / 3, nv = d.positions.size() / 3;
        if (nv > 3 * (size_t)SCENE_MAX_TRIANGLES - base)  // vertices indexed by fewer triangles (count())
            fail(fmt("the scene instantiates more than %d vertices (shadowbench's limit; a mesh counts once per "
                     "node that uses it)", 3 * SCENE_MAX_TRIANGLES));

        for (size_t v = 0; v < nv; v++) {
            const float *f = &d.positions[3 * v];
            struct vec3 w = m4_point(world, v3(f[0], f[1], f[2]));
            if (!std::isfinite(w.x) || !std::isfinite(w.y) || !std::isfinite(w.z))
                fail(fmt("mesh %d primitive %d: vertex %zu is not finite", mi, pi, v));
            if (!(fabsf(w.x) <= SCENE_MAX_COORD && fabsf(w.y) <= SCENE_MAX_COORD && fabsf(w.z) <= SCENE_MAX_COORD))
                fail(fmt("mesh %d primitive %d: vertex %zu lies beyond %g world units (%g, %g, %g)", mi, pi,
                         v, (double)SCENE_MAX_COORD, (double)w.x, (double)w.y, (double)w.z));
            pos.insert(pos.end(), {w.x, w.y, w.z});
        }
        size_t first_index = idx.size();
        for (size_t i = 0; i < d.indices.size(); i++) {
            if (d.indices[i] >= nv)
                fail(fmt("mesh %d primitive %d: index %u at position %zu is out of range (%zu "
                         "vertices)", mi, pi, d.indices[i], i, nv));
            idx.push_back((uint32_t)base + d.indices[i]);
        }

        nrm.resize(pos.size(), 0.0f);
        if (!d.normals.empty()) {
            if (d.normals.size() != d.positions.size())
                fail(fmt("mesh %d primitive %d: NORMAL has %zu elements, POSITION %zu", mi, pi,
                         d.normals.size() / 3, nv));
            struct mat4 inv_t = normal_matrix(world);
            for (size_t v = 0; v < nv; v++) {
                const float *f = &d.normals[3 * v];
                struct vec3 n = v3_normalize(m4_vector(inv_t, v3(f[0], f[1], f[2])));
                if (!std::isfinite(n.x + n.y + n.z))
                    fail(fmt("mesh %d primitive %d: normal %zu is not finite", mi, pi, v));
                memcpy(&nrm[(base + v) * 3], &n, sizeof n);
            }
        } else {
            compute_normals(base, first_index);
        }
    }

    // Inverse transpose of the upper 3x3 (the cofactor matrix suffices up to
    // scale, and normals are renormalised).
    static struct mat4 normal_matrix(struct mat4 w)
    {
        struct vec3 a = v3(w.m[0], w.m[1], w.m[2]), b = v3(w.m[4], w.m[5], w.m[6]),
                    c = v3(w.m[8], w.m[9], w.m[10]);
        struct vec3 ca = v3_cross(b, c), cb = v3_cross(c, a), cc = v3_cross(a, b);
        struct mat4 r = m4_identity();
        float cols[3][3] = {{ca.x, ca.y, ca.z}, {cb.x, cb.y, cb.z}, {cc.x, cc.y, cc.z}};
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++)
                r.m[i * 4 + j] = cols[i][j];
        return r;
    }

    // Area-weighted vertex normals for a primitive without NORMAL.
    void compute_normals(size_t base, size_t first_index)
    {
        for (size_t i = first_index; i < idx.size(); i += 3) {
            struct vec3 p[3];
            for (int k = 0; k < 3; k++)
                memcpy(&p[k], &pos[idx[i + k] * 3], sizeof p[k]);
            struct vec3 n = v3_cross(v3_sub(p[1], p[0]), v3_sub(p[2], p[0]));
            for (int k = 0; k < 3; k++) {
                float *dst = &nrm[idx[i + k] * 3];
                dst[0] += n.x, dst[1] += n.y, dst[2] += n.z;
            }
        }
        for (size_t v = base; v < pos.size() / 3; v++) {
            struct vec3 n;
            memcpy(&n, &nrm[v * 3], sizeof n);
            n = v3_length(n) > 0 ? v3_normalize(n) : v3(0, 0, 1);  // isolated degenerate
            memcpy(&nrm[v * 3], &n, sizeof n);
        }
    }
};

// The files tinygltf may open: the buffers check_buffers resolved, by the
// path tinygltf's FindFile builds. An image's file is never opened (textures
// are ignored, docs/design.md §4): it is not found, which tinygltf only warns of.
struct buffer_files {
    std::set<std::string> paths;
};

// Through util_read_file: regular files only, never blocking on a FIFO or
// reading a device or a folder.
bool read_buffer_file(std::vector<unsigned char> *out, std::string *err, const std::string &path, void *files)
{
    if (!((buffer_files *)files)->paths.count(path)) {
        if (err)
            *err += path.substr(0, 200) + ": not a buffer of the scene\n";
        return false;
    }
    char *bytes = nullptr;
    size_t size = 0;
    int rc = util_read_file(path.c_str(), &bytes, &size);
    if (rc) {
        if (err)
            *err += path.substr(0, 200) + ": " + util_read_error(rc) + "\n";
        return false;
    }
    out->assign(bytes, bytes + size);
    free(bytes);
    return true;
}

// tinygltf's own FileExists opens the file, which blocks on a FIFO.
bool buffer_file_exists(const std::string &path, void *files)
{
    struct stat st;
    return ((buffer_files *)files)->paths.count(path) && stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

bool skip_images(tinygltf::Image *, const int, std::string *, std::string *, int, int,
                 const unsigned char *, int, void *)
{
    return true;  // textures are ignored (docs/design.md §4)
}

// An escaped NUL (\u0000) in the JSON text: cJSON and tinygltf would cut
// the string there, so what is read is not what the file says.
void check_no_nul_escape(const char *json, size_t size)
{
    for (size_t i = 0; i + 6 <= size; i++)
        if (json[i] == '\\' && json[i + 1] == 'u' && json[i + 2] == '0' && json[i + 3] == '0' &&
            json[i + 4] == '0' && json[i + 5] == '0') {
            size_t slashes = 0;  // an escape only after an odd run of backslashes
            while (slashes <= i && json[i - slashes] == '\\')
                slashes++;
            if (slashes % 2)
                fail(fmt("malformed JSON: a string holds \\u0000 (a NUL character) at byte %zu", i));
        }
}

// The first line of a parser's message, in printable ASCII (it may quote
// the file's own bytes).
std::string first_line(const std::string &s)
{
    size_t b = s.find_first_not_of(" \t\r\n");
    if (b == std::string::npos)
        return "unknown error";
    size_t e = s.find_first_of("\r\n", b);
    std::string line = s.substr(b, e == std::string::npos ? std::string::npos : e - b);
    for (char &c : line)
        if ((unsigned char)c < 32 || (unsigned char)c > 126)
            c = '?';
    return line;
}

std::string string_extra(const tinygltf::Value &v, const char *key)
{
    return v.IsObject() && v.Has(key) && v.Get(key).IsString() ? v.Get(key).Get<std::string>() : "";
}

// ---- the JSON's types, checked before tinygltf reads it: tinygltf puts a
// default in place of a value of the wrong type (a camera matrix of
// strings became the identity, "mode": "4" became triangles, a mesh index
// of 2^40 was truncated), and none of that may pass silently.

bool is_index(const cJSON *v)
{
    return cJSON_IsNumber(v) && v->valuedouble >= 0 && v->valuedouble <= INT32_MAX &&
           v->valuedouble == floor(v->valuedouble);
}

bool is_count(const cJSON *v)  // a byte count or offset: exact in a double
{
    return cJSON_IsNumber(v) && v->valuedouble >= 0 && v->valuedouble <= 9007199254740992.0 &&
           v->valuedouble == floor(v->valuedouble);
}

bool is_numbers(const cJSON *v, int n)
{
    if (!cJSON_IsArray(v) || cJSON_GetArraySize(v) != n)
        return false;
    const cJSON *e;
    cJSON_ArrayForEach(e, v) if (!cJSON_IsNumber(e) || !std::isfinite(e->valuedouble)) return false;
    return true;
}

// Each member `key` of every object in array `name` passes `ok`, where present.
void check_members(const cJSON *doc, const char *name, const char *key, bool (*ok)(const cJSON *),
                   const char *must)
{
    const cJSON *array = cJSON_GetObjectItemCaseSensitive(doc, name), *o;
    int i = 0;
    cJSON_ArrayForEach(o, array) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
        if (v && !ok(v))
            fail(fmt("malformed glTF: %s[%d].%s must be %s", name, i, key, must));
        i++;
    }
}

bool is_vec3(const cJSON *v) { return is_numbers(v, 3); }
// 16 finite numbers of an affine transform: glTF's matrices decompose into
// translation, rotation and scale, so the bottom row is 0 0 0 1 (column
// major: elements 3, 7, 11, 15).
bool is_matrix(const cJSON *v)
{
    if (!is_numbers(v, 16))
        return false;
    const cJSON *e = v->child;
    for (int i = 0; i < 16; i++, e = e->next)
        if (i % 4 == 3 && e->valuedouble != (i == 15 ? 1.0 : 0.0))
            return false;
    return true;
}
bool is_bool(const cJSON *v) { return cJSON_IsBool(v); }
bool is_number(const cJSON *v) { return cJSON_IsNumber(v) && std::isfinite(v->valuedouble); }
bool is_text(const cJSON *v) { return cJSON_IsString(v) && util_valid_utf8(v->valuestring); }
bool is_indices(const cJSON *v)
{
    if (!cJSON_IsArray(v))
        return false;
    const cJSON *e;
    cJSON_ArrayForEach(e, v) if (!is_index(e)) return false;
    return true;
}
bool is_unit_quaternion(const cJSON *v)
{
    if (!is_numbers(v, 4))
        return false;
    double len2 = 0;
    const cJSON *e;
    cJSON_ArrayForEach(e, v) len2 += e->valuedouble * e->valuedouble;
    return fabs(sqrt(len2) - 1.0) <= 1e-3;
}
bool is_mode(const cJSON *v) { return is_index(v) && v->valuedouble <= 6; }

// A uri as tinygltf decodes it before opening the file ('+' a space, %XX a
// byte, a bad hex digit 0), so that the file checked is the file read.
std::string uri_decoded(const char *uri)
{
    auto hex = [](char c) {
        return c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10 : c >= 'A' && c <= 'F' ? c - 'A' + 10 : 0;
    };
    std::string out;
    for (size_t i = 0, n = strlen(uri); i < n; i++) {
        if (uri[i] == '+') {
            out += ' ';
        } else if (uri[i] == '%' && n > i + 2) {
            out += (char)(hex(uri[i + 1]) << 4 | hex(uri[i + 2]));
            i += 2;
        } else {
            out += uri[i];
        }
    }
    return out;
}

// A buffer's uri: a base64 data URI that holds at least byteLength bytes,
// or a regular file of exactly byteLength bytes (tinygltf reads it whole,
// then compares) beside the scene, never a folder, a device, a FIFO. Returns
// the files' paths as tinygltf's FindFile joins them: every "/" uri too is
// relative to the scene's folder.
std::set<std::string> check_buffers(const cJSON *doc, const std::string &dir)
{
    std::set<std::string> files;
    const cJSON *buffers = cJSON_GetObjectItemCaseSensitive(doc, "buffers"), *b;
    int i = 0;
    cJSON_ArrayForEach(b, buffers) {
        const cJSON *uri = cJSON_GetObjectItemCaseSensitive(b, "uri");
        const cJSON *length = cJSON_GetObjectItemCaseSensitive(b, "byteLength");
        if (!is_count(length))
            fail(fmt("malformed glTF: buffers[%d].byteLength must be a whole number in [0, 2^53]", i));
        if (uri && !cJSON_IsString(uri))
            fail(fmt("malformed glTF: buffers[%d].uri must be a string", i));
        const char *u = uri ? uri->valuestring : nullptr;
        if (u && strncmp(u, "data:", 5) == 0) {
            const char *comma = strstr(u, ";base64,");
            if (!comma)
                fail(fmt("malformed buffers: buffers[%d].uri is a data URI that is not base64", i));
            const char *data = comma + 8;
            size_t n = strlen(data), pad = n >= 1 && data[n - 1] == '=' ? (n >= 2 && data[n - 2] == '=' ? 2 : 1) : 0;
            size_t bytes = n / 4 * 3 - pad;
            if (n % 4 || strspn(data, "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/=") != n)
                fail(fmt("malformed buffers: buffers[%d].uri: its base64 is malformed (%zu characters)", i, n));
            if ((double)bytes < length->valuedouble)
                fail(fmt("malformed buffers: buffers[%d] holds %zu bytes, its byteLength says %.0f", i, bytes,
                         length->valuedouble));
        } else if (u) {
            const std::string name = uri_decoded(u);
            if (name.find('\0') != std::string::npos)
                fail(fmt("malformed buffers: buffers[%d].uri '%.200s' decodes to a NUL byte", i, u));
            std::string path = dir.back() == '/' ? dir + name : dir + "/" + name;
            struct stat st;
            if (stat(path.c_str(), &st) != 0)
                fail(fmt("malformed buffers: buffers[%d].uri '%.200s': %s", i, u, strerror(errno)));
            if (!S_ISREG(st.st_mode))
                fail(fmt("malformed buffers: buffers[%d].uri '%.200s' is not a regular file", i, u));
            if ((double)st.st_size != length->valuedouble)
                fail(fmt("malformed buffers: buffers[%d].uri '%.200s' holds %lld bytes, its byteLength says %.0f", i,
                         u, (long long)st.st_size, length->valuedouble));
            files.insert(path);
        }
        i++;
    }
    return files;
}

void check_types(const cJSON *doc)
{
    if (!cJSON_IsObject(doc))
        fail("malformed glTF: the document is not a JSON object");
    // A key twice in one object: cJSON reads the first, tinygltf the last.
    // (cJSON itself refuses nesting deeper than CJSON_NESTING_LIMIT, 1000.)
    if (const char *twice = util_json_duplicate_key(doc))
        fail(fmt("malformed JSON: the key \"%.64s\" appears twice in one object", twice));
    static const char *const arrays[] = {"scenes", "nodes", "meshes", "accessors", "bufferViews", "buffers",
                                         "cameras", "extensionsRequired", "extensionsUsed"};
    for (const char *name : arrays) {
        const cJSON *a = cJSON_GetObjectItemCaseSensitive(doc, name);
        if (a && !cJSON_IsArray(a))
            fail(fmt("malformed glTF: \"%s\" must be an array", name));
    }
    // The geometry encodings that exporters write by default or on one
    // click (gltfpack, gltf-transform, Blender) are decoded; any other
    // required extension is refused.
    const cJSON *required;
    cJSON_ArrayForEach(required, cJSON_GetObjectItemCaseSensitive(doc, "extensionsRequired")) {
        const char *name = cJSON_IsString(required) ? required->valuestring : nullptr;
        bool known = false;
        for (const char *k : decoded_extensions)
            known = known || (name && strcmp(name, k) == 0);
        if (!known)
            fail(fmt("the scene requires the extension %.64s, which shadowbench does not support",
                     name ? name : "(not a name)"));
    }
    // glTF: every extension a file uses is listed in extensionsUsed.
    static const char punctual[] = "KHR_lights_punctual";
    bool uses = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(doc, "extensions"), punctual);
    const cJSON *n;
    cJSON_ArrayForEach(n, cJSON_GetObjectItemCaseSensitive(doc, "nodes"))
        uses = uses || cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(n, "extensions"), punctual);
    bool listed = false;
    const cJSON *used;
    cJSON_ArrayForEach(used, cJSON_GetObjectItemCaseSensitive(doc, "extensionsUsed"))
        listed = listed || (cJSON_IsString(used) && strcmp(used->valuestring, punctual) == 0);
    if (uses && !listed)
        fail(fmt("the scene uses %s but does not list it in extensionsUsed (glTF requires it)", punctual));
    const char *version =
        cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(doc, "asset"), "version"));
    if (!version || strncmp(version, "2.", 2) != 0)
        fail("malformed glTF: needs \"asset\": {\"version\": \"2.0\"}");
    const cJSON *scene = cJSON_GetObjectItemCaseSensitive(doc, "scene");
    if (scene && !is_index(scene))
        fail("malformed glTF: \"scene\" must be an index");
    const cJSON *cameras = cJSON_GetObjectItemCaseSensitive(doc, "cameras"), *camera;
    int ci = 0;
    cJSON_ArrayForEach(camera, cameras) {
        const char *type = cJSON_GetStringValue(cJSON_GetObjectItemCaseSensitive(camera, "type"));
        const cJSON *p = cJSON_GetObjectItemCaseSensitive(camera, "perspective");
        if (type && strcmp(type, "perspective") == 0 &&
            (!cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(p, "yfov")) ||
             !cJSON_IsNumber(cJSON_GetObjectItemCaseSensitive(p, "znear"))))
            fail(fmt("malformed glTF: cameras[%d].perspective needs numbers yfov and znear", ci));
        for (const char *key : {"zfar", "aspectRatio"}) {  // unused, but a wrong type is a wrong file
            const cJSON *v = cJSON_GetObjectItemCaseSensitive(p, key);
            if (v && !(is_number(v) && v->valuedouble > 0))
                fail(fmt("malformed glTF: cameras[%d].perspective.%s must be a positive number", ci, key));
        }
        ci++;
    }
    // Members of the top-level arrays' objects, where present: (array, key,
    // test, what it must be).
    static const struct {
        const char *array, *key;
        bool (*ok)(const cJSON *);
        const char *must;
    } members[] = {
        {"scenes", "nodes", is_indices, "an array of indices"},
        {"nodes", "children", is_indices, "an array of indices"},
        {"nodes", "mesh", is_index, "an index"},
        {"nodes", "camera", is_index, "an index"},
        {"nodes", "name", is_text, "a string of UTF-8 text (what a caster motion names)"},
        {"nodes", "matrix", is_matrix, "16 finite numbers of an affine transform (bottom row 0 0 0 1)"},
        {"nodes", "translation", is_vec3, "3 finite numbers"},
        {"nodes", "scale", is_vec3, "3 finite numbers"},
        {"nodes", "rotation", is_unit_quaternion, "a unit quaternion (4 numbers)"},
        {"accessors", "bufferView", is_index, "an index"},
        {"accessors", "byteOffset", is_count, "a whole number in [0, 2^53]"},
        {"accessors", "count", is_count, "a whole number in [0, 2^53]"},
        {"accessors", "componentType", is_index, "a component type"},
        {"accessors", "normalized", is_bool, "true or false"},
        {"bufferViews", "buffer", is_index, "an index"},
        {"bufferViews", "byteOffset", is_count, "a whole number in [0, 2^53]"},
        {"bufferViews", "byteLength", is_count, "a whole number in [0, 2^53]"},
        {"bufferViews", "byteStride", is_count, "a whole number in [0, 2^53]"},
    };
    for (const auto &c : members)
        check_members(doc, c.array, c.key, c.ok, c.must);
    const cJSON *node;
    int ni = 0;
    cJSON_ArrayForEach(node, cJSON_GetObjectItemCaseSensitive(doc, "nodes")) {
        const bool trs = cJSON_GetObjectItemCaseSensitive(node, "translation") ||
                         cJSON_GetObjectItemCaseSensitive(node, "rotation") ||
                         cJSON_GetObjectItemCaseSensitive(node, "scale");
        if (trs && cJSON_GetObjectItemCaseSensitive(node, "matrix"))
            fail(fmt("malformed glTF: nodes[%d] has both a matrix and translation/rotation/scale (glTF allows "
                     "one or the other)", ni));
        if (cJSON_GetObjectItemCaseSensitive(node, "skin") || cJSON_GetObjectItemCaseSensitive(node, "weights"))
            fail(fmt("nodes[%d] has a skin or morph weights: shadowbench does not deform meshes, so its geometry "
                     "would differ from the file's", ni));
        ni++;
    }
    const char *min_version = cJSON_GetStringValue(
        cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(doc, "asset"), "minVersion"));
    if (min_version && strcmp(min_version, "2.0") != 0)
        fail(fmt("the scene needs glTF %.16s or later: shadowbench reads glTF 2.0", min_version));
    // The scene's own text (docs/design.md §4): strings when present.
    const cJSON *meta = cJSON_GetObjectItemCaseSensitive(
        cJSON_GetObjectItemCaseSensitive(
            cJSON_GetArrayItem(cJSON_GetObjectItemCaseSensitive(doc, "scenes"),
                               scene ? (int)scene->valuedouble : 0),
            "extras"),
        "shadowbench");
    for (const char *key : {"description", "shows"}) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(meta, key);
        if (v && !is_text(v))
            fail(fmt("malformed glTF: extras.shadowbench.%s must be a string of UTF-8 text", key));
    }
    const cJSON *motions = cJSON_GetObjectItemCaseSensitive(meta, "motions"), *motion;
    if (motions && !(cJSON_IsArray(motions) && cJSON_GetArraySize(motions) <= SCENE_MAX_MOTIONS))
        fail(fmt("malformed glTF: extras.shadowbench.motions must be an array of at most %d strings",
                 SCENE_MAX_MOTIONS));
    cJSON_ArrayForEach(motion, motions)
        if (!is_text(motion) || !*motion->valuestring || strlen(motion->valuestring) > 200)
            fail("malformed glTF: extras.shadowbench.motions must hold strings of UTF-8 text, 1 to 200 bytes "
                 "(motions as `shadowbench stability --motion` takes them)");
    const cJSON *meshes = cJSON_GetObjectItemCaseSensitive(doc, "meshes"), *mesh;
    int mi = 0;
    cJSON_ArrayForEach(mesh, meshes) {
        const cJSON *prims = cJSON_GetObjectItemCaseSensitive(mesh, "primitives"), *p;
        int pi = 0;
        cJSON_ArrayForEach(p, prims) {
            const cJSON *mode = cJSON_GetObjectItemCaseSensitive(p, "mode");
            const cJSON *indices = cJSON_GetObjectItemCaseSensitive(p, "indices");
            const cJSON *attributes = cJSON_GetObjectItemCaseSensitive(p, "attributes"), *a;
            if (mode && !is_mode(mode))
                fail(fmt("malformed glTF: meshes[%d].primitives[%d].mode must be a number 0..6", mi, pi));
            if (indices && !is_index(indices))
                fail(fmt("malformed glTF: meshes[%d].primitives[%d].indices must be an index", mi, pi));
            if (!cJSON_IsObject(attributes) || !cJSON_GetObjectItemCaseSensitive(attributes, "POSITION"))
                fail(fmt("malformed glTF: meshes[%d].primitives[%d] needs \"attributes\" with a POSITION", mi, pi));
            cJSON_ArrayForEach(a, attributes) if (!is_index(a))
                fail(fmt("malformed glTF: meshes[%d].primitives[%d].attributes.%s must be an index", mi, pi,
                         a->string));
            pi++;
        }
        mi++;
    }
}

// tinygltf must have read each index, count and offset as the file writes
// it: it quietly puts its default in place of a value it does not take (a
// whole number written 1.0, for one), which the type checks above cannot
// see (cJSON reads 1.0 as 1).
void check_read_as_written(const cJSON *doc, const tinygltf::Model &m)
{
    auto same = [](const cJSON *o, const char *key, double read, const std::string &where) {
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(o, key);
        if (v && cJSON_IsNumber(v) && v->valuedouble != read)
            fail(fmt("malformed glTF: %s.%s is %.17g in the file but was read as %.17g (write whole numbers "
                     "without a fraction or an exponent)", where.c_str(), key, v->valuedouble, read));
    };
    auto same_list = [](const cJSON *o, const char *key, const std::vector<int> &read, const std::string &where) {
        const cJSON *a = cJSON_GetObjectItemCaseSensitive(o, key);
        if (!a)
            return;
        bool equal = cJSON_GetArraySize(a) == (int)read.size();
        size_t i = 0;
        for (const cJSON *e = a->child; equal && e; e = e->next, i++)  // the list once: not GetArrayItem
            equal = e->valuedouble == read[i];
        if (!equal)
            fail(fmt("malformed glTF: %s.%s was not read as written (write whole numbers without a fraction "
                     "or an exponent)", where.c_str(), key));
    };
    const cJSON *o;
    int i = 0;
    same(doc, "scene", m.defaultScene, "the document");
    cJSON_ArrayForEach(o, cJSON_GetObjectItemCaseSensitive(doc, "scenes")) {
        same_list(o, "nodes", m.scenes.at(i).nodes, fmt("scenes[%d]", i));
        i++;
    }
    i = 0;
    cJSON_ArrayForEach(o, cJSON_GetObjectItemCaseSensitive(doc, "nodes")) {
        const tinygltf::Node &n = m.nodes.at(i);
        const std::string where = fmt("nodes[%d]", i++);
        same(o, "mesh", n.mesh, where);
        same(o, "camera", n.camera, where);
        same_list(o, "children", n.children, where);
    }
    i = 0;
    cJSON_ArrayForEach(o, cJSON_GetObjectItemCaseSensitive(doc, "meshes")) {
        const cJSON *p;
        int k = 0;
        cJSON_ArrayForEach(p, cJSON_GetObjectItemCaseSensitive(o, "primitives")) {
            const tinygltf::Primitive &prim = m.meshes.at(i).primitives.at(k);
            const std::string where = fmt("meshes[%d].primitives[%d]", i, k++);
            same(p, "mode", prim.mode, where);
            same(p, "indices", prim.indices, where);
            const cJSON *a;
            cJSON_ArrayForEach(a, cJSON_GetObjectItemCaseSensitive(p, "attributes")) {
                auto it = prim.attributes.find(a->string);
                same(cJSON_GetObjectItemCaseSensitive(p, "attributes"), a->string,
                     it == prim.attributes.end() ? -1.0 : it->second, where + ".attributes");
            }
        }
        i++;
    }
    i = 0;
    cJSON_ArrayForEach(o, cJSON_GetObjectItemCaseSensitive(doc, "accessors")) {
        const tinygltf::Accessor &a = m.accessors.at(i);
        const std::string where = fmt("accessors[%d]", i++);
        same(o, "bufferView", a.bufferView, where);
        same(o, "byteOffset", (double)a.byteOffset, where);
        same(o, "count", (double)a.count, where);
        same(o, "componentType", a.componentType, where);
    }
    i = 0;
    cJSON_ArrayForEach(o, cJSON_GetObjectItemCaseSensitive(doc, "bufferViews")) {
        const tinygltf::BufferView &v = m.bufferViews.at(i);
        const std::string where = fmt("bufferViews[%d]", i++);
        same(o, "buffer", v.buffer, where);
        same(o, "byteOffset", (double)v.byteOffset, where);
        same(o, "byteLength", (double)v.byteLength, where);
        same(o, "byteStride", (double)v.byteStride, where);
    }
}

// The JSON of a GLB (version 2 only), bounds-checked.
cJSON *glb_json(const char *bytes, size_t size)
{
    auto u32 = [&](size_t at) {
        return (uint32_t)(unsigned char)bytes[at] | (uint32_t)(unsigned char)bytes[at + 1] << 8 |
               (uint32_t)(unsigned char)bytes[at + 2] << 16 | (uint32_t)(unsigned char)bytes[at + 3] << 24;
    };
    if (size < 20)
        fail(fmt("malformed GLB: %zu bytes, shorter than its headers (20)", size));
    if (u32(4) != 2)
        fail(fmt("GLB version %u: only version 2 is supported", u32(4)));
    const uint32_t length = u32(12);
    if (memcmp(bytes + 16, "JSON", 4) != 0 || length > size - 20)
        fail(fmt("malformed GLB: its first chunk is not JSON of %u bytes within the file's %zu", length, size));
    const char *end = nullptr, *json = bytes + 20;
    if (memchr(json, '\0', length))  // the chunk is padded with spaces, never NULs
        fail("malformed GLB: its JSON chunk holds a NUL byte");
    check_no_nul_escape(json, length);
    cJSON *j = cJSON_ParseWithLengthOpts(json, length, &end, 0);
    while (j && end < json + length && strchr(" \t\r\n", *end))
        end++;
    if (!j || end != json + length) {
        cJSON_Delete(j);
        fail("malformed GLB: its JSON chunk does not parse, or has text after the document");
    }
    return j;
}

// EXT_meshopt_compression's fallback buffers hold nothing the decoder
// needs (their views decode from another buffer) and often have no uri,
// which tinygltf refuses in a .gltf and would fill from a GLB's BIN chunk:
// each becomes a data URI of one zero byte (tinygltf decodes no empty one).
// Returns whether doc changed.
bool empty_fallback_buffers(cJSON *doc)
{
    bool changed = false;
    cJSON *b;
    cJSON_ArrayForEach(b, cJSON_GetObjectItemCaseSensitive(doc, "buffers")) {
        const cJSON *e = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(b, "extensions"), meshopt_ext);
        if (!cJSON_IsTrue(cJSON_GetObjectItemCaseSensitive(e, "fallback")) || cJSON_GetObjectItemCaseSensitive(b, "uri"))
            continue;
        cJSON_DeleteItemFromObjectCaseSensitive(b, "byteLength");
        cJSON_AddNumberToObject(b, "byteLength", 1);
        cJSON_AddStringToObject(b, "uri", "data:application/octet-stream;base64,AA==");
        changed = true;
    }
    return changed;
}

// A primitive of KHR_draco_mesh_compression takes its triangles from its
// Draco data; its index accessor has no buffer view, which tinygltf
// refuses. The accessor is taken out of the primitive into
// indices[{mesh, primitive}] (its count is checked against the data).
// Returns whether doc changed.
bool take_draco_indices(cJSON *doc, std::map<std::pair<int, int>, int> &indices)
{
    bool changed = false;
    int mi = 0;
    cJSON *mesh, *p;
    cJSON_ArrayForEach(mesh, cJSON_GetObjectItemCaseSensitive(doc, "meshes")) {
        int pi = 0;
        cJSON_ArrayForEach(p, cJSON_GetObjectItemCaseSensitive(mesh, "primitives")) {
            const cJSON *e = cJSON_GetObjectItemCaseSensitive(cJSON_GetObjectItemCaseSensitive(p, "extensions"), draco_ext);
            const cJSON *i = cJSON_GetObjectItemCaseSensitive(p, "indices");
            if (e && is_index(i)) {
                indices[{mi, pi}] = (int)i->valuedouble;
                cJSON_DeleteItemFromObjectCaseSensitive(p, "indices");
                changed = true;
            }
            pi++;
        }
        mi++;
    }
    return changed;
}

// A GLB with its JSON chunk replaced by json (padded with spaces), the
// chunks after it as they were.
std::string glb_with_json(const char *bytes, size_t size, const char *json)
{
    auto u32 = [](uint32_t v) { return std::string{(char)v, (char)(v >> 8), (char)(v >> 16), (char)(v >> 24)}; };
    const uint32_t old = (uint32_t)(unsigned char)bytes[12] | (uint32_t)(unsigned char)bytes[13] << 8 |
                         (uint32_t)(unsigned char)bytes[14] << 16 | (uint32_t)(unsigned char)bytes[15] << 24;
    std::string chunk(json);
    chunk.append((4 - chunk.size() % 4) % 4, ' ');
    const std::string rest(bytes + 20 + old, size - 20 - old);
    return "glTF" + u32(2) + u32((uint32_t)(12 + 8 + chunk.size() + rest.size())) + u32((uint32_t)chunk.size()) +
           "JSON" + chunk + rest;
}

void load(const char *path, const char *bytes, size_t size, struct scene *s)
{
    bool glb = size >= 4 && memcmp(bytes, "glTF", 4) == 0;
    if (size > 0x7fffffffu)
        fail("file is larger than 2 GiB");
    cJSON *j = nullptr;
    if (!glb) {  // our own JSON check: a precise position instead of a parser's essay
        const char *end = nullptr;
        const char *nul = (const char *)memchr(bytes, '\0', size);
        if (nul)
            fail(fmt("malformed JSON: a NUL byte at byte %zu", (size_t)(nul - bytes)));
        check_no_nul_escape(bytes, size);
        j = cJSON_ParseWithLengthOpts(bytes, size, &end, 0);
        while (j && end < bytes + size && strchr(" \t\r\n", *end))
            end++;
        if (j && end != bytes + size) {
            cJSON_Delete(j);
            j = nullptr;
            int line = 1;
            for (const char *c = bytes; c < end; c++)
                line += *c == '\n';
            fail(fmt("malformed JSON at line %d (byte %zu): text after the document", line, (size_t)(end - bytes)));
        }
        if (!j) {
            const char *at = cJSON_GetErrorPtr();
            size_t off = at && at >= bytes && at <= bytes + size ? (size_t)(at - bytes) : 0;
            int line = 1;
            for (size_t i = 0; i < off; i++)
                line += bytes[i] == '\n';
            fail(fmt("malformed JSON at line %d (byte %zu)", line, off));
        }
    } else {
        j = glb_json(bytes, size);
    }
    std::string dir(path);
    size_t slash = dir.find_last_of('/');
    dir = slash == std::string::npos ? "." : dir.substr(0, slash + (slash == 0));
    // Deleted however load ends: check_read_as_written needs it after tinygltf.
    std::unique_ptr<cJSON, void (*)(cJSON *)> doc(j, cJSON_Delete);
    check_types(j);
    std::string rewritten;  // what tinygltf reads instead of bytes, when not empty
    std::map<std::pair<int, int>, int> draco_indices;
    const bool fallbacks = empty_fallback_buffers(j), draco = take_draco_indices(j, draco_indices);
    if (fallbacks || draco) {
        std::unique_ptr<char, void (*)(void *)> text(cJSON_PrintUnformatted(j), cJSON_free);
        if (!text)
            throw std::bad_alloc();
        rewritten = glb ? glb_with_json(bytes, size, text.get()) : std::string(text.get());
        bytes = rewritten.data(), size = rewritten.size();
    }
    buffer_files files{check_buffers(j, dir)};

    tinygltf::TinyGLTF gltf;
    gltf.SetImageLoader(skip_images, nullptr);
    gltf.SetFsCallbacks(tinygltf::FsCallbacks{buffer_file_exists, tinygltf::ExpandFilePath, read_buffer_file,
                                              tinygltf::WriteWholeFile, &files});
    tinygltf::Model model;
    std::string err, warn;
    failed_allocation = 0;
    bool ok = glb ? gltf.LoadBinaryFromMemory(&model, &err, &warn, (const unsigned char *)bytes,
                                              (unsigned)size, dir)
                  : gltf.LoadASCIIFromString(&model, &err, &warn, bytes, (unsigned)size, dir);
    if (!ok && failed_allocation)  // tinygltf turns its parser's bad_alloc into an error string
        throw std::bad_alloc();
    if (!ok)  // a line of tinygltf's, capped: it can quote a whole data URI
        fail("malformed glTF: " + first_line(err).substr(0, 200));
    if (model.scenes.size() != (size_t)cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "scenes")) ||
        model.nodes.size() != (size_t)cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "nodes")) ||
        model.meshes.size() != (size_t)cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "meshes")) ||
        model.accessors.size() != (size_t)cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "accessors")) ||
        model.bufferViews.size() != (size_t)cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(j, "bufferViews")))
        fail("malformed glTF: tinygltf did not read every scene, node, mesh, accessor and buffer view");
    size_t mi = 0;
    const cJSON *meshes = cJSON_GetObjectItemCaseSensitive(j, "meshes");
    for (const cJSON *mesh = meshes ? meshes->child : nullptr; mesh; mesh = mesh->next, mi++)
        if ((int)model.meshes[mi].primitives.size() !=
            cJSON_GetArraySize(cJSON_GetObjectItemCaseSensitive(mesh, "primitives")))
            fail(fmt("malformed glTF: meshes[%zu]: tinygltf did not read every primitive", mi));
    check_read_as_written(j, model);

    loader l(model, draco_indices);
    l.run();
    if (!l.have_camera)
        fail("no camera: need a node with a perspective camera");
    if (!l.have_light)
        fail("no light: need a node whose extras hold \"area_light\", or a KHR_lights_punctual directional "
             "light (the sun)");
    if (l.idx.empty())
        fail("no triangles");

    s->vertex_count = l.pos.size() / 3;
    s->triangle_count = l.idx.size() / 3;
    s->positions = (float *)xmalloc(l.pos.size() * sizeof(float));
    s->normals = (float *)xmalloc(l.nrm.size() * sizeof(float));
    s->indices = (uint32_t *)xmalloc(l.idx.size() * sizeof(uint32_t));
    memcpy(s->positions, l.pos.data(), l.pos.size() * sizeof(float));
    memcpy(s->normals, l.nrm.data(), l.nrm.size() * sizeof(float));
    memcpy(s->indices, l.idx.data(), l.idx.size() * sizeof(uint32_t));
    s->camera = l.camera;
    s->light = l.light;

    const tinygltf::Value empty;
    const tinygltf::Value &sx = model.scenes.empty() ? empty
        : model.scenes[model.defaultScene >= 0 ? model.defaultScene : 0].extras;
    const tinygltf::Value &meta = sx.IsObject() && sx.Has("shadowbench") ? sx.Get("shadowbench") : empty;
    s->description = xstrdup(string_extra(meta, "description").c_str());
    s->shows = xstrdup(string_extra(meta, "shows").c_str());
    if (meta.IsObject() && meta.Has("motions")) {  // checked in the raw JSON
        const tinygltf::Value &mv = meta.Get("motions");
        s->motions = (char **)xcalloc(mv.ArrayLen() + 1, sizeof(char *));
        for (size_t i = 0; i < mv.ArrayLen(); i++)
            s->motions[s->motion_count++] = xstrdup(mv.Get((int)i).Get<std::string>().c_str());
    }
    s->nodes = (struct scene_node *)xcalloc(l.ranges.size() + 1, sizeof *s->nodes);
    for (const auto &r : l.ranges)
        s->nodes[s->node_count++] = scene_node{xstrdup(r.name.c_str()), r.first_vertex, r.vertex_count};
}

// The file named in what stops the program while it is read (memory that
// ran out: util_out_of_memory), the caller's context put back after.
struct context_guard {
    const char *outer;
    explicit context_guard(const char *path) : outer(log_set_context(path)) {}
    ~context_guard() { log_set_context(outer); }
};

}  // namespace

extern "C" int scene_load(const char *path, struct scene *s)
{
    *s = scene{};
    char *bytes = nullptr;
    size_t size = 0;
    int err;
    {
        context_guard named(path);
        err = util_read_file(path, &bytes, &size);
    }
    if (err) {
        log_error("%s: cannot open: %s", path, util_read_error(err));
        return err;
    }
    try {
        context_guard named(path);
        load(path, bytes, size, s);
    } catch (const load_error &e) {
        log_error("%s: %s", path, e.what.c_str());
        free(bytes);
        scene_free(s);
        return -EINVAL;
    } catch (const std::bad_alloc &) {
        log_error("%s: out of memory loading it: %zu more bytes were needed and could not be had", path,
                  failed_allocation);
        free(bytes);
        scene_free(s);
        return -ENOMEM;
    } catch (const std::exception &e) {  // tinygltf/json internals
        log_error("%s: malformed glTF: %s", path, e.what());
        free(bytes);
        scene_free(s);
        return -EINVAL;
    }

    s->path = xstrdup(path);
    const char *base = strrchr(path, '/');
    std::string stem = base ? base + 1 : path;
    size_t dot = stem.find_last_of('.');
    s->name = xstrdup((dot == std::string::npos ? stem : stem.substr(0, dot)).c_str());

    s->bounds_min = v3(INFINITY, INFINITY, INFINITY);
    s->bounds_max = v3(-INFINITY, -INFINITY, -INFINITY);
    for (size_t v = 0; v < s->vertex_count; v++) {
        struct vec3 p = v3(s->positions[3 * v], s->positions[3 * v + 1], s->positions[3 * v + 2]);
        s->bounds_min = v3_min(s->bounds_min, p);
        s->bounds_max = v3_max(s->bounds_max, p);
    }

    // The sun has no position: its node's means nothing, so it is the
    // scene's centre, about which light_rotate turns it without moving its
    // map (light_frustum.c).
    if (s->light.shape == LIGHT_SUN)
        s->light.pos = v3_scale(v3_add(s->bounds_min, s->bounds_max), 0.5f);

    // The cache key (docs/design.md §6): the file's bytes plus everything it
    // resolved to, so a changed external buffer is noticed too.
    uint64_t h = util_hash(UTIL_HASH_INIT, bytes, size);
    h = util_hash(h, s->positions, s->vertex_count * 3 * sizeof(float));
    h = util_hash(h, s->indices, s->triangle_count * 3 * sizeof(uint32_t));
    h = util_hash(h, &s->camera, sizeof s->camera);
    h = util_hash(h, &s->light, sizeof s->light);
    s->hash = h;
    free(bytes);
    return 0;
}
