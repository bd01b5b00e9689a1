/* savsm — summed-area variance shadow maps (Lauritzen 2007, "Summed-area
 * variance shadow maps", GPU Gems 3 ch. 8).
 *
 * Computes V as VSM's Chebyshev bound, with the mean and variance of depth
 * taken over a box of any size from a summed-area table of the moments: 4
 * reads per corner pair, 16 SAT values per box, since the box edges fall
 * between texels and the SAT is read bilinearly (the exact integral of the
 * texels over the box). The box is box_width_texels wide, or the receiver's
 * screen footprint in the map where that is larger (no aliasing at a
 * distance).
 *
 * Parameters:
 *   box_width_texels  side of the filter box, texels.
 *   sat_format        fp32: float sums of (d, d²); fp32_centered: of
 *                     (d - 0.5, (d - 0.5)²); int32: fixed point in uint32
 *                     (exact box sums; the scale adapts so the widest box
 *                     fits: boxes, footprint included, are clipped to
 *                     max(box_width_texels, 64) texels).
 *   min_variance      floor on the variance, linear depth units squared.
 *   bleed_reduction   as vsm (0 = off).
 *
 * How it fails: as vsm (light bleeding), plus precision: an fp32 SAT sums
 * millions of values, so a box's mean and variance come from the difference
 * of large, rounded numbers — worst far from the map's origin and for depths
 * far from 0 (centring helps, int32 is exact); the variance, a difference of
 * two rounded moments, suffers most. Box kernels look boxy. */
#include "param_rows.h"

struct savsm_settings {
    float box_width_texels;  /* [1, 1024] */
    int sat_format;          /* enum sat_format */
    float min_variance;      /* linear depth², [0, 0.01] */
    float bleed_reduction;   /* [0, 0.99] */
};

#define SAVSM_MAX_FOOTPRINT_TEXELS 64.0f

static const struct technique_param savsm_params[] = {
    {"box_width_texels", "side of the filter box, shadow-map texels",
     offsetof(struct savsm_settings, box_width_texels), PARAM_FLOAT, 5.0, 1.0, 1024.0, NULL,
     TUNE(1, 3, 5, 9, 17, 33, 65, 129, 257)},
    PARAM_ROW_SAT_FORMAT(struct savsm_settings),
    PARAM_ROW_MIN_VARIANCE(struct savsm_settings),
    PARAM_ROW_BLEED_REDUCTION(struct savsm_settings),
    {NULL},
};

static void savsm_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    const struct savsm_settings *s = settings;
    (void)c;
    r->moments_sat.format = (enum sat_format)s->sat_format;
    /* The footprint can exceed the box at a distance or a grazing angle;
     * int32 clips boxes to this side, and a wider bound would cost
     * fixed-point bits everywhere (64 texels leave 18 of them). */
    r->moments_sat.max_box_texels = s->box_width_texels > SAVSM_MAX_FOOTPRINT_TEXELS
                                        ? s->box_width_texels : SAVSM_MAX_FOOTPRINT_TEXELS;
}

static const struct technique_cell savsm_cells[] = {
    {"parallel_planes", {"box_width_texels=15", "min_variance=0.001"}},
    {"floating_box_sphere", {"sat_format=fp32", "sat_format=fp32_centered"}},
    {"overlapping_occluders", {"bleed_reduction=0.3"}},
    {NULL},
};

TECHNIQUE(savsm, .needs = SM_MOMENTS_SAT, .request = savsm_request, .regression = savsm_cells,
          .summary = "VSM over an exact box filter from a summed-area table: bleeding, SAT precision");
