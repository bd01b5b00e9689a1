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

#define NOISE_W 64
#define NOISE_H 64
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

/* The mean power of tile t's spectrum (its DFT squared over the texels,
 * against white noise's, the variance of a uniform value: 1/12) over the
 * frequencies of radius [lo, hi) cycles per tile. */
static double band_power(const uint16_t *tile, double lo, double hi)
{
    enum { S = TAP_BLUE_NOISE_SIDE };
    double sum = 0;
    int n = 0;
    for (int v = -S / 2; v < S / 2; v++)
        for (int u = -S / 2; u < S / 2; u++) {
            const double r = hypot(u, v);
            if (r < lo || r >= hi)
                continue;
            double re = 0, im = 0;
            for (int y = 0; y < S; y++)
                for (int x = 0; x < S; x++) {
                    const double a = -2 * M_PI * (u * x + v * y) / S, value = tile[y * S + x] / 65536.0 - 0.5;
                    re += value * cos(a), im += value * sin(a);
                }
            sum += (re * re + im * im) / (S * S) / (1.0 / 12.0);
            n++;
        }
    return sum / n;
}

/* The committed texture is a blue-noise dither array (tools/blue_noise.c). */
static uint16_t *blue_noise_file(void)
{
    enum { S = TAP_BLUE_NOISE_SIDE, TILE = S * S };
    char *path = util_printf("%s/shaders/blue_noise.png", SB_SOURCE_DIR);
    uint16_t *px = NULL;
    CHECK(image_read_png16(path, S, 2 * S, &px) == 0, "%s reads", path);
    free(path);
    if (!px)
        return NULL;
    double dot = 0, norm[2] = {0, 0};
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
         * 1.14 below 4 cycles a tile, 1.03 in [4, 8), 0.97 in [16, 32)); these
         * tiles measured 5e-5, 4e-4 and 1.12, 1.17: the power moved from low
         * to high frequencies. 0.01 is far below what white noise reaches
         * over the few dozen frequencies of a low band (its mean there
         * stays above 0.5); over the 2,400 of [16, 32) white noise's mean is
         * 1 within 0.03, so 1.05 asks for the excess. */
        const double low = band_power(px + t * TILE, 0.5, 4), mid = band_power(px + t * TILE, 4, 8),
                     high = band_power(px + t * TILE, 16, 32);
        printf("blue noise tile %d: power %.5f below 4 cycles, %.5f in [4, 8), %.3f in [16, 32)\n", t, low, mid, high);
        CHECK(low < 0.01 && mid < 0.01 && high > 1.05, "blue noise tile %d is not blue: power %.5f, %.5f, %.3f", t,
              low, mid, high);
        for (int i = 0; i < TILE; i++) {
            const double a = px[t * TILE + i] / 65536.0 - 0.5;
            norm[t] += a * a;
            if (t == 1)
                dot += a * (px[i] / 65536.0 - 0.5);
        }
    }
    /* independent tiles: the correlation's standard deviation is 1/64;
     * 0.06 is almost four of them */
    const double corr = dot / sqrt(norm[0] * norm[1]);
    CHECK(fabs(corr) < 0.06, "blue noise: the tiles correlate (%.4f)", corr);
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
