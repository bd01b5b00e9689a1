/* pcss — percentage-closer soft shadows (Fernando 2005, "Percentage-closer
 * soft shadows", SIGGRAPH sketch), for a perspective light (an area light;
 * the sun's orthographic map takes its widths in world space, 2 tan(alpha)
 * (z_r - z_b): shaders/pcss_geometry.glsl).
 *
 * Computes V in three steps: (1) blocker search: comparisons over the region
 * of the map through which the receiver sees the light (the light's shape,
 * projected to the near plane: light_size_uv * (z_r - n) / z_r), averaging
 * the planar depth of the texels that occlude; (2) penumbra by similar
 * triangles: a blocker at z_b covers light_size_uv * n (z_r - z_b) / (z_b z_r)
 * of the map around the receiver; (3) PCF over that region. Taps follow the
 * light's shape: the square pattern shifted per pixel for a rect light, the
 * disk pattern rotated per pixel for a disk light. Early-outs: no blocker
 * found -> lit; every search tap blocked -> umbra.
 *
 * Parameters:
 *   blocker_samples, filter_samples  taps of steps 1 and 3.
 *   light_size_scale     multiplies the scene's light size (1 = the light
 *                        the ground truth uses), in both steps unless:
 *   search_light_size_scale, filter_light_size_scale
 *                        the blocker search's and the filter's own scales
 *                        (seed 003's two radii); 0 = light_size_scale.
 *   pattern              the taps' layout over the light's shape: poisson
 *                        (progressive best-candidate), grid (n x n: a square
 *                        tap count; seed 003's first version), vogel
 *                        (golden-angle spiral), uniform_disk (independent
 *                        uniform points, seed 002's).
 *   rotation             the per-pixel noise that turns (disk) or shifts
 *                        (square) both steps' taps: none, hash, ign,
 *                        ign_2x2, blue_noise (shaders/shadow_taps.glsl).
 *   animate_noise        the frame index moves that noise (for TAA to
 *                        average); `stability` measures it.
 *   early_bail           8 of the search's taps first (NVIDIA's PCSS
 *                        integration); where they agree (all lit, all
 *                        blocked), that is the answer.
 *   penumbra_mask, mask_dilate_blocks, mask_dilate_world
 *                        seed 003's quarter-resolution pre-pass
 *                        (shadow_classify: 16 search taps widened by the
 *                        block); the full filter runs on penumbra blocks only.
 *   denoise_radius_px, denoise_sigma_world, denoise_normal_power
 *                        seed 003's bilateral blur after the receiver pass.
 *   receiver_plane_bias  compare against the receiver's plane at each tap
 *                        (both steps); the search region is wide, so without
 *                        it sloped receivers find themselves as blockers.
 *   constant_bias        depth offset, linear units (1 = near..far).
 *   slope_bias           without receiver_plane_bias only, texels of slope.
 *
 * How it fails: it assumes one planar blocker parallel to the light, so where
 * blockers at several depths overlap the average depth is wrong and the
 * penumbra too wide or narrow; few taps give noise (and a wrong early-out
 * when a small blocker falls between search taps); the search region grows
 * with the light and the receiver's distance, so a fixed tap count
 * undersamples large lights; cost grows with both tap counts. */
#include "param_rows.h"
#include "params.h"

struct pcss_settings {
    int blocker_samples;      /* TAP_COUNTS */
    int filter_samples;       /* TAP_COUNTS */
    float light_size_scale;   /* [0.01, 10] */
    float search_light_size_scale;  /* [0, 10], 0: light_size_scale */
    float filter_light_size_scale;  /* [0, 10], 0: light_size_scale */
    int pattern;              /* TAP_PATTERN_* */
    int rotation;             /* TAP_ROTATION_* */
    int animate_noise;        /* bool */
    int early_bail;           /* bool */
    int penumbra_mask;        /* bool */
    int mask_dilate_blocks;   /* [0, 4] */
    float mask_dilate_world;  /* world units, 0: off */
    int denoise_radius_px;    /* [0, 8], 0: off */
    float denoise_sigma_world;
    float denoise_normal_power;
    int receiver_plane_bias;  /* bool */
    float constant_bias;      /* linear depth units, [0, 0.1] */
    float slope_bias;         /* texels of depth slope, [0, 16] */
};

static const struct technique_param pcss_params[] = {
    {"blocker_samples", "taps of the blocker search",
     offsetof(struct pcss_settings, blocker_samples), PARAM_TAPS, 32, 0, 0, NULL, TUNE_CHOICES},
    {"filter_samples", "taps of the PCF over the estimated penumbra",
     offsetof(struct pcss_settings, filter_samples), PARAM_TAPS, 32, 0, 0, NULL, TUNE_CHOICES},
    PARAM_ROW_LIGHT_SIZE_SCALE(struct pcss_settings),
    {"search_light_size_scale", "the blocker search's own light size scale (0 = light_size_scale)",
     offsetof(struct pcss_settings, search_light_size_scale), PARAM_FLOAT, 0.0, 0.0, 10.0, NULL, NULL},
    {"filter_light_size_scale", "the filter's own light size scale (0 = light_size_scale)",
     offsetof(struct pcss_settings, filter_light_size_scale), PARAM_FLOAT, 0.0, 0.0, 10.0, NULL, NULL},
    PARAM_ROW_TAP_PATTERN(struct pcss_settings, NULL),
    PARAM_ROW_TAP_ROTATION(struct pcss_settings),
    PARAM_ROW_ANIMATE_NOISE(struct pcss_settings),
    {"early_bail", "8 probe taps of the search first; where they agree, that is the answer",
     offsetof(struct pcss_settings, early_bail), PARAM_BOOL, 0, 0, 1, NULL, NULL},
    PARAM_ROWS_PENUMBRA_MASK(struct pcss_settings),
    PARAM_ROWS_DENOISE(struct pcss_settings),
    PARAM_ROW_RECEIVER_PLANE_BIAS(struct pcss_settings),
    PARAM_ROW_CONSTANT_BIAS(struct pcss_settings),
    PARAM_ROW_SLOPE_BIAS(struct pcss_settings, " (unused with receiver_plane_bias)"),
    {NULL},
};

static int pcss_check(const void *settings, char *why, size_t why_size)
{
    const struct pcss_settings *s = settings;
    if (s->pattern != TAP_PATTERN_GRID)
        return 0;
    if (params_grid_taps("blocker_samples", s->blocker_samples, why, why_size) != 0)
        return -1;
    return params_grid_taps("filter_samples", s->filter_samples, why, why_size);
}

static const struct technique_cell pcss_cells[] = {
    {"contact_hardening", {"blocker_samples=16,filter_samples=64", "search_light_size_scale=1.5",
                           "filter_light_size_scale=0.75"}},
    {"parallel_planes", {"light_size_scale=0.5", "pattern=grid,blocker_samples=25,filter_samples=25",
                         "pattern=vogel,rotation=ign_2x2", "rotation=none", "rotation=hash", "rotation=blue_noise",
                         "early_bail=true",
                         "denoise_radius_px=2,denoise_sigma_world=0.5"}},
    {"thin_features", {"penumbra_mask=true", "penumbra_mask=true,mask_dilate_blocks=0"}},
    {"large_light", {"penumbra_mask=true,mask_dilate_world=0.1"}},
    {"stanford_bunny", {"denoise_radius_px=1,denoise_normal_power=16"}},
    {"parallel_planes_disk", {"pattern=vogel", "pattern=uniform_disk", "animate_noise=true"}},
    {"grazing_receiver", {"receiver_plane_bias=false", "receiver_plane_bias=false,slope_bias=4", "constant_bias=0.005"}},
    {NULL},
};

/* Seed 003's PCSS (docs/techniques.md, "Seed 003's pipeline"), step by step:
 * each a named cell of the default run, so "what each shortcut buys" is
 * measured on every scene; poisson16_ign is the textbook pcss at their
 * tap count. */
static const struct technique_preset pcss_presets[] = {
    {"grid7x7", "pattern=grid,blocker_samples=49,filter_samples=49,rotation=none",
     "seed 003's first version: a 7 x 7 grid in both steps, 49 + 49 taps"},
    {"poisson16", "blocker_samples=16,filter_samples=16,rotation=none",
     "16 + 16 Poisson taps, the same at every pixel (banding)"},
    {"poisson16_hash", "blocker_samples=16,filter_samples=16,rotation=hash",
     "16 + 16 Poisson taps, rotated per pixel by white noise"},
    {"poisson16_ign", "blocker_samples=16,filter_samples=16",
     "the textbook pcss at 16 + 16 taps (interleaved gradient noise per pixel)"},
    {"poisson16_2x2", "blocker_samples=16,filter_samples=16,rotation=ign_2x2",
     "16 + 16 Poisson taps, one rotation per 2 x 2 block"},
    {"poisson16_2x2_denoise", "blocker_samples=16,filter_samples=16,rotation=ign_2x2,denoise_radius_px=1",
     "and the bilateral 3 x 3 blur"},
    {"seed003", "blocker_samples=16,filter_samples=16,rotation=ign_2x2,denoise_radius_px=1,penumbra_mask=true",
     "seed 003 as it ships: and the penumbra mask"},
    {NULL},
};

TECHNIQUE(pcss, .needs = SM_DEPTH, .check = pcss_check, .regression = pcss_cells, .presets = pcss_presets,
          .summary = "blocker search, penumbra by similar triangles, PCF of that width");
