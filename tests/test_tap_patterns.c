/* Protects the PCF family's tap layouts and per-pixel noise
 * (shaders/shadow_taps.glsl: the `pattern` and `rotation` parameters), run
 * in GLSL on llvmpipe through a probe shader:
 *   - rotation: none is 0 everywhere; ign_2x2 gives one value to each 2 x 2
 *     block and differs between blocks; ign differs between neighbours;
 *     hash is in [0, 1) with a mean near 1/2; blue_noise is
 *     shaders/blue_noise.png's texel of the pixel modulo its tile, every
 *     frame a fresh permutation, and the file itself is blue (each tile a
 *     permutation of its ranks, little power at low frequencies, the two
 *     tiles uncorrelated);
 *   - pattern: every point of poisson, grid, vogel and uniform_disk at every tap count
 *     lies in its shape (the square [-1, 1]^2 or the unit disk), no two
 *     coincide, and their second moments are those of the uniform
 *     distribution over the shape (disk 1/2, square 2/3 for x² + y²)
 *     within the tolerance stated at each check;
 *   - the concentric map's inverse undoes it. */
#include "check.h"
#include "glsl_probe.h"
#include "base/image.h"

#include <math.h>
#include <stdbool.h>
#include <string.h>

static char dir[] = "/tmp/sb_test_tap_patterns_XXXXXX";

#define NOISE_W 96  /* past the blue-noise tile (64), so its wrap is read */
#define NOISE_H 80
#define TAPS_W 128  /* SAMPLE_PATTERN_MAX: the largest tap count */

static const char probe_source[] =
    "#version 450 core\n"
    "#include \"shadow_taps.glsl\"\n"
    "uniform int u_what;     // 0: noise of mode u_mode; 1: point i of pattern u_mode\n"
    "uniform int u_mode, u_n;\n"
    "uniform bool u_square, u_animate;\n"
    "layout(location = 0) out vec4 result;\n"
    "void main()\n"
    "{\n"
    "    if (u_what == 0) {\n"
    "        result = vec4(sm_rotation_noise(gl_FragCoord.xy, u_mode, u_animate), 0.0, 0.0);\n"
    "        return;\n"
    "    }\n"
    "    int i = int(gl_FragCoord.x);\n"
    "    vec2 p = sm_pattern_point(u_mode, u_square, i, u_n);\n"
    "    vec2 other = u_square ? sm_square_to_disk(p) : sm_disk_to_square(p);\n"
    "    vec2 back = u_square ? sm_disk_to_square(other) : sm_square_to_disk(other);\n"
    "    result = vec4(p, length(back - p), 0.0);\n"
    "}\n";

/* The mean power of a tile's spectrum (its DFT squared over the texels,
 * against white noise's, the variance of a uniform value: 1/12) over the
 * frequencies of radius [lo, hi) cycles per tile; the largest single one
 * into *peak. values: the tile's values minus 1/2. */
static double band_power(const double *values, double lo, double hi, double *peak)
{
    enum { S = TAP_BLUE_NOISE_SIDE };
    double sum = 0;
    int n = 0;
    *peak = 0;
    for (int v = -S / 2; v < S / 2; v++)
        for (int u = -S / 2; u < S / 2; u++) {
            const double r = hypot(u, v);
            if (r < lo || r >= hi)
                continue;
            double re = 0, im = 0;
            for (int y = 0; y < S; y++)
                for (int x = 0; x < S; x++) {
                    const double a = -2 * M_PI * (u * x + v * y) / S;
                    re += values[y * S + x] * cos(a), im += values[y * S + x] * sin(a);
                }
            const double power = (re * re + im * im) / (S * S) / (1.0 / 12.0);
            sum += power, *peak = fmax(*peak, power);
            n++;
        }
    return sum / n;
}

/* The committed texture is a blue-noise dither array (tools/blue_noise.c),
 * and so is each animated frame of it (shadow_taps.glsl's R2 steps). */
static uint16_t *blue_noise_file(void)
{
    enum { S = TAP_BLUE_NOISE_SIDE, TILE = S * S };
    char *path = util_printf("%s/shaders/blue_noise.png", SB_SOURCE_DIR);
    uint16_t *px = NULL;
    CHECK(image_read_png16(path, S, 2 * S, &px) == 0, "%s reads", path);
    free(path);
    if (!px)
        return NULL;
    static double centred[2][TILE];
    const double step[2] = {0.7548776662, 0.5698402910};  /* shadow_taps.glsl's, per frame */
    for (int t = 0; t < 2; t++) {
        static bool seen[TILE];
        memset(seen, 0, sizeof seen);
        int bad = 0;
        for (int i = 0; i < TILE; i++) {
            const int v = px[t * TILE + i], rank = (v - 8) / 16;
            bad += (v - 8) % 16 != 0 || rank < 0 || rank >= TILE || seen[rank];
            if (rank >= 0 && rank < TILE)
                seen[rank] = true;
        }
        CHECK(bad == 0, "blue noise tile %d: %d texels not a rank of a permutation", t, bad);
        /* White noise has power 1 in every band (a rand() tile measured
         * 1.14 below 4 cycles a tile, 1.03 in [4, 8), 0.97 in [16, 32), its
         * largest single frequency in [8, 32) 6.8: the maximum of some 700
         * independent exponential draws); these tiles measured 5e-5, 4e-4
         * and 1.12, 1.17, peaks 9.6 and 10.2: the power moved from low to
         * high frequencies, spread over them. A low band's mean over its few
         * dozen frequencies stays far above 0.01 for white noise; over the
         * 1,200 independent frequencies of [16, 32) its mean has a standard
         * deviation of 0.03, so 1.05 asks for the excess; a periodic
         * pattern puts hundreds at one frequency, so peaks stay under 20.
         * Animated (frame k: v + k step, modulo 1) the wrap costs some of
         * it: measured 0.03 to 0.07 below 8 cycles for frames 1-3, still a
         * fifteenth of white noise's at most; 0.1 bounds it. */
        for (int k = 0; k < 4; k++) {
            for (int i = 0; i < TILE; i++) {
                const double v = px[t * TILE + i] / 65536.0 + k * step[t];
                centred[t][i] = v - floor(v) - 0.5;
            }
            double peak_low, peak_mid, peak;
            const double low = band_power(centred[t], 0.5, 4, &peak_low), mid = band_power(centred[t], 4, 8, &peak_mid),
                         high = band_power(centred[t], 16, 32, &peak);
            band_power(centred[t], 8, 32, &peak);
            printf("blue noise tile %d frame %d: power %.5f below 4 cycles, %.5f in [4, 8), %.3f in [16, 32), "
                   "peak %.2f in [8, 32)\n", t, k, low, mid, high, peak);
            if (k == 0)
                CHECK(low < 0.01 && mid < 0.01 && high > 1.05 && peak < 20,
                      "blue noise tile %d is not blue: power %.5f, %.5f, %.3f, peak %.2f", t, low, mid, high, peak);
            else
                CHECK(low < 0.1 && mid < 0.1, "blue noise tile %d frame %d is not blue: power %.5f, %.5f", t, k, low,
                      mid);
        }
        for (int i = 0; i < TILE; i++)  /* frame 0 again, for the correlation */
            centred[t][i] = px[t * TILE + i] / 65536.0 - 0.5;
    }
    /* Independent tiles: at any toroidal shift of one against the other
     * the correlation's standard deviation is 1/64; the largest over the
     * 4096 shifts measured 0.079; a copy (shifted) gives 1, so 0.12. */
    double norm[2] = {0, 0}, worst = 0;
    for (int t = 0; t < 2; t++)
        for (int i = 0; i < TILE; i++)
            norm[t] += centred[t][i] * centred[t][i];
    for (int dy = 0; dy < S; dy++)
        for (int dx = 0; dx < S; dx++) {
            double dot = 0;
            for (int y = 0; y < S; y++)
                for (int x = 0; x < S; x++)
                    dot += centred[0][y * S + x] * centred[1][(y + dy) % S * S + (x + dx) % S];
            worst = fmax(worst, fabs(dot) / sqrt(norm[0] * norm[1]));
        }
    CHECK(worst < 0.12, "blue noise: the tiles correlate (%.4f at some shift)", worst);
    return px;
}

static void noise_checks(GLuint program)
{
    enum { MODES = 5 };
    static float r[MODES][NOISE_W * NOISE_H * 4], blue_next[NOISE_W * NOISE_H * 4];
    const int modes[MODES] = {TAP_ROTATION_NONE, TAP_ROTATION_HASH, TAP_ROTATION_IGN, TAP_ROTATION_IGN_2X2,
                              TAP_ROTATION_BLUE_NOISE};
    const GLuint blue = shadowmap_blue_noise_create();
    CHECK(blue, "the blue-noise texture loads");
    glBindTextureUnit((GLuint)shadowmap_blue_noise_binding(), blue);
    for (int m = 0; m < MODES; m++) {
        glUseProgram(program);
        glUniform1i(glGetUniformLocation(program, "u_what"), 0);
        glUniform1i(glGetUniformLocation(program, "u_mode"), modes[m]);
        glUniform1f(glGetUniformLocation(program, "sm_noise_frame"), 0.0f);
        glsl_probe_draw(program, NOISE_W, NOISE_H, r[m]);
    }
    /* frame 1: without animate_noise the same, with it all new */
    static float blue_still[NOISE_W * NOISE_H * 4];
    glUniform1f(glGetUniformLocation(program, "sm_noise_frame"), 1.0f);
    glsl_probe_draw(program, NOISE_W, NOISE_H, blue_still);
    glUniform1i(glGetUniformLocation(program, "u_animate"), 1);
    glsl_probe_draw(program, NOISE_W, NOISE_H, blue_next);
    glUniform1i(glGetUniformLocation(program, "u_animate"), 0);
    glUniform1f(glGetUniformLocation(program, "sm_noise_frame"), 0.0f);
    glDeleteTextures(1, &blue);
    uint16_t *file = blue_noise_file();
    int blue_off = 0, blue_same = 0, blue_moved = 0;
    for (int y = 0; file && y < NOISE_H; y++)
        for (int x = 0; x < NOISE_W; x++) {
            const int side = TAP_BLUE_NOISE_SIDE, i = 4 * (y * NOISE_W + x), t = (y % side) * side + x % side;
            for (int c = 0; c < 2; c++) {
                const float want = file[c * side * side + t] / 65536.0f;
                blue_off += r[4][i + c] != want;
                blue_same += blue_next[i + c] == r[4][i + c];
                blue_moved += blue_still[i + c] != r[4][i + c];
            }
        }
    free(file);
    CHECK(blue_off == 0, "blue_noise: %d values differ from the file's texels", blue_off);
    CHECK(blue_same == 0, "blue_noise: %d values the same in the next animated frame", blue_same);
    CHECK(blue_moved == 0, "blue_noise: %d values moved in the next frame without animate_noise", blue_moved);
    int none_off = 0, block_off = 0, blocks_alike = 0, blocks = 0, ign_alike = 0, hash_out = 0;
    double hash_sum = 0;
    for (int y = 0; y < NOISE_H; y++)
        for (int x = 0; x < NOISE_W; x++) {
            const int i = 4 * (y * NOISE_W + x), corner = 4 * ((y & ~1) * NOISE_W + (x & ~1));
            none_off += r[0][i] != 0.0f || r[0][i + 1] != 0.0f;
            for (int c = 0; c < 2; c++) {
                hash_out += !(r[1][i + c] >= 0.0f && r[1][i + c] < 1.0f);
                hash_sum += r[1][i + c];
            }
            block_off += r[3][i] != r[3][corner] || r[3][i + 1] != r[3][corner + 1];
            if (x + 1 < NOISE_W)
                ign_alike += r[2][i] == r[2][i + 4];
            if ((x & 1) == 0 && (y & 1) == 0 && x + 2 < NOISE_W) {
                blocks++;
                blocks_alike += r[3][i] == r[3][i + 8];
            }
        }
    CHECK(none_off == 0, "rotation none: %d pixels not 0", none_off);
    CHECK(block_off == 0, "ign_2x2: %d pixels differ from their 2x2 block's", block_off);
    /* IGN steps by 0.0671 a pixel along x (its constant), so equal
     * neighbours are rounding coincidences: none were seen */
    CHECK(blocks_alike == 0, "ign_2x2: %d of %d blocks equal to the next", blocks_alike, blocks);
    CHECK(ign_alike == 0, "ign: %d pixels equal to their right neighbour", ign_alike);
    const double mean = hash_sum / (2.0 * NOISE_W * NOISE_H);
    /* 8192 uniform values: the mean's standard deviation is 0.0032; 0.02 is
     * over six of them */
    CHECK(hash_out == 0 && fabs(mean - 0.5) < 0.02, "hash: %d values outside [0, 1), mean %.4f", hash_out, mean);
}

static void pattern_checks(GLuint program)
{
    static float r[TAPS_W * 4];
    const int patterns[4] = {TAP_PATTERN_POISSON, TAP_PATTERN_GRID, TAP_PATTERN_VOGEL, TAP_PATTERN_UNIFORM_DISK};
    for (int k = 0; k < 4; k++)
        for (int square = 0; square < 2; square++)
            for (int c = 0; c < TAP_COUNT_KINDS; c++) {
                const int n = tap_counts[c], side = (int)lround(sqrt((double)n));
                if (patterns[k] == TAP_PATTERN_GRID && side * side != n)
                    continue;  /* grid takes square counts only (params_grid_taps) */
                glUseProgram(program);
                glUniform1i(glGetUniformLocation(program, "u_what"), 1);
                glUniform1i(glGetUniformLocation(program, "u_mode"), patterns[k]);
                glUniform1i(glGetUniformLocation(program, "u_n"), n);
                glUniform1i(glGetUniformLocation(program, "u_square"), square);
                glsl_probe_draw(program, TAPS_W, 1, r);
                int outside = 0, coincide = 0;
                double r2 = 0, round_trip = 0;
                for (int i = 0; i < n; i++) {
                    const float x = r[4 * i], y = r[4 * i + 1];
                    outside += square ? fabsf(x) > 1.0f || fabsf(y) > 1.0f : x * x + y * y > 1.0f + 1e-5f;
                    r2 += (x * x + y * y) / n;
                    round_trip = fmax(round_trip, r[4 * i + 2]);
                    for (int j = 0; j < i; j++)
                        coincide += hypotf(x - r[4 * j], y - r[4 * j + 1]) < 1e-4f;
                }
                const char *name = tap_pattern_names[patterns[k]], *shape = square ? "square" : "disk";
                /* The uniform second moment: 2/3 on the square, 1/2 on the
                 * disk. Within 1.25/n of it (seen: 1.07/n for poisson's 32
                 * on the square, 1/n for the 4 x 4 grid on the disk, its
                 * cell centres' own deficit): a set squeezed to 0.9 of its
                 * shape (0.81 times the moment, 0.095 off on the disk)
                 * fails at every count. */
                const double want = square ? 2.0 / 3.0 : 0.5;
                /* uniform_disk's points are independent: its moment is a
                 * mean of n draws, within 4 of its standard deviations,
                 * sqrt(1/12 / n) on the disk (r² is uniform) and
                 * sqrt(8/45 / n) on the square */
                const double bound = patterns[k] == TAP_PATTERN_UNIFORM_DISK
                                         ? 4.0 * sqrt((square ? 8.0 / 45.0 : 1.0 / 12.0) / n)
                                         : 1.25 / n;
                CHECK(outside == 0 && coincide == 0, "%s %s %d: %d outside, %d coinciding", name, shape, n, outside,
                      coincide);
                CHECK(fabs(r2 - want) <= bound, "%s %s %d: mean x² + y² %.4f, uniform's %.4f", name, shape, n, r2,
                      want);
                /* float trigonometry: a few ulps of 1 */
                CHECK(round_trip < 1e-5, "%s %s %d: the concentric map and its inverse differ by %g", name, shape,
                      n, round_trip);
            }
}

int main(void)
{
    if (!mkdtemp(dir))
        return 1;
    if (gl_context_create(GL_BACKEND_OSMESA) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    GLuint program = glsl_probe_program(dir, probe_source, "");
    CHECK(program, "the probe builds");
    if (program) {
        noise_checks(program);
        pattern_checks(program);
        glDeleteProgram(program);
    }
    gl_context_destroy();
    char *rm = util_printf("rm -rf '%s'", dir);
    CHECK(system(rm) == 0, "%s", rm);
    free(rm);
    return check_finish();
}
