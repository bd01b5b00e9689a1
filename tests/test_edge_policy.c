/* Protects the edge policy of the shadow-map layer (techniques/shadowmap.h,
 * DESIGN.md §5): past the map's edge every product continues as its edge
 * texels (clamp-to-edge), for every reader.
 *   - SAT reads (shaders/sat.glsl): over boxes crossing each edge and
 *     corner of a random map, the mean and variance equal a CPU reference
 *     of the clamp-to-edge-extended map over the full box, for every SAT
 *     format.
 *   - The techniques see the same edge: a plate crossing the frustum's
 *     edge shadows the ground on both sides of it; near the map's edge,
 *     where every kernel below reads past it, no technique lights the true
 *     umbra, and pcf and savsm at matched kernel widths agree on the
 *     shadow's diagonal edges as they cross the map's edge. */
#include "check.h"
#include "gltf_writer.h"
#include "run_cmd.h"
#include "base/image.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "techniques/shadowmap.h"

#include <math.h>
#include <stdint.h>
#include <string.h>

static char dir[] = "/tmp/sb_test_edge_XXXXXX";

/* ---- SAT reads past the edge ------------------------------------------- */

#define N 64             /* map side, texels */
#define STRIDE (N + 1)
#define PROBE_W 32       /* boxes per row of the probe's target */
#define PROBE_H 12
#define BOXES (PROBE_W * PROBE_H)
#define MAX_HALF 12.0    /* box half side, texels */
#define INT32_SCALE 65536.0f  /* makes the moments below integers; box sums stay below 2^26 */

/* The probe: sat_mean_variance of box i (centre_uv, half_uv) at pixel i. */
static const char probe_source[] =
    "#version 450 core\n"
    "#include \"sat.glsl\"\n"
    "layout(std430, binding = PROBE_BOXES) readonly buffer Boxes { vec4 boxes[]; };\n"
    "layout(location = 0) out vec4 result;  // mean, variance, returned\n"
    "void main()\n"
    "{\n"
    "    vec4 b = boxes[int(gl_FragCoord.y) * PROBE_W + int(gl_FragCoord.x)];\n"
    "    vec2 mean_var;\n"
    "    bool ok = sat_mean_variance(b.xy, b.zw, mean_var);\n"
    "    result = vec4(mean_var, ok ? 1.0 : 0.0, 0.0);\n"
    "}\n";
enum { PROBE_BOXES_BINDING = 7 };  /* clear of the layer's storage bindings */

static uint64_t rng = 0x9e3779b97f4a7c15ull;
static double uniform(double lo, double hi)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return lo + (hi - lo) * (double)(rng >> 11) / 9007199254740992.0;
}

/* On a multiple of 1/256 texel: uv = texels / N and lo, hi = centre ± half
 * are then exact in float, on the GPU as here. */
static float texels_q(double t) { return (float)(round(t * 256.0) / 256.0); }

/* Weight of texel k in [lo, hi) of the clamp-to-edge-extended line: its
 * overlap with the box, an edge texel's including all that lies past it. */
static double extended_weight(double lo, double hi, int k)
{
    double a = k == 0 ? -INFINITY : k, b = k == N - 1 ? INFINITY : k + 1;
    return fmax(0.0, fmin(hi, b) - fmax(lo, a));
}

/* A random box whose centre lies, along each axis, near the low edge, in
 * the middle or near the high edge (by category % 3 and category / 3), so
 * the nine categories cross every edge and corner, and none. Texels. */
static void random_box(int category, float centre[2], float half[2])
{
    for (int a = 0; a < 2; a++) {
        int where = a ? category / 3 : category % 3;
        double h = uniform(1.0, MAX_HALF);
        double c = where == 0 ? uniform(0.0, 0.9 * h) : where == 2 ? N - uniform(0.0, 0.9 * h)
                                                                    : uniform(h, N - h);
        centre[a] = texels_q(c), half[a] = texels_q(h);
    }
}

/* Renders the probe over the boxes with the SAT `sat` of format f bound as
 * the layer binds its product; results: BOXES x (mean, variance, ok, 0). */
static void probe(GLuint program, GLuint boxes, const uint32_t *sat, enum sat_format f, float *results)
{
    struct shadowmap sm = {0};
    sm.block.map_size_texels = N;
    sm.block.sat_format = (int)f;
    sm.block.sat_scale = f == SAT_INT32 ? INT32_SCALE : 1.0f;
    sm.block.sat_max_box_texels = (float)N;  /* no box is capped */
    glGenBuffers(1, &sm.ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, sm.ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof sm.block, &sm.block, GL_STATIC_DRAW);
    GLuint *buffer = &sm.products[SM_PRODUCT_MOMENTS_SAT].buffer;
    glGenBuffers(1, buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, *buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof(uint32_t) * 2 * STRIDE * STRIDE, sat, GL_STATIC_DRAW);

    GLuint target, fbo, vao;
    glGenTextures(1, &target);
    glBindTexture(GL_TEXTURE_2D, target);
    glTexStorage2D(GL_TEXTURE_2D, 1, GL_RGBA32F, PROBE_W, PROBE_H);
    glGenFramebuffers(1, &fbo);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glFramebufferTexture2D(GL_FRAMEBUFFER, GL_COLOR_ATTACHMENT0, GL_TEXTURE_2D, target, 0);
    CHECK(gl_framebuffer_complete(fbo, "SAT probe"), "probe framebuffer");
    glGenVertexArrays(1, &vao);

    shadowmap_bind(&sm);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PROBE_BOXES_BINDING, boxes);
    glBindFramebuffer(GL_FRAMEBUFFER, fbo);
    glViewport(0, 0, PROBE_W, PROBE_H);
    glUseProgram(program);
    glBindVertexArray(vao);
    glDrawArrays(GL_TRIANGLES, 0, 3);
    glReadPixels(0, 0, PROBE_W, PROBE_H, GL_RGBA, GL_FLOAT, results);
    glBindFramebuffer(GL_FRAMEBUFFER, 0);

    glDeleteVertexArrays(1, &vao);
    glDeleteFramebuffers(1, &fbo);
    glDeleteTextures(1, &target);
    glDeleteBuffers(1, buffer);
    glDeleteBuffers(1, &sm.ubo);
}

/* The SAT of format f over the depths d (N x N), as sat_build.comp lays it
 * out: (N+1)^2 pairs, a zero first row and column. */
static void build_sat(const double *d, enum sat_format f, uint32_t *sat)
{
    memset(sat, 0, sizeof(uint32_t) * 2 * STRIDE * STRIDE);
    for (int y = 1; y <= N; y++)
        for (int x = 1; x <= N; x++)
            for (int c = 0; c < 2; c++) {
                double e = d[(y - 1) * N + x - 1] - (f == SAT_FP32_CENTERED ? 0.5 : 0.0);
                double v = c ? e * e : e;
                uint32_t *s = &sat[2 * (y * STRIDE + x) + c];
                const uint32_t *left = s - 2, *down = s - 2 * STRIDE, *diag = down - 2;
                if (f == SAT_INT32) {
                    *s = (uint32_t)(v * INT32_SCALE) + *left + *down - *diag;
                } else {
                    float l, b, g, sum;
                    memcpy(&l, left, 4), memcpy(&b, down, 4), memcpy(&g, diag, 4);
                    sum = (float)v + l + b - g;
                    memcpy(s, &sum, 4);
                }
            }
}

/* Mean and variance of the depths d over the box centre ± half (texels)
 * of the clamp-to-edge-extended map, in double. */
static void reference(const double *d, const float centre[2], const float half[2], double out[2])
{
    double s1 = 0, s2 = 0, area = 4.0 * half[0] * half[1];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            double w = extended_weight(centre[0] - half[0], centre[0] + half[0], x) *
                       extended_weight(centre[1] - half[1], centre[1] + half[1], y);
            s1 += w * d[y * N + x], s2 += w * d[y * N + x] * d[y * N + x];
        }
    out[0] = s1 / area, out[1] = s2 / area - out[0] * out[0];
}

/* The probe's program, from a copy of shaders/ with the probe added; 0 if
 * it does not build (logged). */
static GLuint probe_program(void)
{
    char *copy = util_printf("cp '%s'/shaders/* '%s'", SB_SOURCE_DIR, dir);
    char *path = util_printf("%s/sat_probe.frag", dir);
    CHECK(system(copy) == 0, "%s", copy);
    util_write_file_atomic(path, probe_source, strlen(probe_source));
    struct strbuf defines = {0};
    shadowmap_shader_defines(&defines);
    strbuf_printf(&defines, "#define SM_LIGHT_SHAPE SM_LIGHT_RECT\n#define PROBE_BOXES %d\n"
                  "#define PROBE_W %d\n", PROBE_BOXES_BINDING, PROBE_W);
    GLuint program = 0;
    if (shader_init(dir) == 0)
        program = shader_program("SAT probe", defines.data,
                                 (const struct shader_stage[]){{GL_VERTEX_SHADER, {"fullscreen.vert"}},
                                                               {GL_FRAGMENT_SHADER, {"sat_probe.frag"}}},
                                 2);
    strbuf_free(&defines);
    free(copy), free(path);
    return program;
}

static void sat_reads_past_edge(void)
{
    /* Depths k/16: every moment is a multiple of 2^-8 below 1, so every SAT
     * value of every format is exact (fp32: sums below 2^12 need 20 bits;
     * int32: m * 2^16 is an integer) and so are the reader's box sums.
     * What remains is its float weighting of 36 positive box sums, a
     * relative error of about 36 * 2^-24 = 2e-6 on moments below 1, and
     * three times that on the variance m2 - m1^2: hence 1e-5 (measured
     * 2e-7). A box clipped to the map, the old policy, errs by up to 0.18
     * here. */
    const double tol = 1e-5;
    static const char *const where[9] = {  /* by random_box's category */
        "the low-x, low-y corner", "the low-y edge", "the high-x, low-y corner",
        "the low-x edge", "no edge", "the high-x edge",
        "the low-x, high-y corner", "the high-y edge", "the high-x, high-y corner"};
    double *d = xmalloc(sizeof(double) * N * N);
    for (int i = 0; i < N * N; i++)
        d[i] = floor(uniform(0.0, 17.0)) / 16.0;
    float boxes[BOXES][4];
    double want[BOXES][2];
    for (int i = 0; i < BOXES; i++) {
        float c[2], h[2];
        random_box(i % 9, c, h);
        boxes[i][0] = c[0] / N, boxes[i][1] = c[1] / N, boxes[i][2] = h[0] / N, boxes[i][3] = h[1] / N;
        reference(d, c, h, want[i]);
    }
    GLuint program = probe_program(), boxes_buffer;
    CHECK(program != 0, "the SAT probe must build");
    glGenBuffers(1, &boxes_buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, boxes_buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof boxes, boxes, GL_STATIC_DRAW);

    uint32_t *sat = xmalloc(sizeof(uint32_t) * 2 * STRIDE * STRIDE);
    float (*got)[4] = xmalloc(sizeof(float) * 4 * BOXES);
    for (int f = SAT_FP32; program && f <= SAT_INT32; f++) {
        build_sat(d, (enum sat_format)f, sat);
        probe(program, boxes_buffer, sat, (enum sat_format)f, &got[0][0]);
        int wrong[9] = {0}, worst = 0;
        double err = 0;
        for (int i = 0; i < BOXES; i++) {
            double e = fmax(fabs(got[i][0] - want[i][0]), fabs(got[i][1] - want[i][1]));
            if (e > err)
                err = e, worst = i;
            wrong[i % 9] += !(e <= tol) || got[i][2] != 1.0f;
        }
        printf("%-14s largest error over %d boxes %.3g (box %d: centre (%g, %g), half (%g, %g) "
               "texels)\n", sat_format_names[f], BOXES, err, worst, boxes[worst][0] * N,
               boxes[worst][1] * N, boxes[worst][2] * N, boxes[worst][3] * N);
        for (int k = 0; k < 9; k++)
            CHECK(wrong[k] == 0, "%s: %d boxes across %s differ from the clamp-to-edge reference "
                  "by more than %g", sat_format_names[f], wrong[k], where[k], tol);
    }
    free(got), free(sat), free(d);
    glDeleteBuffers(1, &boxes_buffer);
    if (program)
        glDeleteProgram(program);
}

/* ---- the techniques see the same edge ---------------------------------- */

#define W 192
#define H 192
#define NEAR_EDGE_PX 6  /* 2 texels: every kernel below reaches past the edge from there */
#define DEEP_PX 16      /* 5 texels, see the umbra check */

/* A light 3 above a ground 32 wide: the frustum takes its 75-degree cap, so
 * the map (256^2) ends 11.2 out on the ground and 5.6 out at height 1.5. A
 * diamond plate 1.5 up, from 4 to 10 out, crosses that edge; its shadow on
 * the ground (8 to 20 out) crosses the map's edge in a true umbra between
 * two diagonal penumbrae. The camera looks down on the ground across the
 * map's edge (a map texel is about 3.2 pixels there), the plate out of
 * view. */
static void write_scene(const char *path)
{
    struct mesh_builder m = {0};
    mesh_add_quad(&m, v3(-16, 0, -16), v3(0, 0, 32), v3(32, 0, 0));
    mesh_add_quad(&m, v3(4, 1.5f, 0), v3(3, 0, 3), v3(3, 0, -3));
    struct gltf_scene_desc d = {
        .description = "edge policy (test)", .shows = "a diamond plate across the map's edge",
        .camera_pos = v3(11.2f, 2.5f, 3.0f), .camera_target = v3(11.2f, 0, 2.5f), .camera_yfov_rad = 1.6f,
        .camera_znear = 0.05f, .light_pos = v3(0, 3, 0), .light_target = v3(0, 0, 0),
        .light_width = 1, .light_height = 1,
    };
    CHECK(gltf_write(path, &m, &d) == 0, "writing %s", path);
    mesh_free(&m);
}

/* Is there, within r pixels (a square) of (x, y), a pixel that is scored
 * or not as `scored` says, with V_gt at least v_min? */
static bool any_within(const float *v_gt, const float *mask, int x, int y, int r, bool scored,
                       float v_min)
{
    for (int yy = y - r; yy <= y + r; yy++)
        for (int xx = x - r; xx <= x + r; xx++)
            if (xx >= 0 && yy >= 0 && xx < W && yy < H && (mask[yy * W + xx] >= 0.5f) == scored &&
                v_gt[yy * W + xx] >= v_min)
                return true;
    return false;
}

static float *read_v(const char *technique)
{
    char *path = util_printf("%s/out/edge/%s/visibility.exr", dir, technique);
    struct exr_channel v[] = {{"V", NULL}};
    CHECK(image_read_exr(path, W, H, v, 1, NULL) == 0, "reading %s", path);
    free(path);
    return v[0].data;
}

/* Marks the scored pixels near the map's edge (an unscored pixel, past the
 * frustum, within NEAR_EDGE_PX) and, among them, those in deep umbra (no
 * scored pixel within DEEP_PX has V_gt >= 0.05, leak_fraction's umbra).
 * Returns how many are in deep umbra. */
static int mark_edge(const float *v_gt, const float *mask, bool *near, bool *deep)
{
    int near_count = 0, deep_count = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            int i = y * W + x;
            near[i] = mask[i] >= 0.5f && any_within(v_gt, mask, x, y, NEAR_EDGE_PX, false, -INFINITY);
            deep[i] = near[i] && !any_within(v_gt, mask, x, y, DEEP_PX, true, 0.05f);
            near_count += near[i], deep_count += deep[i];
        }
    printf("near the map's edge: %d scored pixels, %d in deep umbra\n", near_count, deep_count);
    return deep_count;
}

/* Every kernel in deep umbra at the edge covers only the plate in the
 * extended map: the edge texels hold the plate, and the plate's own edge,
 * seen from the light's centre, lies mid-penumbra (which is over 11 texels
 * wide), so over DEEP_PX + 5 = 10 texels away, beyond every kernel's reach
 * (8). Any lit pixel (V > 0.25, leak_fraction's threshold) is the edge
 * read as lit: none is allowed. */
static void no_light_in_umbra(const char *technique, const float *v, const bool *deep, int deep_count)
{
    int lit = 0;
    for (int i = 0; v && i < W * H; i++)
        lit += deep[i] && v[i] > 0.25f;
    CHECK(v && lit == 0, "%s lights %d of %d deep-umbra pixels at the map's edge", technique, lit,
          deep_count);
}

/* pcf (a 10 x 10 grid over a 12-texel square) and savsm (the square's
 * exact integral) estimate the same covered share where the plate's
 * diagonal edges cross the map's edge: two depths make savsm's bound
 * exact, and the grid's share of a straight edge errs by under one row of
 * cells, 1/10, rms about 1/10 / sqrt(12) = 0.03; hence 0.05 (measured
 * 0.014). The old policies differ here by 0.39 (depth border lit) and
 * 0.084 (SAT box clipped). */
static void pcf_matches_savsm(const float *pcf, const float *savsm, const bool *near)
{
    double se = 0;
    int n = 0;
    for (int i = 0; pcf && savsm && i < W * H; i++) {
        bool soft = (pcf[i] > 0.02f && pcf[i] < 0.98f) || (savsm[i] > 0.02f && savsm[i] < 0.98f);
        if (near[i] && soft)
            se += (pcf[i] - savsm[i]) * (pcf[i] - savsm[i]), n++;
    }
    double rms = n ? sqrt(se / n) : NAN;
    printf("pcf vs savsm near the map's edge: rms difference %.4f over %d soft pixels\n", rms, n);
    CHECK(n >= 50, "the diagonal penumbrae must cross the map's edge: %d pixels", n);
    CHECK(rms < 0.05, "pcf and savsm must see the same edge: rms difference %.4f", rms);
}

static void techniques_see_same_edge(const char *sb)
{
    char *scene = util_printf("%s/edge.gltf", dir);
    write_scene(scene);
    /* Kernels that reach past the map's edge from 2 texels inside it:
     * pcf's 12-texel square grid and savsm's 12-texel box (matched), vsm's
     * 8-texel blur, pcss's and pcss_savsm's search (about 6 texels). */
    static const char *const names[] = {"pcf", "savsm", "pcss", "vsm", "pcss_savsm"};
    char *cmd = util_printf("%s run --scene %s --technique pcf,savsm,pcss,vsm,pcss_savsm "
                            "--set pcf.pattern=grid --set pcf.samples=100 --set pcf.radius_texels=6 "
                            "--set savsm.box_width_texels=12 --set vsm.blur_radius_texels=8 "
                            "--width %d --height %d --gt-samples 256 --shadow-map-size 256 "
                            "--frames 1 --warmup 0 --no-cache -q --out %s/out",
                            sb, scene, W, H, dir);
    struct strbuf err = {0};
    int status = run_cmd(cmd, &err, NULL);
    CHECK(status == 0, "run exit %d: %s", status, err.data);

    char *gt_path = util_printf("%s/out/edge/groundtruth.exr", dir);
    struct exr_channel gt[] = {{"V", NULL}, {"mask", NULL}};
    bool *near = xcalloc(W * H, sizeof *near), *deep = xcalloc(W * H, sizeof *deep);
    if (image_read_exr(gt_path, W, H, gt, 2, NULL) == 0) {
        int deep_count = mark_edge(gt[0].data, gt[1].data, near, deep);
        CHECK(deep_count >= 200, "the scene must put deep umbra at the map's edge: %d pixels",
              deep_count);
        float *v[5];
        for (int t = 0; t < 5; t++) {
            v[t] = read_v(names[t]);
            no_light_in_umbra(names[t], v[t], deep, deep_count);
        }
        pcf_matches_savsm(v[0], v[1], near);
        for (int t = 0; t < 5; t++)
            free(v[t]);
    } else {
        CHECK(false, "ground truth missing");
    }
    free(gt[0].data), free(gt[1].data);
    free(near), free(deep);
    free(gt_path), free(cmd), free(scene);
    strbuf_free(&err);
}

int main(int argc, char **argv)
{
    if (argc < 2 || !mkdtemp(dir))
        return 1;
    if (gl_context_create() != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    sat_reads_past_edge();
    gl_context_destroy();
    techniques_see_same_edge(argv[1]);
    remove_tree(dir);
    return check_finish();
}
