/* The occluders of a shadow-ray origin (cull.h).
 *
 * The triangles go into a 4-wide BVH built by Embree's BVH builder
 * (rtcBuildBVH, SAH), searched with the pyramid from o over the light. A box
 * or a triangle is ruled out when it lies outside one of the pyramid's six
 * planes (the tangent plane through o, the light's plane, four sides through
 * o and the light's edges); a triangle also when o and the light's four
 * corners lie on one side of its plane, so that no segment from o to the
 * light crosses it. That second test rules out the surface's own triangles
 * round o, which wrap round the pyramid's apex.
 *
 * Patches: each triangle is one, and two triangles sharing an edge make a
 * quad where the quad is convex and exactly coplanar (plates, box faces), so
 * the patch is exactly their union. One patch then stands for both, and a
 * plate hides the light from its umbra as one occluder. */
#include "cull.h"
#include "base/log.h"
#include "base/util.h"

#include <float.h>
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

const char *cull_embree_error_text(enum RTCError code)
{
    switch (code) {
    case RTC_ERROR_NONE: return "no error recorded";
    case RTC_ERROR_INVALID_ARGUMENT: return "an invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "an invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory (raise the address-space limit, ulimit -v, or free memory)";
    case RTC_ERROR_UNSUPPORTED_CPU: return "this CPU is not supported";
    case RTC_ERROR_CANCELLED: return "cancelled";
    default: return "an unknown error";
    }
}

/* Steps (boxes and triangles tested) a search may take before it gives up
 * and the pixel is traced: a few microseconds, against the ~1000 rays (tens
 * of microseconds) it spares. */
#define CULL_BUDGET 512
#define CULL_LEAF_MAX 4
#define CULL_WIDTH 4
#define CULL_MAX_DEPTH 64
/* Distances below the margin count as on the plane: this fraction of the
 * scene's extent (1/25 of the shadow rays' origin offset, GT_OFFSET_SCALE,
 * so the surface under o is still ruled out), and at least CULL_ROUNDING
 * times the largest coordinate: 32 roundings of it, above the error of the
 * dot products and cross products the tests take. */
#define CULL_MARGIN_SCALE 4e-6f
#define CULL_ROUNDING (32.0f * FLT_EPSILON)

struct box { struct vec3 lo, hi; };

struct node {
    bool leaf;
    unsigned count;  /* children, or triangles of a leaf */
    union {
        struct {
            struct box box[CULL_WIDTH];
            const struct node *child[CULL_WIDTH];
        };
        unsigned tri[CULL_LEAF_MAX];
    };
};

struct plane { struct vec3 n; float d; };  /* unit n; signed distance n.x - d */

struct triangle {
    struct vec3 v[3];
    struct plane plane;  /* n = 0 when degenerate (never hit, never ruled out by its plane) */
};

/* A convex polygon, its corners in order round it. */
struct patch {
    int count;    /* 3 or 4; 0: a degenerate triangle */
    int winding;  /* +1: the corners go anticlockwise about plane.n, -1: clockwise */
    struct plane plane;
    struct vec3 v[4];
};

struct cull {
    struct vec3 corner[4];  /* the light, or the square round the disk, in order */
    int light_winding;      /* +1: the corners go anticlockwise about the light's z */
    struct plane light;     /* n = the light's z: the emitting side is negative */
    float margin;
    struct triangle *tris;
    struct patch *patches;  /* a triangle's own, or the quad of a merged pair (at the lower index) */
    unsigned *patch_of;     /* per triangle: its patch */
    RTCBVH bvh;
    const struct node *root;
};

static float signed_distance(const struct plane *p, struct vec3 x) { return v3_dot(p->n, x) - p->d; }

static struct plane plane_through(struct vec3 n, struct vec3 x)
{
    return (struct plane){n, v3_dot(n, x)};
}

/* ---- the BVH, through Embree's builder callbacks ---- */

static void *create_node(RTCThreadLocalAllocator alloc, unsigned count, void *user)
{
    (void)user;
    struct node *n = rtcThreadLocalAlloc(alloc, sizeof *n, 16);
    memset(n, 0, sizeof *n);
    n->count = count;
    return n;
}

static void set_children(void *node, void **children, unsigned count, void *user)
{
    (void)user;
    struct node *n = node;
    for (unsigned i = 0; i < count; i++)
        n->child[i] = children[i];
}

static void set_bounds(void *node, const struct RTCBounds **bounds, unsigned count, void *user)
{
    (void)user;
    struct node *n = node;
    for (unsigned i = 0; i < count; i++)
        n->box[i] = (struct box){v3(bounds[i]->lower_x, bounds[i]->lower_y, bounds[i]->lower_z),
                                 v3(bounds[i]->upper_x, bounds[i]->upper_y, bounds[i]->upper_z)};
}

static void *create_leaf(RTCThreadLocalAllocator alloc, const struct RTCBuildPrimitive *prims, size_t count,
                         void *user)
{
    (void)user;
    struct node *n = rtcThreadLocalAlloc(alloc, sizeof *n, 16);
    memset(n, 0, sizeof *n);
    n->leaf = true;
    n->count = (unsigned)count;
    for (size_t i = 0; i < count; i++)
        n->tri[i] = prims[i].primID;
    return n;
}

static int build_bvh(RTCDevice dev, struct cull *c, size_t count)
{
    /* Embree reads these 32-byte aligned; sizeof is 32, so the size is a multiple. */
    struct RTCBuildPrimitive *prims = aligned_alloc(32, count * sizeof *prims);
    if (!prims)
        return -1;
    for (size_t i = 0; i < count; i++) {
        struct vec3 lo = v3_min(c->tris[i].v[0], v3_min(c->tris[i].v[1], c->tris[i].v[2]));
        struct vec3 hi = v3_max(c->tris[i].v[0], v3_max(c->tris[i].v[1], c->tris[i].v[2]));
        prims[i] = (struct RTCBuildPrimitive){lo.x, lo.y, lo.z, 0, hi.x, hi.y, hi.z, (unsigned)i};
    }
    struct RTCBuildArguments a = rtcDefaultBuildArguments();
    a.buildQuality = RTC_BUILD_QUALITY_MEDIUM;
    a.maxBranchingFactor = CULL_WIDTH;
    a.maxDepth = CULL_MAX_DEPTH;
    a.maxLeafSize = CULL_LEAF_MAX;
    a.bvh = c->bvh = rtcNewBVH(dev);
    a.primitives = prims;
    a.primitiveCount = a.primitiveArrayCapacity = count;
    a.createNode = create_node;
    a.setNodeChildren = set_children;
    a.setNodeBounds = set_bounds;
    a.createLeaf = create_leaf;
    c->root = c->bvh ? rtcBuildBVH(&a) : NULL;
    free(prims);
    return c->root ? 0 : -1;
}

/* ---- patches ---- */

struct edge { unsigned lo, hi, tri, apex; };  /* apex: the triangle's vertex off the edge */

static int edge_order(const void *a, const void *b)
{
    const struct edge *x = a, *y = b;
    if (x->lo != y->lo)
        return x->lo < y->lo ? -1 : 1;
    if (x->hi != y->hi)
        return x->hi < y->hi ? -1 : 1;
    return x->tri < y->tri ? -1 : x->tri > y->tri;
}

static struct patch make_patch(const struct vec3 *v, int count, int winding, struct plane plane)
{
    struct patch p = {.count = count, .winding = winding, .plane = plane};
    for (int i = 0; i < count; i++)
        p.v[i] = v[i];
    return p;
}

/* The winding about n of the quad q (corners in order round it) where it is
 * strictly convex (every corner turns the same way): +1 or -1; else 0. */
static int convex_quad(const struct vec3 q[4], struct vec3 n)
{
    int positive = 0;
    for (int i = 0; i < 4; i++) {
        struct vec3 e0 = v3_sub(q[(i + 1) % 4], q[i]), e1 = v3_sub(q[(i + 2) % 4], q[(i + 1) % 4]);
        float turn = v3_dot(v3_cross(e0, e1), n);
        if (turn == 0.0f)
            return 0;
        positive += turn > 0.0f;
    }
    return positive == 4 ? 1 : positive == 0 ? -1 : 0;
}

/* Two triangles sharing an edge merge into a quad where the quad is convex
 * and the fourth corner's computed distance from the first triangle's plane
 * is 0 (axis-aligned plates and box faces): the patch is their union up to
 * float rounding, which the margin covers. */
static void build_patches(const struct scene *s, struct cull *c)
{
    const size_t count = s->triangle_count;
    for (size_t i = 0; i < count; i++) {
        c->patch_of[i] = (unsigned)i;
        c->patches[i] = c->tris[i].plane.n.x == 0 && c->tris[i].plane.n.y == 0 && c->tris[i].plane.n.z == 0
                            ? (struct patch){0}
                            : make_patch(c->tris[i].v, 3, 1, c->tris[i].plane);
    }

    struct edge *edges = xmalloc(3 * count * sizeof *edges);
    for (size_t i = 0; i < count; i++)
        for (int k = 0; k < 3; k++) {
            unsigned a = s->indices[3 * i + k], b = s->indices[3 * i + (k + 1) % 3];
            edges[3 * i + k] = (struct edge){a < b ? a : b, a < b ? b : a, (unsigned)i,
                                             s->indices[3 * i + (k + 2) % 3]};
        }
    qsort(edges, 3 * count, sizeof *edges, edge_order);
    bool *merged = xcalloc(count, sizeof *merged);
    for (size_t e = 0; e + 1 < 3 * count; e++) {
        const struct edge *x = &edges[e], *y = &edges[e + 1];
        /* exactly two triangles on the edge, neither merged yet */
        if (x->lo != y->lo || x->hi != y->hi || merged[x->tri] || merged[y->tri])
            continue;
        if (e + 2 < 3 * count && edges[e + 2].lo == x->lo && edges[e + 2].hi == x->hi)
            continue;
        if (e > 0 && edges[e - 1].lo == x->lo && edges[e - 1].hi == x->hi)
            continue;
        const struct patch *px = &c->patches[x->tri];
        if (!px->count || !c->patches[y->tri].count)
            continue;
        const float *P = s->positions;
        struct vec3 q[4] = {v3(P[3 * x->apex], P[3 * x->apex + 1], P[3 * x->apex + 2]),
                            v3(P[3 * x->lo], P[3 * x->lo + 1], P[3 * x->lo + 2]),
                            v3(P[3 * y->apex], P[3 * y->apex + 1], P[3 * y->apex + 2]),
                            v3(P[3 * x->hi], P[3 * x->hi + 1], P[3 * x->hi + 2])};
        const int winding = convex_quad(q, px->plane.n);
        if (signed_distance(&px->plane, q[2]) != 0.0f || !winding)
            continue;
        const unsigned lo = x->tri < y->tri ? x->tri : y->tri;
        c->patches[lo] = make_patch(q, 4, winding, px->plane);
        c->patch_of[x->tri] = c->patch_of[y->tri] = lo;
        merged[x->tri] = merged[y->tri] = true;
    }
    free(merged);
    free(edges);
}

struct cull *cull_build(RTCDevice dev, const struct scene *s)
{
    struct cull *c = xcalloc(1, sizeof *c);
    const struct scene_light *L = &s->light;
    const float hx = L->shape == LIGHT_RECT ? 0.5f * L->width : L->radius;
    const float hy = L->shape == LIGHT_RECT ? 0.5f * L->height : L->radius;
    for (int i = 0; i < 4; i++)
        c->corner[i] = v3_add(L->pos, v3_add(v3_scale(L->x, (i == 1 || i == 2) ? hx : -hx),
                                             v3_scale(L->y, i >= 2 ? hy : -hy)));
    c->light = plane_through(L->z, L->pos);
    c->light_winding = v3_dot(v3_cross(v3_sub(c->corner[1], c->corner[0]), v3_sub(c->corner[2], c->corner[1])),
                              L->z) > 0.0f ? 1 : -1;
    /* Above the rounding of the coordinates as they are (a scene far from
     * the origin rounds coarser than its size suggests). */
    float largest = 0.0f;
    for (size_t i = 0; i < 3 * s->vertex_count; i++)
        largest = fmaxf(largest, fabsf(s->positions[i]));
    for (int i = 0; i < 4; i++)
        largest = fmaxf(largest, fmaxf(fabsf(c->corner[i].x), fmaxf(fabsf(c->corner[i].y), fabsf(c->corner[i].z))));
    c->margin = fmaxf(CULL_MARGIN_SCALE * scene_extent(s), CULL_ROUNDING * largest);

    const size_t count = s->triangle_count;
    c->tris = xmalloc(count * sizeof *c->tris);
    c->patches = xmalloc(count * sizeof *c->patches);
    c->patch_of = xmalloc(count * sizeof *c->patch_of);
    for (size_t i = 0; i < count; i++) {
        struct triangle *t = &c->tris[i];
        for (int k = 0; k < 3; k++) {
            const float *p = &s->positions[3 * s->indices[3 * i + k]];
            t->v[k] = v3(p[0], p[1], p[2]);
        }
        struct vec3 n = v3_cross(v3_sub(t->v[1], t->v[0]), v3_sub(t->v[2], t->v[0]));
        float len = v3_length(n);
        t->plane = len > 0.0f && isfinite(len) ? plane_through(v3_scale(n, 1.0f / len), t->v[0])
                                               : (struct plane){v3(0, 0, 0), 0.0f};
    }
    build_patches(s, c);
    if (count && build_bvh(dev, c, count) != 0) {
        log_error("ground truth: Embree cannot build the culling BVH: %s",
                  cull_embree_error_text(rtcGetDeviceError(dev)));
        cull_free(c);
        return NULL;
    }
    return c;
}

void cull_free(struct cull *c)
{
    if (!c)
        return;
    if (c->bvh)
        rtcReleaseBVH(c->bvh);
    free(c->tris);
    free(c->patches);
    free(c->patch_of);
    free(c);
}

float cull_margin(const struct cull *c) { return c->margin; }

/* ---- the search ---- */

/* The pyramid from o over the light, above the tangent plane: inside all
 * six planes (signed distance <= 0). */
struct pyramid {
    struct plane side[6];
    struct vec3 o;
};

static bool box_outside(const struct plane *p, const struct box *b, float margin)
{
    /* the corner deepest inside p */
    struct vec3 c = v3(p->n.x > 0 ? b->lo.x : b->hi.x, p->n.y > 0 ? b->lo.y : b->hi.y,
                       p->n.z > 0 ? b->lo.z : b->hi.z);
    return signed_distance(p, c) > margin;
}

/* Whether the light's corners and o all lie more than the margin on one
 * side of p. */
static bool light_one_side(const struct cull *c, const struct plane *p, struct vec3 o)
{
    const float so = signed_distance(p, o);
    if (fabsf(so) <= c->margin)
        return false;
    for (int i = 0; i < 4; i++) {
        float sc = signed_distance(p, c->corner[i]);
        if (so > 0 ? sc <= c->margin : sc >= -c->margin)
            return false;
    }
    return true;
}

static bool triangle_ruled_out(const struct cull *c, const struct pyramid *py, const struct triangle *t)
{
    for (int p = 0; p < 6; p++)
        if (signed_distance(&py->side[p], t->v[0]) > c->margin &&
            signed_distance(&py->side[p], t->v[1]) > c->margin &&
            signed_distance(&py->side[p], t->v[2]) > c->margin)
            return true;
    return light_one_side(c, &t->plane, py->o);
}

/* Patch p set up for segments from o; false where o lies within the margin
 * of its plane (too close to decide). Each edge plane contains the edge's
 * own vector and is oriented by the patch's winding and o's side, never by a
 * nearly-zero dot product (a patch seen edge-on). With d the edge and n the
 * plane's normal, cross(d, o - v) . (inward in-plane direction) = -winding
 * |d|^2 (n . (o - v)): the sign follows. */
static bool make_occluder(const struct cull *c, const struct patch *p, struct vec3 o, struct cull_occluder *out)
{
    const float so = signed_distance(&p->plane, o);
    if (fabsf(so) <= c->margin)
        return false;
    *out = (struct cull_occluder){.n = p->plane.n, .d = p->plane.d, .so = so};
    const float sign = (float)-p->winding * (so > 0.0f ? 1.0f : -1.0f);
    for (int k = 0; k < 4; k++) {  /* a triangle's third edge twice */
        const int a = k < p->count ? k : p->count - 1;
        const struct vec3 va = p->v[a], edge = v3_sub(p->v[(a + 1) % p->count], va);
        out->edge[k] = v3_scale(v3_normalize(v3_cross(edge, v3_sub(o, va))), sign);
    }
    return true;
}

int cull_occluders(const struct cull *c, struct vec3 o, struct vec3 n, struct cull_occluder out[CULL_MAX_OCCLUDERS])
{
    if (signed_distance(&c->light, o) >= -c->margin)  /* behind the one-sided light, or on it */
        return -1;
    if (!c->root)
        return 0;
    struct pyramid py = {.o = o};
    py.side[0] = plane_through(v3_scale(n, -1.0f), o);  /* above the tangent plane */
    py.side[1] = c->light;
    /* Through o and the light's edge corner[i] corner[i+1], outward: o is in
     * front of the light (its signed distance negative), so by
     * make_occluder's identity cross(edge, o - corner) points inwards where
     * the corners go anticlockwise. */
    for (int i = 0; i < 4; i++) {
        const struct vec3 edge = v3_sub(c->corner[(i + 1) % 4], c->corner[i]);
        const struct vec3 inward = v3_normalize(v3_cross(edge, v3_sub(o, c->corner[i])));
        py.side[2 + i] = plane_through(v3_scale(inward, (float)-c->light_winding), o);
    }

    unsigned patch[CULL_MAX_OCCLUDERS];
    int count = 0;
    const struct node *stack[CULL_MAX_DEPTH * CULL_WIDTH];
    int top = 0, budget = CULL_BUDGET;
    stack[top++] = c->root;
    while (top > 0) {
        const struct node *node = stack[--top];
        if (node->leaf) {
            for (unsigned i = 0; i < node->count; i++) {
                if (--budget < 0)
                    return -1;
                if (triangle_ruled_out(c, &py, &c->tris[node->tri[i]]))
                    continue;
                const unsigned id = c->patch_of[node->tri[i]];
                bool known = false;
                for (int k = 0; k < count && !known; k++)
                    known = patch[k] == id;
                if (known)
                    continue;
                if (count == CULL_MAX_OCCLUDERS || !c->patches[id].count ||
                    !make_occluder(c, &c->patches[id], o, &out[count]))
                    return -1;
                patch[count++] = id;
            }
            continue;
        }
        for (unsigned i = 0; i < node->count; i++) {
            if (--budget < 0)
                return -1;
            bool outside = false;
            for (int p = 0; p < 6 && !outside; p++)
                outside = box_outside(&py.side[p], &node->box[i], c->margin);
            if (outside)
                continue;
            if (top == CULL_MAX_DEPTH * CULL_WIDTH)  /* deeper than the builder was asked for */
                return -1;
            stack[top++] = node->child[i];
        }
    }
    return count;
}
