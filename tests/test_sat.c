/* Protects the summed-area tables (shaders/sat_build.comp), moments_sat's
 * (d, d²) and msm_sat's (w, w², w³, w⁴), w = 2d - 1, on a 2048^2 map whose
 * depths are far from 0.5: a receiver plane at linear depth 0.9 fills the
 * map, under a small blocker at depth 0.
 *   - int32: each GPU table equals a CPU reference bit for bit (the same
 *     fixed-point rounding of the same moments, summed in uint32; w's odd
 *     powers in two's complement), and a 4-tap box difference equals the
 *     box's direct sum exactly, wrap-around and all.
 *   - precision: over random boxes, the error of the mean and variance read
 *     from moments_sat (as sat.glsl reads them) orders fp32 > fp32_centered
 *     >= int32; msm_sat's mean moments err less in int32 than in fp32, and
 *     int32 only by its rounding.
 *   - the sun (sun_exact()): the same scene under a sun, an orthographic
 *     map whose linear depth is 1 - d_hw: both int32 tables equal the CPU
 *     reference of that conversion bit for bit. */
#include "check.h"
#include "gltf_writer.h"
#include "run_cmd.h"
#include "gl/gl_context.h"
#include "gl/scene_mesh.h"
#include "gl/shader.h"
#include "scene/scene.h"
#include "techniques/shadowmap.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

#define N 2048
#define STRIDE (N + 1)
#define BOXES 4000
#define MAX_BOX 64

static char dir[] = "/tmp/sb_test_sat_XXXXXX";

static uint64_t rng = 88172645463325252ull;
static int rand_below(int n)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return (int)(rng % (uint64_t)n);
}

struct box { int x0, y0, x1, y1; };  /* [x0, x1) x [y0, y1), texels */

static struct box random_box(void)
{
    struct box b;
    int w = 1 + rand_below(MAX_BOX), h = 1 + rand_below(MAX_BOX);
    b.x0 = rand_below(N - w + 1), b.y0 = rand_below(N - h + 1);
    b.x1 = b.x0 + w, b.y1 = b.y0 + h;
    return b;
}

/* A table: product p (SM_PRODUCT_MOMENTS_SAT or _MSM_SAT) in format f,
 * read back; channels moments per entry. */
struct table {
    int product, channels;
    enum sat_format format;
    float scale;
    uint32_t *sat;
};

static struct table build_sat(struct shadowmap *sm, const struct scene_mesh *mesh, int product,
                              enum sat_format f)
{
    struct table t = {.product = product, .channels = product == SM_PRODUCT_MSM_SAT ? 4 : 2, .format = f};
    struct sat_request sr = {.format = f, .max_box_texels = MAX_BOX};
    struct shadowmap_request r = {.products = SM_DEPTH | (1u << product)};
    if (product == SM_PRODUCT_MSM_SAT)
        r.msm_sat = sr;
    else
        r.moments_sat = sr;
    CHECK(shadowmap_prepare(sm, &r) == 0, "SAT resources");
    for (int p = 0; p < SM_PRODUCT_COUNT; p++)
        if (r.products & (1u << p))
            shadowmap_render_product(sm, mesh, p, &r);
    size_t bytes = sizeof(uint32_t) * (size_t)t.channels * STRIDE * STRIDE;
    t.sat = xmalloc(bytes);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, sm->products[product].buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)bytes, t.sat);
    t.scale = shadowmap_sat_fields(sm, product)->scale;
    return t;
}

static uint32_t at(const struct table *t, int x, int y, int c)
{
    return t->sat[t->channels * (y * STRIDE + x) + c];
}

/* The mean of channel c over box b, read as sat.glsl reads it. */
static float box_mean(const struct table *t, struct box b, int c)
{
    float area = (float)((b.x1 - b.x0) * (b.y1 - b.y0));
    uint32_t u[4] = {at(t, b.x1, b.y1, c), at(t, b.x0, b.y1, c), at(t, b.x1, b.y0, c), at(t, b.x0, b.y0, c)};
    if (t->format == SAT_INT32)
        return (float)(int32_t)(u[0] - u[1] - u[2] + u[3]) / t->scale / area;
    float v[4];
    memcpy(v, u, sizeof v);
    return ((v[0] - v[1]) - (v[2] - v[3])) / area;
}

/* moments[i * channels + c]: as the table's input; the reference rounds
 * them as the shader does (float multiply by a power of two is exact, then
 * + 0.5 and floor), sums them in uint32, and must equal the table. */
static void int32_exact(const struct table *t, const float *moments)
{
    const int C = t->channels;
    uint32_t *q = xmalloc(sizeof(uint32_t) * C * N * N), *ref = xcalloc((size_t)C * STRIDE * STRIDE, sizeof *ref);
    for (int i = 0; i < C * N * N; i++)
        q[i] = (uint32_t)(int32_t)floorf(moments[i] * t->scale + 0.5f);
    for (int y = 1; y <= N; y++)
        for (int x = 1; x <= N; x++)
            for (int c = 0; c < C; c++)
                ref[C * (y * STRIDE + x) + c] = q[C * ((y - 1) * N + x - 1) + c] +
                                                ref[C * ((y - 1) * STRIDE + x) + c] +
                                                ref[C * (y * STRIDE + x - 1) + c] -
                                                ref[C * ((y - 1) * STRIDE + x - 1) + c];
    CHECK(memcmp(ref, t->sat, sizeof(uint32_t) * C * STRIDE * STRIDE) == 0,
          "int32 SAT (%d channels) must equal the CPU reference bit for bit", C);
    int wrong = 0;
    for (int k = 0; k < BOXES; k++) {
        struct box b = random_box();
        for (int c = 0; c < C; c++) {
            int64_t direct = 0;
            for (int y = b.y0; y < b.y1; y++)
                for (int x = b.x0; x < b.x1; x++)
                    direct += (int32_t)q[C * (y * N + x) + c];
            uint32_t taps = at(t, b.x1, b.y1, c) - at(t, b.x0, b.y1, c) - at(t, b.x1, b.y0, c) +
                            at(t, b.x0, b.y0, c);
            wrong += direct >= (1ll << 31) || direct < -(1ll << 31) || (int32_t)taps != direct;
        }
    }
    CHECK(wrong == 0, "%d of %d int32 box sums (%d channels) differ from the direct sum", wrong, C * BOXES, C);
    free(q), free(ref);
}

/* RMS error over random boxes of what a shader reads from the table,
 * against double-precision sums of the moments (moments[i * channels + c],
 * the table's input before any centring): two channels, the mean (err[0])
 * and variance (err[1]) of depth, as sat_mean_variance forms them; four,
 * each mean moment (err[c]). */
static void box_rms(const struct table *t, const float *moments, double err[4])
{
    const int C = t->channels;
    rng = 88172645463325252ull;  /* the same boxes for every table */
    double se[4] = {0};
    for (int k = 0; k < BOXES; k++) {
        struct box b = random_box();
        double s[4] = {0}, area = (double)(b.x1 - b.x0) * (b.y1 - b.y0);
        for (int y = b.y0; y < b.y1; y++)
            for (int x = b.x0; x < b.x1; x++)
                for (int c = 0; c < C; c++)
                    s[c] += moments[C * (y * N + x) + c];
        double want[4];
        float got[4];
        for (int c = 0; c < C; c++)
            want[c] = s[c] / area, got[c] = box_mean(t, b, c);
        if (C == 2) {  /* the variance is shift-invariant: centred or not, m1 - m0² */
            got[1] -= got[0] * got[0], want[1] -= want[0] * want[0];
            got[0] += t->format == SAT_FP32_CENTERED ? 0.5f : 0.0f;
        }
        for (int c = 0; c < C; c++)
            se[c] += (got[c] - want[c]) * (got[c] - want[c]);
    }
    for (int c = 0; c < C; c++)
        err[c] = sqrt(se[c] / BOXES);
}

/* Light at height 4 facing down; blocker (1 x 1) at height 2 is the near
 * plane; a sliver at height -0.22, hidden under the receiver, sets the far
 * plane, so the receiver (height 0) sits at d = 2 / 2.22 = 0.90. */
static void write_scene(const char *path, bool sun)
{
    struct mesh_builder m = {0};
    mesh_add_quad(&m, v3(-6, 0, -6), v3(0, 0, 12), v3(12, 0, 0));
    mesh_add_quad(&m, v3(-0.5f, 2, -0.5f), v3(0, 0, 1), v3(1, 0, 0));
    mesh_add_quad(&m, v3(0, -0.22f, 0), v3(0, 0, 0.01f), v3(0.01f, 0, 0));
    struct gltf_scene_desc d = {
        .description = "SAT precision (test)", .shows = "depths far from 0.5",
        .camera_pos = v3(0, 3, 3), .camera_target = v3(0, 0, 0), .camera_yfov_rad = 0.8f,
        .camera_znear = 0.05f, .light_pos = v3(0, 4, 0), .light_target = v3(0, 0, 0),
        .light_width = 1, .light_height = 1, .sun_angular_diameter_deg = sun ? 0.53 : 0,
    };
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

/* Both tables in one request, each its own format and scale in its own
 * slot of the block: each is what it is alone, bit for bit. */
static void both_tables(struct shadowmap *sm, const struct scene_mesh *mesh)
{
    struct table alone[2] = {build_sat(sm, mesh, SM_PRODUCT_MOMENTS_SAT, SAT_FP32_CENTERED),
                             build_sat(sm, mesh, SM_PRODUCT_MSM_SAT, SAT_INT32)};
    struct shadowmap_request r = {.products = SM_DEPTH | SM_MOMENTS_SAT | SM_MSM_SAT,
                                  .moments_sat = {SAT_FP32_CENTERED, MAX_BOX}, .msm_sat = {SAT_INT32, MAX_BOX}};
    CHECK(shadowmap_prepare(sm, &r) == 0, "a request of both tables");
    for (int p = 0; p < SM_PRODUCT_COUNT; p++)
        if (r.products & (1u << p))
            shadowmap_render_product(sm, mesh, p, &r);
    for (int k = 0; k < 2; k++) {
        const int p = alone[k].product;
        const size_t bytes = sizeof(uint32_t) * (size_t)alone[k].channels * STRIDE * STRIDE;
        uint32_t *together = xmalloc(bytes);
        glBindBuffer(GL_SHADER_STORAGE_BUFFER, sm->products[p].buffer);
        glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, (GLsizeiptr)bytes, together);
        const struct shadowmap_sat_block *b = shadowmap_sat_fields(sm, p);
        CHECK(memcmp(together, alone[k].sat, bytes) == 0 && b->format == (int)alone[k].format &&
                  b->scale == alone[k].scale,
              "product %d: with the other table in the request, its table or its fields changed", p);
        free(together), free(alone[k].sat);
    }
}

/* The sun's depth conversion, as shaders/depth.glsl's sun branch: linear
 * depth is 1 - d_hw; each int32 table equals its CPU reference. */
static void sun_exact(const char *path)
{
    write_scene(path, true);
    struct scene s;
    struct scene_mesh mesh = {0};
    struct shadowmap sm = {0};
    CHECK(scene_load(path, &s) == 0 && s.light.shape == LIGHT_SUN, "the sun's scene");
    scene_mesh_upload(&s, &mesh);
    CHECK(shadowmap_create(&sm, &s, &(struct shadowmap_desc){.size_texels = N}) == 0 && sm.frustum.sun,
          "the sun's shadow map");
    float *depth = xmalloc(sizeof(float) * N * N), *m2 = xmalloc(sizeof(float) * 2 * N * N),
          *m4 = xmalloc(sizeof(float) * 4 * N * N);
    CHECK(shadowmap_prepare(&sm, &(struct shadowmap_request){.products = SM_DEPTH}) == 0, "depth map");
    shadowmap_render_product(&sm, &mesh, SM_PRODUCT_DEPTH, NULL);
    glBindTexture(GL_TEXTURE_2D, sm.products[SM_PRODUCT_DEPTH].texture);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    for (int i = 0; i < N * N; i++) {
        float d = 1.0f - depth[i], w = 2.0f * d - 1.0f, w2 = w * w;
        m2[2 * i] = d, m2[2 * i + 1] = d * d;
        m4[4 * i] = w, m4[4 * i + 1] = w2, m4[4 * i + 2] = w2 * w, m4[4 * i + 3] = w2 * w2;
    }
    const int products[] = {SM_PRODUCT_MOMENTS_SAT, SM_PRODUCT_MSM_SAT};
    for (int k = 0; k < 2; k++) {
        struct table t = build_sat(&sm, &mesh, products[k], SAT_INT32);
        int32_exact(&t, k ? m4 : m2);
        free(t.sat);
    }
    free(depth), free(m2), free(m4);
    shadowmap_destroy(&sm);
    scene_mesh_destroy(&mesh);
    scene_free(&s);
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    char *path = util_printf("%s/sat_precision.gltf", dir);
    write_scene(path, false);
    struct scene s;
    struct scene_mesh mesh = {0};
    struct shadowmap sm = {0};
    if (scene_load(path, &s) != 0 || gl_context_create(GL_BACKEND_OSMESA) != 0 || !gl_context_load_test_functions() ||
        shader_init(NULL) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    scene_mesh_upload(&s, &mesh);
    CHECK(shadowmap_create(&sm, &s, &(struct shadowmap_desc){.size_texels = N}) == 0, "shadow map");

    /* The tables' input: linear depth from the depth map, converted as
     * shaders/depth.glsl does (same float operations, no fused ones), and
     * its moments: d, d² (moments_sat) and w, w², w³, w⁴ (msm_sat). */
    float *depth = xmalloc(sizeof(float) * N * N), *m2 = xmalloc(sizeof(float) * 2 * N * N),
          *m4 = xmalloc(sizeof(float) * 4 * N * N);
    CHECK(shadowmap_prepare(&sm, &(struct shadowmap_request){.products = SM_DEPTH}) == 0, "depth map");
    shadowmap_render_product(&sm, &mesh, SM_PRODUCT_DEPTH, NULL);
    glBindTexture(GL_TEXTURE_2D, sm.products[SM_PRODUCT_DEPTH].texture);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    float n = sm.block.near_world, f = sm.block.far_world;
    int far_from_half = 0;
    for (int i = 0; i < N * N; i++) {
        float z = n * f / (depth[i] * (f - n) + n);
        float d = (z - n) / (f - n), w = 2.0f * d - 1.0f, w2 = w * w;
        m2[2 * i] = d, m2[2 * i + 1] = d * d;
        m4[4 * i] = w, m4[4 * i + 1] = w2, m4[4 * i + 2] = w2 * w, m4[4 * i + 3] = w2 * w2;
        far_from_half += fabsf(d - 0.5f) > 0.35f;
    }
    CHECK(far_from_half == N * N, "every depth far from 0.5: %d of %d", far_from_half, N * N);

    double err2[3][4], err4[3][4];
    const int products[] = {SM_PRODUCT_MOMENTS_SAT, SM_PRODUCT_MSM_SAT};
    for (int fmt = SAT_FP32; fmt <= SAT_INT32; fmt++)
        for (int k = 0; k < 2; k++) {
            const int p = products[k];
            if (p == SM_PRODUCT_MSM_SAT && fmt == SAT_FP32_CENTERED)
                continue;  /* not offered: w is centred */
            struct table t = build_sat(&sm, &mesh, p, (enum sat_format)fmt);
            const float *moments = p == SM_PRODUCT_MSM_SAT ? m4 : m2;
            if (fmt == SAT_INT32) {
                CHECK(t.scale == 262144.0f, "int32 scale for 64-texel boxes: 2^(30 - floor(log2(66^2))) = "
                      "2^18, got %g", t.scale);
                int32_exact(&t, moments);
            }
            box_rms(&t, moments, p == SM_PRODUCT_MSM_SAT ? err4[fmt] : err2[fmt]);
            free(t.sat);
        }
    printf("SAT at %d^2, rms error over %d boxes up to %dx%d texels:\n", N, BOXES, MAX_BOX, MAX_BOX);
    for (int fmt = SAT_FP32; fmt <= SAT_INT32; fmt++)
        printf("  moments_sat %-14s mean %.3g  variance %.3g\n", sat_format_names[fmt], err2[fmt][0], err2[fmt][1]);
    for (int fmt = SAT_FP32; fmt <= SAT_INT32; fmt += SAT_INT32 - SAT_FP32)
        printf("  msm_sat     %-14s w %.3g  w^2 %.3g  w^3 %.3g  w^4 %.3g\n", sat_format_names[fmt], err4[fmt][0],
               err4[fmt][1], err4[fmt][2], err4[fmt][3]);
    CHECK(err2[SAT_FP32][1] > err2[SAT_FP32_CENTERED][1] && err2[SAT_FP32][0] > err2[SAT_FP32_CENTERED][0],
          "centring must help fp32");
    CHECK(err2[SAT_FP32_CENTERED][1] >= err2[SAT_INT32][1] && err2[SAT_FP32_CENTERED][0] >= err2[SAT_INT32][0],
          "int32 must be at least as precise as fp32_centered");
    /* int32 errs only by its rounding, half a unit of 2^-18 per texel. */
    CHECK(err2[SAT_INT32][0] <= 0.5 / 262144.0, "int32 mean error %.3g beyond its rounding", err2[SAT_INT32][0]);
    for (int c = 0; c < 4; c++)
        CHECK(err4[SAT_FP32][c] > err4[SAT_INT32][c], "msm_sat: int32 must beat fp32 on moment %d", c + 1);
    both_tables(&sm, &mesh);
    char *sun_path = util_printf("%s/sat_sun.gltf", dir);
    sun_exact(sun_path);
    free(sun_path);
    CHECK(shadowmap_prepare(&sm, &(struct shadowmap_request){
              .products = SM_DEPTH | SM_MSM_SAT, .msm_sat.format = SAT_FP32_CENTERED}) != 0,
          "msm_sat must refuse fp32_centered");

    free(depth), free(m2), free(m4);
    shadowmap_destroy(&sm);
    scene_mesh_destroy(&mesh);
    gl_context_destroy();
    scene_free(&s);
    free(path);
    remove_tree(dir);
    return check_finish();
}
