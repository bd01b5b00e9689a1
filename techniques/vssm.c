/* vssm — variance soft shadow mapping (Yang, Dong, Feng, Seidel and Kautz
 * 2010, "Variance soft shadow mapping", Computer Graphics Forum 29(7),
 * Pacific Graphics): PCSS on the summed-area table of the moments, as
 * pcss_savsm, plus the paper's kernel subdivision where the Chebyshev
 * estimate cannot be trusted.
 *
 * Computes V like pcss_savsm: over the search box, mean mu and variance s²
 * of depth; alpha = Chebyshev bound at the receiver depth t is the
 * unblocked share, and the blocked share 1 - alpha has mean depth z_occ =
 * (mu - alpha t) / (1 - alpha); penumbra width as PCSS; VSM over that box.
 * That estimate assumes the box holds two depths, the receiver's and one
 * blocker's. Surfaces farther than the receiver in the box (a receiver
 * sloping away, a ground plane seen past a caster's edge) break it, and a
 * box shows it in one of two ways: t <= mu, where the bound says "no
 * blocker, lit" (the case the paper names), or a variance so large that
 * the blocker depth the two-depth model needs, mu - s² / (t - mu), lies
 * nearer than the near plane, where no geometry is. There the box is split
 * into N x N sub-boxes, each estimated alone (its own mean and variance
 * from the SAT), and the results averaged: the blocked share and its depth
 * mass in the search, the visibility in the filter. A sub-box with t <= its
 * mean counts as unblocked. Where a box does hold two depths, the sub-boxes
 * do too and their average equals the box's estimate (parallel_planes:
 * identical to pcss_savsm). Elsewhere it can cost accuracy: on a steep
 * receiver (contact_hardening's pole) sub-boxes that hold only the
 * receiver's own far side darken its lit face (a hostile pass at 128²:
 * rmse 0.026 -> 0.094 against subdivisions 1). The paper subdivides in the same two places.
 * Uniform (the default): N x N sub-boxes at once. Adaptive (the paper's
 * scheme, adaptive=true): 2 x 2, and each part whose own estimate is
 * still not to be trusted split again, down to 1/N of the box (N rounded
 * up to a power of two, at most 3 levels); a part trusted on the way is
 * estimated whole. At the default run's 512² it draws lower
 * penumbra_rmse than uniform at N = 4 and 8 but leaks more on
 * overlapping_occluders at N = 4 (docs/techniques.md, vssm), and on llvmpipe it is
 * not cheaper: the reads it saves where parts are trusted it spends on
 * the intermediate levels and a divergent loop.
 * The second trigger is ours: on overlapping_occluders the leak comes from
 * boxes with t > mu whose far ground inflates the variance, and with the
 * t <= mu trigger alone the leak_fraction stayed 0.518 for N = 1 to 8 (as
 * pcss_savsm's; 256², 144 samples).
 *
 * receiver_plane (an addition to the paper): each sub-box is tested at
 * the depth of the receiver's plane at its centre, not at the pixel's t.
 * A sub-box on the near side of a sloped receiver otherwise reads the
 * receiver itself as a blocker (t > its mean), and the subdivision turns
 * every sloped surface into acne: without the plane 77 % of
 * grazing_receiver's lit pixels are dark (test_soft_techniques; 0.08 %
 * with it), as an earlier experiment with one 2 x 2 level found (73 %).
 *
 * Parameters:
 *   sat_format, light_size_scale, min_variance, min_blocker_fraction,
 *   bleed_reduction   as pcss_savsm.
 *   subdivisions      N: sub-boxes per axis where a box's estimate is not
 *                     to be trusted (either trigger above; 1 = pcss_savsm);
 *                     the pixels that need it cost N² SAT box reads more.
 *   adaptive          split level by level where needed (above), not
 *                     N x N at once.
 *   receiver_plane    test each sub-box at the receiver's plane (above).
 *
 * How it fails: inside each sub-box VSM's errors remain (bleeding where
 * blockers overlap in depth, a z_occ averaged over several depths); a
 * sub-box holding blockers and more far receiver than blockers still
 * reads t <= mu and lit, so a coarse grid leaves part of the leak it
 * targets; the receiver plane is the pixel's tangent plane, so a curved
 * receiver's sub-boxes still see its curvature; box kernels; SAT
 * precision as savsm. */
#include "param_rows.h"

struct vssm_settings {
    int sat_format;              /* enum sat_format */
    float light_size_scale;      /* [0.01, 10] */
    float min_variance;          /* linear depth², [0, 0.01] */
    float min_blocker_fraction;  /* [0, 0.5] */
    float bleed_reduction;       /* [0, 0.99] */
    int subdivisions;            /* [1, 8]: N x N sub-boxes */
    int adaptive;                /* bool */
    int receiver_plane;          /* bool */
};

static const struct technique_param vssm_params[] = {
    PARAM_ROW_SAT_FORMAT(struct vssm_settings),
    PARAM_ROW_LIGHT_SIZE_SCALE(struct vssm_settings),
    PARAM_ROW_MIN_VARIANCE(struct vssm_settings),
    PARAM_ROW_MIN_BLOCKER_FRACTION(struct vssm_settings, "estimated blocked share"),
    PARAM_ROW_BLEED_REDUCTION(struct vssm_settings),
    {"subdivisions", "sub-boxes per axis where a box's Chebyshev estimate is not to be trusted (1 = none)",
     offsetof(struct vssm_settings, subdivisions), PARAM_INT, 2, 1, 8, NULL, TUNE(2, 4)},
    /* Not tuned: it would double vssm's tune, already past its budget;
     * its effect is measured by a sweep (docs/techniques.md, vssm). */
    {"adaptive", "split 2 x 2, and again where a part is still not to be trusted, down to 1/N of the box "
     "(N rounded up to a power of two); else N x N at once", offsetof(struct vssm_settings, adaptive),
     PARAM_BOOL, 0, 0, 1, NULL, NULL},
    {"receiver_plane", "test each sub-box at the receiver's plane at its centre, not at the pixel's depth",
     offsetof(struct vssm_settings, receiver_plane), PARAM_BOOL, 1, 0, 1, NULL, TUNE_CHOICES},
    {NULL},
};

static void vssm_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    const struct vssm_settings *s = settings;
    sat_request_search_box(&r->moments_sat, s->sat_format, s->light_size_scale, c);
}

static const struct technique_cell vssm_cells[] = {
    {"floating_box_sphere", {"sat_format=fp32_centered"}},
    {"parallel_planes", {"light_size_scale=0.5"}},
    {"grazing_receiver", {"min_variance=0.001"}},
    {"contact_hardening", {"min_blocker_fraction=0.05"}},
    {"overlapping_occluders", {"bleed_reduction=0.3", "subdivisions=4", "adaptive=true,subdivisions=4"}},
    {"curved_receivers", {"receiver_plane=false"}},
    {NULL},
};

TECHNIQUE(vssm, .needs = SM_MOMENTS_SAT, .request = vssm_request, .regression = vssm_cells,
          .summary = "PCSS on SAT moments, the kernel subdivided where the Chebyshev test says lit wrongly");
