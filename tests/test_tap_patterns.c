/* Protects the PCF family's tap layouts and per-pixel noise
 * (shaders/shadow_taps.glsl: the `pattern` and `rotation` parameters), run
 * in GLSL on llvmpipe through a probe shader:
 *   - rotation: none is 0 everywhere; ign_2x2 gives one value to each 2 x 2
 *     block and differs between blocks; ign differs between neighbours;
 *     hash is in [0, 1) with a mean near 1/2;
 *   - pattern: every point of poisson, grid, vogel and uniform_disk at every tap count
 *     lies in its shape (the square [-1, 1]^2 or the unit disk), no two
 *     coincide, and their second moments are those of the uniform
 *     distribution over the shape (disk 1/2, square 2/3 for x² + y²)
 *     within the tolerance stated at each check;
 *   - the concentric map's inverse undoes it. */
#include "check.h"
#include "glsl_probe.h"

#include <math.h>

static char dir[] = "/tmp/sb_test_tap_patterns_XXXXXX";

#define NOISE_W 64
#define NOISE_H 64
#define TAPS_W 128  /* SAMPLE_PATTERN_MAX: the largest tap count */

static const char probe_source[] =
    "#version 450 core\n"
    "#include \"shadow_taps.glsl\"\n"
    "uniform int u_what;     // 0: noise of mode u_mode; 1: point i of pattern u_mode\n"
    "uniform int u_mode, u_n;\n"
    "uniform bool u_square;\n"
    "layout(location = 0) out vec4 result;\n"
    "void main()\n"
    "{\n"
    "    if (u_what == 0) {\n"
    "        result = vec4(sm_rotation_noise(gl_FragCoord.xy, u_mode), 0.0, 0.0);\n"
    "        return;\n"
    "    }\n"
    "    int i = int(gl_FragCoord.x);\n"
    "    vec2 p = sm_pattern_point(u_mode, u_square, i, u_n);\n"
    "    vec2 other = u_square ? sm_square_to_disk(p) : sm_disk_to_square(p);\n"
    "    vec2 back = u_square ? sm_disk_to_square(other) : sm_square_to_disk(other);\n"
    "    result = vec4(p, length(back - p), 0.0);\n"
    "}\n";

static void noise_checks(GLuint program)
{
    static float r[4][NOISE_W * NOISE_H * 4];
    const int modes[4] = {TAP_ROTATION_NONE, TAP_ROTATION_HASH, TAP_ROTATION_IGN, TAP_ROTATION_IGN_2X2};
    for (int m = 0; m < 4; m++) {
        glUseProgram(program);
        glUniform1i(glGetUniformLocation(program, "u_what"), 0);
        glUniform1i(glGetUniformLocation(program, "u_mode"), modes[m]);
        glsl_probe_draw(program, NOISE_W, NOISE_H, r[m]);
    }
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
