/* evsm — exponential variance shadow maps (Annen, Mertens, Seidel, Flerackers
 * and Kautz 2008, "Exponential shadow maps", GI; Lauritzen and McCool 2008,
 * "Layered variance shadow maps", GI, which warps the moments
 * exponentially).
 *
 * Computes V as the Chebyshev bound of vsm, applied to the moments of
 * exponentially warped depth rather than of depth: with w = 2d - 1 (d the
 * linear depth in [0, 1]), the positive warp e^{c+ w} and, for evsm4, the
 * negative warp -e^{-c- w}, each with its square, read from the evsm product
 * (prefiltered by a separable Gaussian, mipmapped, sampled trilinearly at
 * the receiver's footprint) and taken at the receiver's own warped depth;
 * evsm4 keeps the smaller of the two bounds. A warp stretches the depths
 * behind a blocker apart from the blocker's own, so the variance a second
 * occluder far behind adds, which is what lights a vsm umbra, counts for
 * far less: the bound is tight where vsm's bleeds. Filament's "VSM" and
 * Falcor's EVSM are this.
 *
 * Parameters:
 *   variant             evsm2 (positive warp) or evsm4 (both warps).
 *   positive_exponent   c+, at most SM_EVSM_MAX_EXPONENT (42): e^{2c} at
 *                       depth 1 must stay within fp32 (FLT_MAX = e^{88.7}).
 *   negative_exponent   c- of evsm4, same bound.
 *   blur_radius_texels  Gaussian prefilter of the warped moments (sigma =
 *                       r / 2; 0 = mipmaps only), timed as filter prep.
 *   min_variance        floor on the variance of depth (linear depth
 *                       units squared), carried into each warp's space
 *                       through its slope: (dW/dd)² min_variance. Its own
 *                       row, far below vsm's: for an occluder well apart
 *                       from the receiver the floor lights the umbra by
 *                       about 4 c² min_variance (0.064 at c = 40 with
 *                       vsm's 1e-5), since the warped gap grows with the
 *                       same e^{cw} as the slope.
 *   bleed_reduction     maps the bound in [amount, 1] to [0, 1] (0 = off).
 *
 * How it fails: bleeding remains where the exponent cannot separate the
 * depths (blockers close in depth to the receiver: contact shadows bleed
 * with small c), and an exponent large enough to separate them makes the
 * warped moments of a receiver at a grazing slope vary steeply across a
 * texel: acne-like darkening unless min_variance is raised. The fp32 bound
 * on c limits how far the warp goes; the blur is fixed (no contact
 * hardening), as vsm's. */
#include "param_rows.h"

struct evsm_settings {
    int variant;              /* 0: evsm2, 1: evsm4 */
    float positive_exponent;  /* (0, SM_EVSM_MAX_EXPONENT] */
    float negative_exponent;  /* (0, SM_EVSM_MAX_EXPONENT] */
    int blur_radius_texels;   /* [0, SM_MAX_BLUR_RADIUS_TEXELS] */
    float min_variance;       /* linear depth², [0, 1e-4] */
    float bleed_reduction;    /* [0, 0.99] */
};

static const char *const evsm_variants[] = {"evsm2", "evsm4", NULL};

static const struct technique_param evsm_params[] = {
    {"variant", "evsm2: the positive warp; evsm4: positive and negative warps, the smaller bound",
     offsetof(struct evsm_settings, variant), PARAM_ENUM, 1, 0, 0, evsm_variants, TUNE_CHOICES},
    {"positive_exponent", "c+ of the warp e^{c+ (2d - 1)}; at most 42, what fp32 holds of e^{2c}",
     offsetof(struct evsm_settings, positive_exponent), PARAM_FLOAT, 40.0, 0.5, SM_EVSM_MAX_EXPONENT, NULL,
     TUNE(5, 10, 20, 30, 40, 42)},
    {"negative_exponent", "c- of the warp -e^{-c- (2d - 1)} (evsm4); at most 42",
     offsetof(struct evsm_settings, negative_exponent), PARAM_FLOAT, 5.0, 0.5, SM_EVSM_MAX_EXPONENT, NULL,
     TUNE(1, 2.5, 5, 10, 20, 40)},
    PARAM_ROW_BLUR_RADIUS(struct evsm_settings, "warped moments"),
    {"min_variance", "floor on the variance of depth, linear depth units squared, carried into each warp "
     "through its slope (an umbra is lit by about 4 c^2 times it)", offsetof(struct evsm_settings, min_variance),
     PARAM_FLOAT, 1e-8, 0.0, 1e-4, NULL, TUNE(1e-10, 1e-9, 1e-8, 1e-7, 1e-6)},
    PARAM_ROW_BLEED_REDUCTION(struct evsm_settings),
    {NULL},
};

static void evsm_request(const void *settings, const struct request_context *c, struct shadowmap_request *r)
{
    const struct evsm_settings *s = settings;
    (void)c;
    r->evsm.positive = s->positive_exponent, r->evsm.negative = s->negative_exponent;
    r->evsm.blur_radius_texels = s->blur_radius_texels;
}

static const struct technique_cell evsm_cells[] = {
    {"overlapping_occluders", {"variant=evsm2,positive_exponent=20", "bleed_reduction=0.3"}},
    {"contact_hardening", {"negative_exponent=20,blur_radius_texels=8"}},
    {"grazing_receiver", {"min_variance=1e-06"}},
    {NULL},
};

TECHNIQUE(evsm, .needs = SM_EVSM, .request = evsm_request, .regression = evsm_cells,
          .summary = "Chebyshev bound on exponentially warped moments: far less bleeding than vsm");
