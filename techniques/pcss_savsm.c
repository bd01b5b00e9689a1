/* pcss_savsm — PCSS on a summed-area variance shadow map, as the seed
 * article 004 builds it: the Chebyshev blocker estimate and Lauritzen's SAT
 * filtering, with no kernel subdivision. It is not Yang et al. 2010's
 * "Variance soft shadow mapping" (VSSM), which subdivides the kernel where
 * the Chebyshev test is unreliable: that is techniques/vssm.c.
 *
 * Computes V like PCSS, with both area queries answered in O(1) by the SAT
 * of the moments. Blocker search: over the search box take mean mu and
 * variance s² of depth; alpha = Chebyshev bound at the receiver depth t is
 * the estimated unblocked share, so the blocked share 1 - alpha has mean
 * depth z_occ = (mu - alpha t) / (1 - alpha) (guards: t <= mu -> lit;
 * 1 - alpha < min_blocker_fraction -> lit; z_occ clamped to [0, t]).
 * Penumbra width as PCSS; then VSM over that box. Both steps are exact for a
 * planar blocker over a planar receiver parallel to a rect light: the box
 * holds two depths, where the Chebyshev bound is tight. For a disk light the
 * search box bounds the disk's footprint and the filter box has its area.
 *
 * Parameters:
 *   sat_format            as savsm (int32: the scale is set by the widest
 *                         search box, light_size_uv * (1 - near/far); the
 *                         sun's, light_size_uv * (far - near)).
 *   light_size_scale      multiplies the scene's light size.
 *   min_variance          floor on the variance, linear depth units squared.
 *   min_blocker_fraction  below this estimated blocked share, lit.
 *   bleed_reduction       as vsm, on the final bound (0 = off).
 *
 * How it fails: both of VSM's errors, twice — bleeding in the filter, and a
 * wrong z_occ where the search box holds more than two depths (a sloped or
 * curved receiver, overlapping blockers), which sets a wrong penumbra width;
 * box-shaped kernels; SAT precision as savsm. */
#include "param_rows.h"

struct pcss_savsm_settings {
    int sat_format;              /* enum sat_format */
    float light_size_scale;      /* [0.01, 10] */
    float min_variance;          /* linear depth², [0, 0.01] */
    float min_blocker_fraction;  /* [0, 0.5] */
    float bleed_reduction;       /* [0, 0.99] */
};

static const struct technique_param pcss_savsm_params[] = {
    PARAM_ROW_SAT_FORMAT(struct pcss_savsm_settings),
    PARAM_ROW_LIGHT_SIZE_SCALE(struct pcss_savsm_settings),
    PARAM_ROW_MIN_VARIANCE(struct pcss_savsm_settings),
    PARAM_ROW_MIN_BLOCKER_FRACTION(struct pcss_savsm_settings, "estimated blocked share"),
    PARAM_ROW_BLEED_REDUCTION(struct pcss_savsm_settings),
    {NULL},
};

static void pcss_savsm_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    const struct pcss_savsm_settings *s = settings;
    sat_request_search_box(&r->moments_sat, s->sat_format, s->light_size_scale, c);
}

static const struct technique_cell pcss_savsm_cells[] = {
    {"floating_box_sphere", {"sat_format=fp32", "sat_format=fp32_centered"}},
    {"parallel_planes", {"light_size_scale=0.5", "min_variance=0.001"}},
    {"contact_hardening", {"min_blocker_fraction=0.05"}},
    {"overlapping_occluders", {"bleed_reduction=0.3"}},
    {NULL},
};

TECHNIQUE(pcss_savsm, .needs = SM_MOMENTS_SAT, .request = pcss_savsm_request, .regression = pcss_savsm_cells,
          .summary = "PCSS with blocker depth and filtering from SAT moments: O(1) in the light size");
