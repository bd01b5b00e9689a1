/* Protects the summed-area table of the moments (shaders/sat_build.comp)
 * on a 2048^2 map whose depths are far from 0.5: a receiver plane at linear
 * depth 0.9 fills the map, under a small blocker at depth 0.
 *   - int32: the GPU table equals a CPU reference bit for bit (the same
 *     fixed-point rounding of the same moments, summed in uint32), and a
 *     4-tap box difference equals the box's direct sum exactly, wrap-around
 *     and all.
 *   - precision: over random boxes, the error of the mean and variance read
 *     from the table (as sat.glsl reads them) orders fp32 > fp32_centered >=
 *     int32. */
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

/* The SAT of one format, read back. */
static uint32_t *build_sat(struct shadowmap *sm, const struct scene_mesh *mesh, enum sat_format f,
                           float *scale)
{
    struct shadowmap_request r = {.products = SM_DEPTH | SM_MOMENTS_SAT,
                                  .moments_sat = {.format = f, .max_box_texels = MAX_BOX}};
    CHECK(shadowmap_prepare(sm, &r) == 0, "SAT resources");
    for (int p = 0; p < SM_PRODUCT_COUNT; p++)
        if (r.products & (1u << p))
            shadowmap_render_product(sm, mesh, p, &r);
    uint32_t *sat = xmalloc(sizeof(uint32_t) * 2 * STRIDE * STRIDE);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, sm->products[SM_PRODUCT_MOMENTS_SAT].buffer);
    glGetBufferSubData(GL_SHADER_STORAGE_BUFFER, 0, sizeof(uint32_t) * 2 * STRIDE * STRIDE, sat);
    *scale = sm->block.sat_scale;
    return sat;
}

static uint32_t at(const uint32_t *sat, int x, int y, int c) { return sat[2 * (y * STRIDE + x) + c]; }
static float atf(const uint32_t *sat, int x, int y, int c)
{
    float v;
    uint32_t u = at(sat, x, y, c);
    memcpy(&v, &u, sizeof v);
    return v;
}

static void int32_exact(const uint32_t *sat, const float *moments, float scale)
{
    /* The reference: round(m * scale) as the shader does it (float multiply
     * by a power of two is exact, then + 0.5 and truncation), summed in
     * uint32. */
    uint32_t *q = xmalloc(sizeof(uint32_t) * 2 * N * N), *ref = xcalloc(2 * STRIDE * STRIDE, sizeof *ref);
    for (int i = 0; i < 2 * N * N; i++)
        q[i] = (uint32_t)(moments[i] * scale + 0.5f);
    for (int y = 1; y <= N; y++)
        for (int x = 1; x <= N; x++)
            for (int c = 0; c < 2; c++)
                ref[2 * (y * STRIDE + x) + c] = q[2 * ((y - 1) * N + x - 1) + c] +
                                                ref[2 * ((y - 1) * STRIDE + x) + c] +
                                                ref[2 * (y * STRIDE + x - 1) + c] -
                                                ref[2 * ((y - 1) * STRIDE + x - 1) + c];
    CHECK(memcmp(ref, sat, sizeof(uint32_t) * 2 * STRIDE * STRIDE) == 0,
          "int32 SAT must equal the CPU reference bit for bit");
    int wrong = 0;
    for (int k = 0; k < BOXES; k++) {
        struct box b = random_box();
        for (int c = 0; c < 2; c++) {
            uint64_t direct = 0;
            for (int y = b.y0; y < b.y1; y++)
                for (int x = b.x0; x < b.x1; x++)
                    direct += q[2 * (y * N + x) + c];
            uint32_t taps = at(sat, b.x1, b.y1, c) - at(sat, b.x0, b.y1, c) - at(sat, b.x1, b.y0, c) +
                            at(sat, b.x0, b.y0, c);
            wrong += direct >= (1ull << 32) || taps != (uint32_t)direct;
        }
    }
    CHECK(wrong == 0, "%d of %d int32 box sums differ from the direct sum", wrong, 2 * BOXES);
    free(q), free(ref);
}

/* RMS error of the box variance (and mean, in *mean_rms) read from the table
 * as sat.glsl does, against double-precision sums of the moments. */
static double variance_rms(const uint32_t *sat, enum sat_format f, float scale, const float *moments,
                           double *mean_rms)
{
    rng = 88172645463325252ull;  /* the same boxes for every format */
    double se_var = 0, se_mean = 0;
    for (int k = 0; k < BOXES; k++) {
        struct box b = random_box();
        double s1 = 0, s2 = 0, area = (double)(b.x1 - b.x0) * (b.y1 - b.y0);
        for (int y = b.y0; y < b.y1; y++)
            for (int x = b.x0; x < b.x1; x++)
                s1 += moments[2 * (y * N + x)], s2 += moments[2 * (y * N + x) + 1];
        double mean = s1 / area, var = s2 / area - mean * mean;
        float m[2];
        for (int c = 0; c < 2; c++) {
            if (f == SAT_INT32) {
                uint32_t d = at(sat, b.x1, b.y1, c) - at(sat, b.x0, b.y1, c) - at(sat, b.x1, b.y0, c) +
                             at(sat, b.x0, b.y0, c);
                m[c] = (float)(int32_t)d / scale / (float)area;
            } else {
                m[c] = ((atf(sat, b.x1, b.y1, c) - atf(sat, b.x0, b.y1, c)) -
                        (atf(sat, b.x1, b.y0, c) - atf(sat, b.x0, b.y0, c))) / (float)area;
            }
        }
        float got_mean = f == SAT_FP32_CENTERED ? m[0] + 0.5f : m[0];
        float got_var = m[1] - m[0] * m[0];
        se_mean += (got_mean - mean) * (got_mean - mean);
        se_var += (got_var - var) * (got_var - var);
    }
    *mean_rms = sqrt(se_mean / BOXES);
    return sqrt(se_var / BOXES);
}

/* Light at height 4 facing down; blocker (1 x 1) at height 2 is the near
 * plane; a sliver at height -0.22, hidden under the receiver, sets the far
 * plane, so the receiver (height 0) sits at d = 2 / 2.22 = 0.90. */
static void write_scene(const char *path)
{
    struct mesh_builder m = {0};
    mesh_add_quad(&m, v3(-6, 0, -6), v3(0, 0, 12), v3(12, 0, 0));
    mesh_add_quad(&m, v3(-0.5f, 2, -0.5f), v3(0, 0, 1), v3(1, 0, 0));
    mesh_add_quad(&m, v3(0, -0.22f, 0), v3(0, 0, 0.01f), v3(0.01f, 0, 0));
    struct gltf_scene_desc d = {
        .description = "SAT precision (test)", .shows = "depths far from 0.5",
        .camera_pos = v3(0, 3, 3), .camera_target = v3(0, 0, 0), .camera_yfov_rad = 0.8f,
        .camera_znear = 0.05f, .light_pos = v3(0, 4, 0), .light_target = v3(0, 0, 0),
        .light_width = 1, .light_height = 1,
    };
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    char *path = util_printf("%s/sat_precision.gltf", dir);
    write_scene(path);
    struct scene s;
    struct scene_mesh mesh = {0};
    struct shadowmap sm = {0};
    if (scene_load(path, &s) != 0 || gl_context_create() != 0 || shader_init(NULL) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    scene_mesh_upload(&s, &mesh);
    CHECK(shadowmap_create(&sm, &s, &(struct shadowmap_desc){.size_texels = N}) == 0, "shadow map");

    /* The SAT's input: linear depth from the depth map, converted as
     * shaders/depth.glsl does (same float operations, no fused ones). */
    float *moments = NULL;
    double var_rms[3], mean_rms[3];
    for (int f = SAT_FP32; f <= SAT_INT32; f++) {
        float scale;
        uint32_t *sat = build_sat(&sm, &mesh, (enum sat_format)f, &scale);
        if (!moments) {
            moments = xmalloc(sizeof(float) * 2 * N * N);
            float *depth = xmalloc(sizeof(float) * N * N);
            glBindTexture(GL_TEXTURE_2D, sm.products[SM_PRODUCT_DEPTH].texture);
            glPixelStorei(GL_PACK_ALIGNMENT, 4);
            glGetTexImage(GL_TEXTURE_2D, 0, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
            float n = sm.block.near_world, f = sm.block.far_world;
            for (int i = 0; i < N * N; i++) {
                float z = n * f / (depth[i] * (f - n) + n);
                float d = (z - n) / (f - n);
                moments[2 * i] = d, moments[2 * i + 1] = d * d;
            }
            free(depth);
            int far_from_half = 0;
            for (int i = 0; i < N * N; i++)
                far_from_half += fabsf(moments[2 * i] - 0.5f) > 0.35f;
            CHECK(far_from_half == N * N, "every depth far from 0.5: %d of %d", far_from_half, N * N);
        }
        if (f == SAT_INT32) {
            CHECK(scale == 262144.0f, "int32 scale for 64-texel boxes: 2^(30 - floor(log2(66^2))) = "
                  "2^18, got %g", scale);
            int32_exact(sat, moments, scale);
        }
        var_rms[f] = variance_rms(sat, (enum sat_format)f, scale, moments, &mean_rms[f]);
        free(sat);
    }
    printf("SAT at %d^2, rms error over %d boxes up to %dx%d texels:\n", N, BOXES, MAX_BOX, MAX_BOX);
    for (int f = SAT_FP32; f <= SAT_INT32; f++)
        printf("  %-14s mean %.3g  variance %.3g\n", sat_format_names[f], mean_rms[f], var_rms[f]);
    CHECK(var_rms[SAT_FP32] > var_rms[SAT_FP32_CENTERED] && mean_rms[SAT_FP32] > mean_rms[SAT_FP32_CENTERED],
          "centring must help fp32");
    CHECK(var_rms[SAT_FP32_CENTERED] >= var_rms[SAT_INT32] && mean_rms[SAT_FP32_CENTERED] >= mean_rms[SAT_INT32],
          "int32 must be at least as precise as fp32_centered");
    /* int32 errs only by its rounding, half a unit of 2^-18 per texel. */
    CHECK(mean_rms[SAT_INT32] <= 0.5 / 262144.0, "int32 mean error %.3g beyond its rounding",
          mean_rms[SAT_INT32]);

    free(moments);
    shadowmap_destroy(&sm);
    scene_mesh_destroy(&mesh);
    gl_context_destroy();
    scene_free(&s);
    free(path);
    remove_tree(dir);
    return check_finish();
}
