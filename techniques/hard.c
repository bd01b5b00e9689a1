/* hard — one depth comparison per pixel: the classic shadow map
 * (Williams 1978, "Casting curved shadows on curved surfaces").
 *
 * Computes V = 1 if the receiver's linear light depth, minus a bias, is not
 * behind the depth stored in the nearest shadow-map texel, else 0. It knows
 * nothing of the light's size, so its shadow has no penumbra at all.
 *
 * Parameters:
 *   constant_bias  depth offset in linear shadow-map depth units ([0,1]
 *                  spans near..far of the light frustum).
 *   slope_bias     offset in texels of the receiver's own depth slope: 1
 *                  covers the depth change across one texel at the receiver's
 *                  angle to the light (tan θ, capped at 10).
 *
 * How it fails: aliasing (blocky edges at the texel grid), acne (self-
 * shadowing stripes) when the bias is too small, peter-panning (shadows
 * detached from their casters) when it is too large, and a hard edge where
 * the truth has a penumbra. */
#include "param_rows.h"

struct hard_settings {
    float constant_bias;  /* linear depth units, [0, 0.1] */
    float slope_bias;     /* texels of depth slope, [0, 16] */
};

static const struct technique_param hard_params[] = {
    PARAM_ROW_CONSTANT_BIAS(struct hard_settings),
    PARAM_ROW_SLOPE_BIAS(struct hard_settings, ""),
    {NULL},
};

static const struct technique_cell hard_cells[] = {
    {"grazing_receiver", {"constant_bias=0.005", "slope_bias=4"}},
    {NULL},
};

TECHNIQUE(hard, .needs = SM_DEPTH, .regression = hard_cells,
          .summary = "one depth comparison: aliased hard edge, no penumbra");
