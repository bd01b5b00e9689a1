/* Writes shaders/blue_noise.png: the tileable blue-noise texture behind the
 * `rotation=blue_noise` tap noise (shadow_taps.glsl's sm_blue_noise).
 *
 * Two independent 64 x 64 tiles, stacked (channel 0 in rows 0-63, channel 1
 * in rows 64-127), each a dither array made by Ulichney's void-and-cluster
 * method (1993, "The void-and-cluster method for dither array
 * generation"). Every pixel gets a rank 0..4095 such that, for every k, the
 * pixels of rank below k are spread evenly over the torus: no low
 * frequencies, so a per-pixel rotation from it turns banding into noise a
 * small blur (the denoiser, TAA) removes better than white noise.
 *
 *   energy   of a pixel: the sum over the set pixels of a Gaussian of their
 *            toroidal distance (sigma 1.5 pixels, Ulichney's value);
 *   cluster  the set pixel of highest energy; void: the unset of lowest;
 *   phase 0  a random 10 % of pixels, then move the tightest cluster into
 *            the largest void until the two are the same pixel;
 *   phase 1  remove the tightest cluster of that prototype, one at a time,
 *            ranks counting down from its size;
 *   phase 2  from the prototype, fill the largest void, one at a time, ranks
 *            counting up to 4095. (Ulichney's phase 3 swaps the roles of set
 *            and unset at half: with a Gaussian that sums to a constant, the
 *            tightest cluster of unset pixels is the largest void of set
 *            ones, so the fill simply goes on.)
 * Ties go to the lowest index. A pixel's value is (rank + 0.5) / 4096,
 * stored as 16 rank + 8 in a 16-bit grey PNG (so it shows as the texture).
 *
 *   build/blue_noise shaders/blue_noise.png          writes it
 *   build/blue_noise --check shaders/blue_noise.png  exit 0 if the file holds
 *                                                    what the generator makes
 * Deterministic (fixed seeds; sums of exp() in doubles, so reproduced pixel
 * for pixel by the same libm and floating-point contraction, as Debian's
 * build here): test_blue_noise runs --check; test_tap_patterns checks the
 * file's spectrum (no power at low frequencies). */
#include "base/image.h"
#include "techniques/technique.h"

#include <errno.h>
#include <math.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIDE TAP_BLUE_NOISE_SIDE
#define PIXELS (SIDE * SIDE)
#define TILES 2
#define SIGMA 1.5
#define INITIAL_FRACTION 0.1

static uint64_t rng_state;

static uint64_t next_random(void)  /* xorshift64* */
{
    rng_state ^= rng_state >> 12;
    rng_state ^= rng_state << 25;
    rng_state ^= rng_state >> 27;
    return rng_state * 0x2545f4914f6cdd1dull;
}

static double kernel[SIDE][SIDE];  /* the Gaussian of the toroidal offset (dx, dy) */

static void make_kernel(void)
{
    for (int dy = 0; dy < SIDE; dy++)
        for (int dx = 0; dx < SIDE; dx++) {
            int x = dx <= SIDE / 2 ? dx : SIDE - dx, y = dy <= SIDE / 2 ? dy : SIDE - dy;
            kernel[dy][dx] = exp(-(x * x + y * y) / (2.0 * SIGMA * SIGMA));
        }
}

/* energy += sign * the kernel centred on pixel p */
static void splat(double *energy, int p, double sign)
{
    int px = p % SIDE, py = p / SIDE;
    for (int y = 0; y < SIDE; y++)
        for (int x = 0; x < SIDE; x++)
            energy[y * SIDE + x] += sign * kernel[(y - py + SIDE) % SIDE][(x - px + SIDE) % SIDE];
}

/* The set pixel of highest energy (want_set) or the unset one of lowest. */
static int extreme(const double *energy, const bool *set, bool want_set)
{
    int best = -1;
    for (int p = 0; p < PIXELS; p++) {
        if (set[p] != want_set)
            continue;
        if (best < 0 || (want_set ? energy[p] > energy[best] : energy[p] < energy[best]))
            best = p;
    }
    return best;
}

static void void_and_cluster(uint64_t seed, int rank[PIXELS])
{
    static bool prototype[PIXELS], set[PIXELS];
    static double prototype_energy[PIXELS], energy[PIXELS];
    rng_state = seed;
    memset(prototype, 0, sizeof prototype);
    memset(prototype_energy, 0, sizeof prototype_energy);
    int ones = 0;
    while (ones < (int)(INITIAL_FRACTION * PIXELS)) {
        int p = (int)(next_random() % PIXELS);
        if (!prototype[p]) {
            prototype[p] = true, ones++;
            splat(prototype_energy, p, 1.0);
        }
    }
    for (int round = 0;; round++) {  /* phase 0: 162 and 151 moves for these seeds */
        if (round == PIXELS) {
            fprintf(stderr, "blue_noise: phase 0 did not converge in %d moves\n", PIXELS);
            exit(1);
        }
        int cluster = extreme(prototype_energy, prototype, true);
        prototype[cluster] = false;
        splat(prototype_energy, cluster, -1.0);
        int hole = extreme(prototype_energy, prototype, false);
        prototype[hole] = true;
        splat(prototype_energy, hole, 1.0);
        if (hole == cluster)
            break;
    }
    memcpy(set, prototype, sizeof set);  /* phase 1 */
    memcpy(energy, prototype_energy, sizeof energy);
    for (int r = ones - 1; r >= 0; r--) {
        int cluster = extreme(energy, set, true);
        set[cluster] = false;
        splat(energy, cluster, -1.0);
        rank[cluster] = r;
    }
    memcpy(set, prototype, sizeof set);  /* phase 2 */
    memcpy(energy, prototype_energy, sizeof energy);
    for (int r = ones; r < PIXELS; r++) {
        int hole = extreme(energy, set, false);
        set[hole] = true;
        splat(energy, hole, 1.0);
        rank[hole] = r;
    }
}

int main(int argc, char **argv)
{
    bool check = argc == 3 && strcmp(argv[1], "--check") == 0;
    if (argc != 2 + check || argv[argc - 1][0] == '-') {
        fprintf(stderr, "usage: blue_noise [--check] FILE.png\n");
        return 2;
    }
    const char *path = argv[argc - 1];
    static const uint64_t seeds[TILES] = {0x9e3779b97f4a7c15ull, 0xd1b54a32d192ed03ull};
    static uint16_t pixels[TILES * PIXELS];
    static int rank[PIXELS];
    make_kernel();
    for (int t = 0; t < TILES; t++) {
        void_and_cluster(seeds[t], rank);
        for (int p = 0; p < PIXELS; p++)
            pixels[t * PIXELS + p] = (uint16_t)(16 * rank[p] + 8);
    }
    if (!check)
        return image_write_png16(path, SIDE, TILES * SIDE, pixels) == 0 ? 0 : 1;
    uint16_t *stored;
    int err = image_read_png16(path, SIDE, TILES * SIDE, &stored);
    if (err) {
        if (err == -ENOENT)
            fprintf(stderr, "blue_noise: %s: no such file\n", path);
        return 1;
    }
    int differ = 0;
    for (int p = 0; p < TILES * PIXELS; p++)
        differ += stored[p] != pixels[p];
    free(stored);
    if (differ)
        fprintf(stderr, "blue_noise: %s differs from the generator's texture at %d of %d pixels: "
                        "regenerate it with build/blue_noise %s\n", path, differ, TILES * PIXELS, path);
    return differ ? 1 : 0;
}
