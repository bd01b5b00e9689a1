/* Protects 4MSM (shaders/msm_common.glsl), Hamburger, which msm and
 * msm_soft share, and Hausdorff, msm's option, run as the GPU runs them on
 * moments chosen here:
 *   - where four moments determine the distribution (one or two depths),
 *     the bound is the true blocked share and z_blocker the blockers' mean
 *     depth: both depths in front of the receiver give G = 1 and their
 *     weighted mean (not the nearer root alone), one in front gives its
 *     mass and its depth, none gives 0;
 *   - moments known only to within half a fixed-point step 2^-k (what the
 *     int32 SAT of msm_soft hands over) still give those answers once
 *     msm_quantisation_bias(2^-k) is added to the moment bias, for every k
 *     the SAT can pick: without it, a 4096² map's 78 % of lit pixels went
 *     dark;
 *   - on moments of three to five depths, Hausdorff's G is the sharpest
 *     bound, certified here in double precision independently of how the
 *     shader finds it (see certify()), and not below Hamburger's (by more
 *     than 1e-3). */
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
/* msm_quantisation_bias's derivation (msm_common.glsl), done here: with the
 * error matrix's norm at most sqrt(2) step and the target's Hankel matrix's
 * least eigenvalue (1.375 - sqrt(0.953125)) / 2, alpha >= this x step
 * suffices, to first order. */
#define QUANTISATION_DERIVED (sqrt(2.0) / ((1.375 - sqrt(0.953125)) / 2))
enum { PROBE_BINDING = 7 };    /* clear of the layer's storage bindings */

/* The probe: case i is two vec4s, the moments b and (z, alpha, step,
 * floor); at pixel i, (G, z_blocker, the alpha used) for b biased by
 * alpha, plus msm_quantisation_bias(step) where floor is 1, and
 * Hausdorff's G for b biased by alpha alone (msm, its one user, reads
 * fp32 moments, never the int32 SAT's), towards its own target, or
 * Hamburger's where floor is -1 (a control). */
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
    "    vec4 bh = c.w < 0.0 ? msm_bias(b, c.y) : msm_hausdorff_bias(b, c.y);\n"
    "    result = vec4(g, z_blocker, alpha, msm_occlusion_hausdorff(bh, c.x));\n"
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
 * nothing checked); returns the worst G error. Hausdorff is scored where
 * the moments are as exact as msm's fp32 product holds them (step at most
 * 2^-24: fp32 rounds a moment in [-1, 1] by at most 2^-25).
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
    const double K = 4.0, alpha = MSM_ALPHA + (floor ? SM_MSM_QUANTISATION_FACTOR * step : 0.0);
    const bool hausdorff = step <= ldexp(1.0, -24);
    static struct msm_case cases[CASES];
    static struct truth truths[CASES];
    static float got[CASES][4];
    for (int i = 0; i < CASES; i++)
        make_case(i % 6, step, floor, &cases[i], &truths[i]);
    run(program, cases, &got[0][0]);
    double err_g[6] = {0}, err_z[6] = {0}, err_h[6] = {0}, worst = 0, alpha_err = 0;
    int outside = 0;
    for (int i = 0; i < CASES; i++) {
        const struct truth *t = &truths[i];
        double z = cases[i].z, P = 1.0;
        for (int j = 0; j < (t->p < 1.0f ? 2 : 1); j++)
            if (t->w[j] < z)
                P *= z - t->w[j];
        double unit = alpha / (P * P);
        double eg = fabs(got[i][0] - t->g) / unit, ez = fabs(got[i][1] - t->z_blocker) / unit;
        double eh = fabs(got[i][3] - t->g) / (MSM_ALPHA / (P * P));
        err_g[i % 6] = fmax(err_g[i % 6], isfinite(eg) ? eg : INFINITY);
        err_h[i % 6] = fmax(err_h[i % 6], isfinite(eh) ? eh : INFINITY);
        if (t->g > 0)
            err_z[i % 6] = fmax(err_z[i % 6], isfinite(ez) ? ez : INFINITY);
        outside += !(got[i][0] >= 0.0f && got[i][0] <= 1.0f) + !(got[i][3] >= 0.0f && got[i][3] <= 1.0f);
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
        printf(truths[k].g > 0 ? ", z_blocker %.2f" : "", err_z[k]);
        printf(hausdorff ? ", Hausdorff G %.2f\n" : "\n", err_h[k]);
        CHECK(err_g[k] <= K, "%s, %s: G errs by %g alpha / P^2", what, kind_names[k], err_g[k]);
        CHECK(!hausdorff || err_h[k] <= K, "%s, %s: Hausdorff's G errs by %g alpha / P^2", what, kind_names[k],
              err_h[k]);
        CHECK(err_z[k] <= K, "%s, %s: z_blocker errs by %g alpha / P^2", what, kind_names[k], err_z[k]);
    }
    return worst;
}

/* Solves a x = y, n <= 5 unknowns, by elimination with partial pivoting;
 * false where a is singular. */
static bool solve(int n, double a[5][5], double y[5], double x[5])
{
    for (int c = 0; c < n; c++) {
        int p = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(a[r][c]) > fabs(a[p][c]))
                p = r;
        if (a[p][c] == 0.0)
            return false;
        for (int k = 0; k < n; k++) {
            double t = a[c][k]; a[c][k] = a[p][k], a[p][k] = t;
        }
        double t = y[c]; y[c] = y[p], y[p] = t;
        for (int r = c + 1; r < n; r++) {
            double f = a[r][c] / a[c][c];
            for (int k = c; k < n; k++)
                a[r][k] -= f * a[c][k];
            y[r] -= f * y[c];
        }
    }
    for (int r = n - 1; r >= 0; r--) {
        double s = y[r];
        for (int k = r + 1; k < n; k++)
            s -= a[r][k] * x[k];
        x[r] = s / a[r][r];
    }
    return true;
}

/* The sharpest lower bound on P(W < z) over distributions on [-1, 1] with
 * moments b (b[0] = 1), with its certificate, in double precision: a
 * support S through z (Hamburger's {z, z2, z3} where both roots are in
 * [-1, 1], else {-1, z, x, 1}, x the root of the linear equation
 * E[(W + 1)(W - z)(W - x)(W - 1)] = 0), weights on S, all >= 0, that
 * reproduce all five moments, and a quartic p <= [w < z] on [-1, 1] (on a
 * grid of 20001 points) equal to [s < z] at each s in S, E[p] the weights'
 * share. Then every
 * distribution has P(W < z) >= E[p(W)] = the weights' share in front of
 * z, which one of them (the weights) attains: no bound is sharper, none
 * valid is higher. How S was found does not matter to the proof. false
 * where a step fails; *hausdorff says which support. */
static bool certify(const double b[5], double z, double *g, bool *hausdorff)
{
    double d2 = b[2] - b[1] * b[1], l32 = (b[3] - b[1] * b[2]) / d2;
    double d3 = b[4] - b[2] * b[2] - l32 * l32 * d2;
    double c3 = (z * z - b[2] - l32 * (z - b[1])) / d3, c2 = (z - b[1]) / d2 - l32 * c3;
    double c1 = 1.0 - b[1] * c2 - b[2] * c3, disc = c2 * c2 - 4.0 * c3 * c1;
    double s[4] = {0}, flat[2];
    int n, nflat;
    if (disc >= 0 && c3 != 0) {
        double r0 = (-c2 - sqrt(disc)) / (2.0 * c3), r1 = (-c2 + sqrt(disc)) / (2.0 * c3);
        s[1] = fmin(r0, r1), s[2] = fmax(r0, r1);
    }
    *hausdorff = !(disc >= 0 && c3 != 0 && s[1] >= -1.0 && s[2] <= 1.0);
    if (!*hausdorff) {
        n = 3, s[0] = z, nflat = 2, flat[0] = s[1], flat[1] = s[2];
    } else {
        /* E[(W² - 1)(W - z)(W - x)] = 0, linear in x. */
        double e1 = b[4] - z * b[3] - b[2] + z * b[1], e0 = b[3] - z * b[2] - b[1] + z * b[0];
        n = 4, s[0] = -1.0, s[1] = z, s[2] = e1 / e0, s[3] = 1.0, nflat = 1, flat[0] = s[2];
        if (!(s[2] > -1.0 && s[2] < 1.0))
            return false;
    }
    /* Weights from the first n moments; the rest must follow. */
    double a[5][5], y[5], w[5], coef[5];
    for (int k = 0; k < n; k++) {
        for (int j = 0; j < n; j++)
            a[k][j] = pow(s[j], k);
        y[k] = b[k];
    }
    if (!solve(n, a, y, w))
        return false;
    for (int k = 0; k < 5; k++) {
        double m = 0;
        for (int j = 0; j < n; j++)
            m += w[j] * pow(s[j], k);
        if (fabs(m - b[k]) > 1e-9)
            return false;
    }
    *g = 0;
    for (int j = 0; j < n; j++) {
        if (w[j] < -1e-12)
            return false;
        *g += s[j] < z ? w[j] : 0.0;
    }
    /* p: its value at each support point, flat at the others than z. */
    int row = 0;
    for (int j = 0; j < n; j++, row++) {
        for (int k = 0; k < 5; k++)
            a[row][k] = pow(s[j], k);
        y[row] = s[j] < z;
    }
    for (int j = 0; j < nflat; j++, row++) {
        for (int k = 0; k < 5; k++)
            a[row][k] = k ? k * pow(flat[j], k - 1) : 0.0;
        y[row] = 0.0;
    }
    if (!solve(5, a, y, coef))
        return false;
    double mean = 0;  /* E[p], which must be the weights' share */
    for (int k = 0; k < 5; k++)
        mean += coef[k] * b[k];
    if (fabs(mean - *g) > 1e-9)
        return false;
    for (int i = 0; i <= 20000; i++) {
        double x = -1.0 + i / 10000.0, p = 0;
        for (int k = 4; k >= 0; k--)
            p = p * x + coef[k];
        if (p > (x < z ? 1.0 : 0.0) + 1e-9)
            return false;
    }
    return true;
}

/* Hausdorff's G against certify() on three to five depths at random in
 * [-0.95, 0.95], the receiver at least 0.05 from each; moments rounded
 * to fp32 as the product holds them, biased by alpha. */
static void hausdorff_against_certificate(GLuint program, double alpha)
{
    static const double target[5] = {1.0, 0.0, 1.0 / 3.0, 0.0, 0.2};  /* MSM_HAUSDORFF_BIAS_TARGET */
    static struct msm_case cases[CASES];
    static double ref[CASES];
    static bool branch[CASES];
    static float got[CASES][4];
    int uncertified = 0, in_branch = 0;
    for (int i = 0; i < CASES; i++) {
        int n = 3 + i % 3;
        double w[5], p[5], sum = 0, z;
        for (int j = 0; j < n; j++)
            w[j] = uniform(-0.95, 0.95), p[j] = uniform(0.05, 1.0), sum += p[j];
        bool near;
        do {
            z = uniform(-0.95, 0.95), near = false;
            for (int j = 0; j < n; j++)
                near |= fabs(z - w[j]) < 0.05;
        } while (near);
        double b[5] = {1.0};
        for (int k = 1; k < 5; k++) {
            double m = 0;
            for (int j = 0; j < n; j++)
                m += p[j] / sum * pow(w[j], k);
            cases[i].b[k - 1] = (float)m;
            b[k] = (1.0 - alpha) * cases[i].b[k - 1] + alpha * target[k];
        }
        cases[i].z = (float)z, cases[i].alpha = (float)alpha, cases[i].step = 0, cases[i].floor = 0;
        if (!certify(b, (double)(float)z, &ref[i], &branch[i]))
            uncertified++, ref[i] = NAN;  /* fails the error check too */
        in_branch += branch[i];
    }
    run(program, cases, &got[0][0]);
    double err = 0, below = 0, gain = 0;
    for (int i = 0; i < CASES; i++) {
        err = fmax(err, isnan(ref[i]) ? INFINITY : fabs(got[i][3] - ref[i]));
        below = fmax(below, got[i][0] - got[i][3]);  /* their bias targets differ: by O(alpha) */
        gain += branch[i] ? got[i][3] - got[i][0] : 0.0;
    }
    printf("Hausdorff, alpha %g: %d of %d cases off Hamburger's support; worst error against the certified "
           "bound %.3g; Hamburger above it by at most %.3g; mean gain over Hamburger there %.4f\n",
           alpha, in_branch, CASES, err, below, in_branch ? gain / in_branch : 0.0);
    CHECK(uncertified == 0, "alpha %g: %d cases have no certified bound", alpha, uncertified);
    CHECK(in_branch >= CASES / 10, "alpha %g: only %d cases test the Hausdorff branch", alpha, in_branch);
    /* 1e-3: fp32's rounding of the moments (2^-25) through the bound's
     * conditioning, measured 6.1e-4 at alpha 3e-5 and 5e-6 at 3e-3; the
     * branch left out (Hamburger's G) errs by the mean gain, 0.033. */
    CHECK(err <= 1e-3, "alpha %g: Hausdorff's G errs by %g", alpha, err);
    CHECK(below <= 1e-3, "alpha %g: Hamburger's G exceeds Hausdorff's by %g", alpha, below);
}

/* The control for Hausdorff's bias target: towards Hamburger's, on the
 * edge of the moment space on [-1, 1], fp32's rounding of one depth's
 * moments (step 2^-24) must give a receiver on that depth ten times the
 * shadow the test allows, 4 alpha (measured 146 alpha). */
static void hausdorff_target_control(GLuint program)
{
    static struct msm_case cases[CASES];
    static struct truth truths[CASES];
    static float got[CASES][4];
    for (int i = 0; i < CASES; i++) {
        make_case(4, ldexp(1.0, -24), false, &cases[i], &truths[i]);  /* one depth, receiver on it */
        cases[i].floor = -1.0f;
    }
    run(program, cases, &got[0][0]);
    double worst = 0;
    for (int i = 0; i < CASES; i++)
        worst = fmax(worst, got[i][3] / MSM_ALPHA);
    printf("Hausdorff biased towards Hamburger's target, one depth at the receiver, fp32 rounding: "
           "worst G %.3g alpha (truth 0)\n", worst);
    CHECK(worst > 40.0, "the control must fail: worst G %g alpha", worst);
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    if (gl_context_create(GL_BACKEND_OSMESA) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    /* The factor the shaders use is sufficient (at least the derivation's)
     * and close to it (its bias bleeds: grown further, it would also widen
     * the tolerances below, which are in units of alpha). */
    CHECK(SM_MSM_QUANTISATION_FACTOR >= QUANTISATION_DERIVED && SM_MSM_QUANTISATION_FACTOR <= 1.001 * QUANTISATION_DERIVED,
          "SM_MSM_QUANTISATION_FACTOR %g is not in [%g, 1.001 x that], its derivation", SM_MSM_QUANTISATION_FACTOR,
          QUANTISATION_DERIVED);
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
        hausdorff_against_certificate(program, MSM_ALPHA);
        hausdorff_against_certificate(program, 3e-3);
        hausdorff_target_control(program);
        CHECK(control > 100.0, "without msm_quantisation_bias the cases must fail (worst %g)", control);
        glDeleteProgram(program);
    }
    gl_context_destroy();
    remove_tree(dir);
    return check_finish();
}
