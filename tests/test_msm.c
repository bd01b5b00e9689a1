/* Protects Hamburger 4MSM (shaders/msm_common.glsl), which msm and msm_soft
 * share, run as the GPU runs it on moments chosen here:
 *   - where four moments determine the distribution (one or two depths),
 *     the bound is the true blocked share and z_blocker the blockers' mean
 *     depth: both depths in front of the receiver give G = 1 and their
 *     weighted mean (not the nearer root alone), one in front gives its
 *     mass and its depth, none gives 0;
 *   - moments known only to within half a fixed-point step 2^-k (what the
 *     int32 SAT of msm_soft hands over) still give those answers once
 *     msm_quantisation_bias(2^-k) is added to the moment bias, for every k
 *     the SAT can pick: without it, a 4096² map's 78 % of lit pixels went
 *     dark. */
#include "check.h"
#include "glsl_probe.h"
#include "run_cmd.h"

#include <math.h>
#include <stdint.h>

static char dir[] = "/tmp/sb_test_msm_XXXXXX";

#define PROBE_W 64
#define PROBE_H 64
#define CASES (PROBE_W * PROBE_H)
#define MSM_ALPHA 3e-5f  /* msm and msm_soft's default moment bias (fp32 arithmetic) */
#define QUANTISATION_BIAS 7.1  /* what msm_quantisation_bias must add per step (msm_common.glsl) */
enum { PROBE_BINDING = 7 };    /* clear of the layer's storage bindings */

/* The probe: case i is two vec4s, the moments b and (z, alpha, step,
 * floor); at pixel i, (G, z_blocker, the alpha used, 0) for b biased by
 * alpha, plus msm_quantisation_bias(step) where floor is 1. */
static const char probe_source[] =
    "#version 450 core\n"
    "#include \"msm_common.glsl\"\n"
    "layout(std430, binding = PROBE_BINDING) readonly buffer Cases { vec4 cases[]; };\n"
    "layout(location = 0) out vec4 result;\n"
    "void main()\n"
    "{\n"
    "    int i = int(gl_FragCoord.y) * PROBE_W + int(gl_FragCoord.x);\n"
    "    vec4 b = cases[2 * i], c = cases[2 * i + 1];\n"
    "    float alpha = c.y + (c.w > 0.0 ? msm_quantisation_bias(c.z) : 0.0), z_blocker;\n"
    "    float g = msm_occlusion(msm_bias(b, alpha), c.x, z_blocker);\n"
    "    result = vec4(g, z_blocker, alpha, 0.0);\n"
    "}\n";

struct msm_case {
    float b[4];
    float z, alpha, step, floor;
};

/* What a case stands for: two depths w[0] < w[1] (mass p at w[0]; p = 1
 * for one depth), the receiver at z, and the answer. */
struct truth {
    float w[2], p;
    float g, z_blocker;
};

static uint64_t rng = 0x2545f4914f6cdd1dull;
static double uniform(double lo, double hi)
{
    rng ^= rng << 13, rng ^= rng >> 7, rng ^= rng << 17;
    return lo + (hi - lo) * (double)(rng >> 11) / 9007199254740992.0;
}

/* The moments of mass p at w0 and 1 - p at w1, each moved by step / 2 up
 * or down at random (the extremes a box mean of rounded texels reaches). */
static void moments(const struct truth *t, double step, float b[4])
{
    for (int i = 0; i < 4; i++) {
        double e = i + 1, m = t->p * pow(t->w[0], e) + (1.0 - t->p) * pow(t->w[1], e);
        b[i] = (float)(m + (step > 0 ? (uniform(0, 1) < 0.5 ? -0.5 : 0.5) * step : 0.0));
    }
}

/* Fills a case: depths at least 0.1 apart in [-0.9, 0.6], the receiver
 * 0.05 to 0.3 behind both, on the farther (a blocker over a receiver), or
 * 0.05 in front of both, by kind % 3; one depth (kind / 3 == 1): the
 * receiver behind it, on it or in front of it. */
static void make_case(int kind, double step, bool floor, struct msm_case *c, struct truth *t)
{
    double a = uniform(-0.9, 0.5), b = uniform(a + 0.1, 0.6);
    bool one = kind / 3 == 1;
    t->w[0] = (float)a, t->w[1] = (float)b, t->p = one ? 1.0f : (float)uniform(0.1, 0.9);
    double mean = t->p * a + (1.0 - t->p) * b;
    switch (kind % 3) {
    case 0: /* behind all */
        c->z = (float)((one ? a : b) + uniform(0.05, 0.3)), t->g = 1.0f, t->z_blocker = (float)(one ? a : mean);
        break;
    case 1: /* on the farther (one depth: on it) */
        if (one)
            c->z = (float)a, t->g = 0.0f, t->z_blocker = c->z;
        else
            c->z = (float)b, t->g = t->p, t->z_blocker = (float)a;
        break;
    default: /* in front of all */
        c->z = (float)(a - 0.05), t->g = 0.0f, t->z_blocker = c->z;
    }
    moments(t, step, c->b);
    c->alpha = MSM_ALPHA, c->step = (float)step, c->floor = floor ? 1.0f : 0.0f;
}

/* Runs the cases; results CASES x 4. */
static void run(GLuint program, const struct msm_case *cases, float *results)
{
    GLuint buffer;
    glGenBuffers(1, &buffer);
    glBindBuffer(GL_SHADER_STORAGE_BUFFER, buffer);
    glBufferData(GL_SHADER_STORAGE_BUFFER, sizeof(struct msm_case) * CASES, cases, GL_STATIC_DRAW);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, PROBE_BINDING, buffer);
    glsl_probe_draw(program, PROBE_W, PROBE_H, results);
    glDeleteBuffers(1, &buffer);
}

static const char *const kind_names[6] = {
    "two depths, receiver behind both", "two depths, receiver on the farther",
    "two depths, receiver in front of both", "one depth, receiver behind it",
    "one depth, receiver on it", "one depth, receiver in front of it"};

/* Scores cases made with fixed-point step (0: exact moments), with the
 * quantisation bias added where floor is set (without it: a control,
 * nothing checked); returns the worst G error.
 * The bias mixes a share alpha of a spread distribution into the moments,
 * and the bound may then place mass of order alpha / dist² at the
 * receiver, dist being the distance of (1, z, z²) from the span of the
 * depths' (1, w, w²) (the Christoffel function of the biased Hankel
 * matrix), which shrinks as z nears a depth. Errors are read in units of
 * alpha / P², P the product of z's distances to the depths in front of it
 * (1 if none): a scale, not a derived bound. K = 4 is set from what was
 * measured: 1.9 (G) and 2.5 (z_blocker) at worst over all kinds and
 * steps. alpha is computed here, not read back, so a bias grown beyond
 * its derivation cannot widen its own tolerance. At k <= 8 alpha (>= 0.028)
 * makes 4 alpha / P² exceed 1 for the receiver-behind kinds: there those
 * checks say only that G is finite and in [0, 1]. z_blocker is checked
 * where a share is in front. */
static double score(GLuint program, double step, bool floor, const char *what)
{
    const double K = 4.0, alpha = MSM_ALPHA + (floor ? QUANTISATION_BIAS * step : 0.0);
    static struct msm_case cases[CASES];
    static struct truth truths[CASES];
    static float got[CASES][4];
    for (int i = 0; i < CASES; i++)
        make_case(i % 6, step, floor, &cases[i], &truths[i]);
    run(program, cases, &got[0][0]);
    double err_g[6] = {0}, err_z[6] = {0}, worst = 0, alpha_err = 0;
    int outside = 0;
    for (int i = 0; i < CASES; i++) {
        const struct truth *t = &truths[i];
        double z = cases[i].z, P = 1.0;
        for (int j = 0; j < (t->p < 1.0f ? 2 : 1); j++)
            if (t->w[j] < z)
                P *= z - t->w[j];
        double unit = alpha / (P * P);
        double eg = fabs(got[i][0] - t->g) / unit, ez = fabs(got[i][1] - t->z_blocker) / unit;
        err_g[i % 6] = fmax(err_g[i % 6], isfinite(eg) ? eg : INFINITY);
        if (t->g > 0)
            err_z[i % 6] = fmax(err_z[i % 6], isfinite(ez) ? ez : INFINITY);
        outside += !(got[i][0] >= 0.0f && got[i][0] <= 1.0f);
        alpha_err = fmax(alpha_err, fabs(got[i][2] - alpha) / alpha);
    }
    for (int k = 0; k < 6; k++)
        worst = fmax(worst, err_g[k]);
    if (!floor)  /* a control: only the worst error is wanted */
        return worst;
    CHECK(outside == 0, "%s: %d values of G are not in [0, 1]", what, outside);
    CHECK(alpha_err <= 1e-6, "%s: the shader's alpha differs from %g by %g of it", what, alpha, alpha_err);
    for (int k = 0; k < 6; k++) {
        printf("%-18s %-38s worst error, in alpha / P^2: G %.2f", what, kind_names[k], err_g[k]);
        printf(truths[k].g > 0 ? ", z_blocker %.2f\n" : "\n", err_z[k]);
        CHECK(err_g[k] <= K, "%s, %s: G errs by %g alpha / P^2", what, kind_names[k], err_g[k]);
        CHECK(err_z[k] <= K, "%s, %s: z_blocker errs by %g alpha / P^2", what, kind_names[k], err_z[k]);
    }
    return worst;
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    if (gl_context_create() != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    char *defines = util_printf("#define PROBE_W %d\n#define PROBE_BINDING %d\n", PROBE_W, PROBE_BINDING);
    GLuint program = glsl_probe_program(dir, probe_source, defines);
    free(defines);
    CHECK(program != 0, "the 4MSM probe must build");
    if (program) {
        score(program, 0.0, true, "exact moments");  /* alpha is MSM_ALPHA alone */
        for (int k = 4; k <= 24; k++) {  /* every scale sat_int32_scale can pick (k = 4: an 8192² map, a box as wide) */
            char *what = util_printf("step 2^-%d", k);
            score(program, ldexp(1.0, -k), true, what);
            free(what);
        }
        /* The control: at k = 13 (a 4096² map) without the quantisation
         * bias, the same cases must fail (measured: G 1 where 0 is true). */
        double control = score(program, ldexp(1.0, -13), false, "step 2^-13, no quantisation bias");
        printf("step 2^-13 without the quantisation bias: worst G error %.3g alpha / P^2\n", control);
        CHECK(control > 100.0, "without msm_quantisation_bias the cases must fail (worst %g)", control);
        glDeleteProgram(program);
    }
    gl_context_destroy();
    remove_tree(dir);
    return check_finish();
}
