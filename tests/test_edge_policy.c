/* Protects the edge policy of the shadow-map layer (techniques/shadowmap.h,
 * docs/design.md §5): past the map's edge every product continues as its edge
 * texels (clamp-to-edge), for every reader.
 *   - SAT reads (shaders/sat.glsl): over boxes crossing each edge and
 *     corner of a random map, or lying wholly past it, the moments read
 *     equal a CPU reference of the clamp-to-edge-extended map over the
 *     full box, for both tables (two and four moments) in every format.
 *   - The techniques see the same edge: a plate crossing the frustum's
 *     edge shadows the ground on both sides of it; near the map's edge,
 *     where the kernels below read past it, no technique of the registry
 *     lights the true umbra, and pcf and savsm at matched kernel widths
 *     agree on the shadow's diagonal edges as they cross the map's edge. */
#include "check.h"
#include "gltf_writer.h"
#include "glsl_probe.h"
#include "run_cmd.h"
#include "base/image.h"
#include "score/metrics.h"
#include "techniques/technique.h"

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
#define INT32_SCALE 65536.0f  /* makes the moments below integers; box sums stay below 2^28 */

/* The probe, for SAT_CHANNELS 2 or 4 (both tables): at pixel i, box i's
 * (centre_uv, half_uv) mean moments as sat.glsl reads them; for 2 channels
 * sat_mean_variance's (mean, variance). A box it calls empty gives -1000. */
static const char probe_source[] =
    "#version 450 core\n"
    "#include \"sat.glsl\"\n"
    "layout(std430, binding = PROBE_BOXES) readonly buffer Boxes { vec4 boxes[]; };\n"
    "layout(location = 0) out vec4 result;\n"
    "void main()\n"
    "{\n"
    "    vec4 b = boxes[int(gl_FragCoord.y) * PROBE_W + int(gl_FragCoord.x)];\n"
    "#if SAT_CHANNELS == 4\n"
    "    vec4 mean;\n"
    "    result = sat_box_mean(b.xy, b.zw, mean) ? mean : vec4(-1000.0);\n"
    "#else\n"
    "    vec2 mean_var;\n"
    "    result = sat_mean_variance(b.xy, b.zw, mean_var) ? vec4(mean_var, 0.0, 0.0) : vec4(-1000.0);\n"
    "#endif\n"
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
 * the nine categories cross every edge and corner, and none. Near an edge
 * the centre falls from 0.9 half-sides inside the map to 1.5 outside it
 * (vssm's sub-boxes): about a fifth of those boxes lie wholly past the
 * edge. Texels. */
static void random_box(int category, float centre[2], float half[2])
{
    for (int a = 0; a < 2; a++) {
        int where = a ? category / 3 : category % 3;
        double h = uniform(1.0, MAX_HALF);
        double c = where == 0 ? uniform(-1.5 * h, 0.9 * h) : where == 2 ? N - uniform(-1.5 * h, 0.9 * h)
                                                                        : uniform(h, N - h);
        centre[a] = texels_q(c), half[a] = texels_q(h);
    }
}

/* Depth d's moments as the table of c channels stores them: 2, (e, e²)
 * with e = d, or d - 0.5 for fp32_centered; 4, (w, w², w³, w⁴) with
 * w = 2d - 1. */
static void moments(double d, int c, enum sat_format f, double m[4])
{
    double e = c == 4 ? 2.0 * d - 1.0 : d - (f == SAT_FP32_CENTERED ? 0.5 : 0.0);
    for (int i = 0; i < c; i++)
        m[i] = i ? m[i - 1] * e : e;
}

/* The SAT of c channels and format f over the depths d (N x N), as
 * sat_build.comp lays it out: (N+1)^2 entries, a zero first row and
 * column. */
static void build_sat(const double *d, int c, enum sat_format f, uint32_t *sat)
{
    memset(sat, 0, sizeof(uint32_t) * 4 * STRIDE * STRIDE);
    for (int y = 1; y <= N; y++)
        for (int x = 1; x <= N; x++) {
            double m[4];
            moments(d[(y - 1) * N + x - 1], c, f, m);
            for (int i = 0; i < c; i++) {
                uint32_t *s = &sat[c * (y * STRIDE + x) + i];
                const uint32_t *left = s - c, *down = s - c * STRIDE, *diag = down - c;
                if (f == SAT_INT32) {
                    *s = (uint32_t)(int32_t)(m[i] * INT32_SCALE) + *left + *down - *diag;
                } else {
                    float l, b, g, sum;
                    memcpy(&l, left, 4), memcpy(&b, down, 4), memcpy(&g, diag, 4);
                    sum = (float)m[i] + l + b - g;
                    memcpy(s, &sum, 4);
                }
            }
        }
}

/* What the probe returns for the box centre ± half (texels) of the
 * clamp-to-edge-extended map of depths d, in double. */
static void reference(const double *d, int c, enum sat_format f, const float centre[2],
                      const float half[2], double out[4])
{
    double sum[4] = {0}, area = 4.0 * half[0] * half[1];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            double w = extended_weight(centre[0] - half[0], centre[0] + half[0], x) *
                       extended_weight(centre[1] - half[1], centre[1] + half[1], y), m[4];
            moments(d[y * N + x], c, f, m);
            for (int i = 0; i < c; i++)
                sum[i] += w * m[i];
        }
    for (int i = 0; i < 4; i++)
        out[i] = i < c ? sum[i] / area : 0.0;
    if (c == 2) {  /* the variance is shift-invariant; sat_mean_variance's mean is of d */
        out[1] -= out[0] * out[0];
        out[0] += f == SAT_FP32_CENTERED ? 0.5 : 0.0;
    }
}

/* Runs the probe of c channels over the boxes with the SAT `sat` of format
 * f bound as the layer binds its product; results: BOXES x 4. */
static void probe(GLuint program, GLuint boxes, int c, const uint32_t *sat, enum sat_format f,
                  float *results)
{
    struct shadowmap sm = {0};
    sm.block.map_size_texels = N;
    for (int k = 0; k < SM_SAT_TABLES; k++)  /* whichever the probe reads; no box is capped */
        sm.block.sat[k] = (struct shadowmap_sat_block){(int)f, f == SAT_INT32 ? INT32_SCALE : 1.0f, (float)N, 0};
    glGenBuffers(1, &sm.ubo);
    glBindBuffer(GL_UNIFORM_BUFFER, sm.ubo);
    glBufferData(GL_UNIFORM_BUFFER, sizeof sm.block, &sm.block, GL_STATIC_DRAW);
    GLuint *buffer = &sm.products[c == 4 ? SM_PRODUCT_MSM_SAT : SM_PRODUCT_MOMENTS_SAT].buffer;
    glGenBuffers(1, buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, *buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof(uint32_t) * c * STRIDE * STRIDE, sat, GL_STATIC_DRAW);
    shadowmap_bind(&sm);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PROBE_BOXES_BINDING, boxes);
    glsl_probe_draw(program, PROBE_W, PROBE_H, results);
    glDeleteBuffers(1, buffer);
    glDeleteBuffers(1, &sm.ubo);
}

static void sat_reads_past_edge(void)
{
    /* Depths k/16: w = 2d - 1 is a multiple of 1/8 and every moment of
     * either table a multiple of 2^-12 of magnitude at most 1, so every
     * SAT value of every format is exact (fp32: sums below 2^12 need 24
     * bits; int32: m * 2^16 is an integer) and so are the reader's box
     * sums. What remains is its float weighting of 36 box sums, a
     * relative error of about 36 * 2^-24 = 2e-6 on moments of magnitude
     * below 1, and three times that on the variance m2 - m1^2: hence
     * 1e-5 (measured 3e-7 on two channels, 7e-8 on four). A box clipped to the map, the
     * old policy, errs by up to 0.18 here. */
    const double tol = 1e-5;
    static const char *const where[9] = {  /* by random_box's category */
        "the low-x, low-y corner", "the low-y edge", "the high-x, low-y corner",
        "the low-x edge", "no edge", "the high-x edge",
        "the low-x, high-y corner", "the high-y edge", "the high-x, high-y corner"};
    double *d = xmalloc(sizeof(double) * N * N);
    for (int i = 0; i < N * N; i++)
        d[i] = floor(uniform(0.0, 17.0)) / 16.0;
    float boxes[BOXES][4];
    int outside = 0;  /* boxes wholly past an edge */
    for (int i = 0; i < BOXES; i++) {
        float c[2], h[2];
        random_box(i % 9, c, h);
        boxes[i][0] = c[0] / N, boxes[i][1] = c[1] / N, boxes[i][2] = h[0] / N, boxes[i][3] = h[1] / N;
        outside += c[0] + h[0] < 0 || c[0] - h[0] > N || c[1] + h[1] < 0 || c[1] - h[1] > N;
    }
    printf("%d of %d boxes lie wholly past an edge\n", outside, BOXES);
    CHECK(outside >= BOXES / 20, "too few boxes wholly past an edge (%d) to test them", outside);
    GLuint boxes_buffer;
    glGenBuffers(1, &boxes_buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, boxes_buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof boxes, boxes, GL_STATIC_DRAW);

    uint32_t *sat = xmalloc(sizeof(uint32_t) * 4 * STRIDE * STRIDE);
    float (*got)[4] = xmalloc(sizeof(float) * 4 * BOXES);
    for (int c = 2; c <= 4; c += 2) {
        char *defines = util_printf("#define SAT_CHANNELS %d\n#define PROBE_BOXES %d\n#define PROBE_W %d\n", c,
                                    PROBE_BOXES_BINDING, PROBE_W);
        GLuint program = glsl_probe_program(dir, probe_source, defines);
        free(defines);
        CHECK(program != 0, "the SAT probe (%d channels) must build", c);
        for (int f = SAT_FP32; program && f <= SAT_INT32; f++) {
            if (c == 4 && f == SAT_FP32_CENTERED)
                continue;  /* not offered for four channels */
            build_sat(d, c, (enum sat_format)f, sat);
            probe(program, boxes_buffer, c, sat, (enum sat_format)f, &got[0][0]);
            int wrong[9] = {0}, worst = 0;
            double err = 0;
            for (int i = 0; i < BOXES; i++) {
                double want[4], e = 0;
                reference(d, c, (enum sat_format)f, (const float[]){boxes[i][0] * N, boxes[i][1] * N},
                          (const float[]){boxes[i][2] * N, boxes[i][3] * N}, want);
                for (int k = 0; k < c; k++)
                    e = fmax(e, fabs(got[i][k] - want[k]));
                if (e > err)
                    err = e, worst = i;
                wrong[i % 9] += !(e <= tol);
            }
            printf("%d channels, %-14s largest error over %d boxes %.3g (box %d: centre (%g, %g), "
                   "half (%g, %g) texels)\n", c, sat_format_names[f], BOXES, err, worst,
                   boxes[worst][0] * N, boxes[worst][1] * N, boxes[worst][2] * N, boxes[worst][3] * N);
            for (int k = 0; k < 9; k++)
                CHECK(wrong[k] == 0, "%d channels, %s: %d boxes across %s differ from the clamp-to-edge "
                      "reference by more than %g", c, sat_format_names[f], wrong[k], where[k], tol);
        }
        if (program)
            glDeleteProgram(program);
    }
    free(got), free(sat), free(d);
    glDeleteBuffers(1, &boxes_buffer);
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
            deep[i] = near[i] && !any_within(v_gt, mask, x, y, DEEP_PX, true, (float)METRICS_LEAK_GT);
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
        lit += deep[i] && v[i] > (float)METRICS_LEAK_TECH;
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
    /* Every technique (the registry's), and kernels that reach past the
     * map's edge from 2 texels inside it: pcf's 12-texel square grid and
     * savsm's 12-texel box (matched), vsm's 8-texel blur, pcss's and
     * pcss_savsm's search (about 6 texels). babylon_pcss fades its shadow
     * toward lit by the blocker-to-receiver gap in its depth metric
     * (mix(shadow, 1, gap), docs/engines.md): the plate-to-ground gap is
     * most of the fitted range, which lights the umbra wherever it falls,
     * not at the edge only, so the range is widened 20 times (every gap
     * under 0.05), as its check cells on parallel_planes do. */
    struct strbuf names = {0};
    technique_names(&names, ",");
    char *cmd = util_printf("%s run --scene %s --technique %s --settings default "
                            "--set pcf.pattern=grid --set pcf.samples=100 --set pcf.radius_texels=6 "
                            "--set savsm.box_width_texels=12 --set vsm.blur_radius_texels=8 "
                            "--set babylon_pcss.shadow_max_z_scale=20 "
                            "--width %d --height %d --gt-samples 256 --shadow-map-size 256 "
                            "--frames 1 --warmup 0 --no-cache -q --out %s/out",
                            sb, scene, names.data, W, H, dir);
    strbuf_free(&names);
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
        for (int t = 0; technique_list[t]; t++) {
            float *v = read_v(technique_list[t]->name);
            no_light_in_umbra(technique_list[t]->name, v, deep, deep_count);
            free(v);
        }
        float *pcf = read_v("pcf"), *savsm = read_v("savsm");
        pcf_matches_savsm(pcf, savsm, near);
        free(pcf), free(savsm);
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
    if (gl_context_create(GL_BACKEND_OSMESA) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    sat_reads_past_edge();
    gl_context_destroy();
    techniques_see_same_edge(argv[1]);
    remove_tree(dir);
    return check_finish();
}
