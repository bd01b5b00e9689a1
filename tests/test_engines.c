/* The engine adapters against what they must equal (docs/engines.md):
 *   - the shadow term alone: where an adapter writes the engine's shadow
 *     term itself (three, Babylon, PlayCanvas), it equals the ratio of the engine's own
 *     lit render with shadows to the same without, on lit pixels, within
 *     1e-5 (two float32 renders whose only difference is the one factor: a
 *     few ulps), for every mode, on an area-light scene and a sun scene;
 *   - where the term IS that ratio (Filament: no shadow-term material),
 *     what makes the ratio the shadow factor: the unshadowed render is 0
 *     exactly where the light is wholly behind the surface (no ambient, no
 *     emissive, no indirect light) and above 0 where it is wholly in front
 *     (the light reaches every scored point); the ratio lies in [0, 1 +
 *     1e-5] on lit pixels; and on the pixels the truth sees fully lit, at
 *     least a quarter have a ratio within 1e-6 of 1 (a term the shadowed
 *     variant multiplies in besides the visibility would move them all;
 *     Filament's own light acne at its default biases moves about half of
 *     them on the sun scenes, a few on the spot scenes);
 *   - coverage: on every shipped scene the engine sees a surface where the
 *     ray tracer's camera rays hit one, at the same distance (within its
 *     mode's depth tolerance: METRICS_DEPTH_TOLERANCE, or Filament's own
 *     off the truth's silhouettes, techniques/filament.c), silhouettes aside and
 *     counted: a pixel that disagrees must lie next to a change of the
 *     truth's coverage or a jump of its distance. The check can fail: the
 *     engine's own distances moved 3 tolerances along every ray (another
 *     surface) disagree on every hit pixel off the silhouettes. A wider
 *     tolerance must still be needed: at METRICS_DEPTH_TOLERANCE some
 *     shipped scene disagrees off its silhouettes;
 *   - on parallel_planes, each engine's nearest mode to one comparison is a
 *     hard edge within a texel of shadowbench's own `hard`: row by row,
 *     their edges' world positions on the receiver differ by at most one
 *     texel of shadowbench's map there, plus the pixel each is found to.
 *     three's BasicShadowMap and Babylon's unfiltered map use shadowbench's
 *     map; PlayCanvas's PCF1 (one hardware compare of a linearly filtered
 *     map, a bilinear 2 x 2) and Filament's PCF (Castano's 3 x 3 tent: it
 *     has no unfiltered mode) are symmetric filters, which leave a straight
 *     edge's 0.5 crossing where one compare puts it, on maps 1.4 to 2 times
 *     as coarse (their symmetric cones): the coarser maps must move no edge
 *     by more than a texel of shadowbench's.
 * Skips (77) when the engines are not installed. */
#include "check.h"
#include "base/util.h"
#include "engine/engine.h"
#include "gl/gl_context.h"
#include "gl/shader.h"
#include "pipeline/cell.h"
#include "scene/catalog.h"
#include "scene/light_frustum.h"
#include "techniques/params.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define W 96
#define H 72

static struct program_cache programs;

static int open_scene(struct scene *s, struct scene_setup *ss, const char *name)
{
    char *path = catalog_resolve(name);
    const int rc = !path || scene_load(path, s) != 0 ||
                   scene_setup_open(ss, s, &(struct scene_setup_desc){.width = W, .height = H,
                                                                      .shadow_map_size = 1024, .gt_samples = 64,
                                                                      .programs = &programs});
    free(path);
    return rc ? -1 : 0;
}

static void *settings_of(const struct technique *t, const char *list)
{
    void *s = params_defaults(t);
    if (list && params_apply(t, s, list, t->name) != 0)
        CHECK(false, "%s: %s", t->name, list);
    return s;
}

/* How each engine is checked: its mode nearest to one comparison (its
 * camera, and its light's frustum against shadowbench's) with the settings
 * it is checked at, and whether the adapter's shadow term is the lit /
 * unlit ratio itself. */
struct engine_check {
    const char *engine, *edge_mode, *edge_settings;
    bool term_is_ratio;
};

static const struct engine_check engine_checks[] = {
    {"three", "three_basic", "normal_bias=0.02", false},
    {"babylon", "babylon_hard", "normal_bias=0.02", false},
    {"playcanvas", "playcanvas_pcf1", "normal_bias=0.02", false},
    {"filament", "filament_pcf", NULL, true},
};
#define ENGINE_CHECKS (int)(sizeof engine_checks / sizeof engine_checks[0])

static const struct engine_check *check_of(const struct technique *t)
{
    for (int i = 0; i < ENGINE_CHECKS; i++)
        if (strcmp(engine_checks[i].engine, t->engine) == 0)
            return &engine_checks[i];
    return NULL;
}

/* Renders outputs of t at its settings on ss (the caller's W x H images). */
static int render_outputs(const struct technique *t, const void *settings, struct scene *s, struct scene_setup *ss,
                          float *img[ENGINE_OUTPUT_COUNT], unsigned outputs)
{
    struct engine_result e = {0};
    memcpy(e.image, img, sizeof e.image);
    return engine_render(&(struct engine_request){.t = t, .settings = settings, .scene = s,
                                                  .frustum = &ss->cascades.map[0].frustum, .label = t->name,
                                                  .width = W, .height = H, .map_size = 1024, .frames = 1,
                                                  .outputs = outputs},
                         &e);
}

/* Every mode that writes its shadow term itself: shadow == lit / unlit on lit pixels. */
static void shadow_term_is_the_ratio(const char *scene_name)
{
    struct scene s = {0};
    struct scene_setup ss = {0};
    if (open_scene(&s, &ss, scene_name) != 0) {
        CHECK(false, "%s: set-up", scene_name);
        scene_setup_free(&ss), scene_free(&s);
        return;
    }
    const size_t n = (size_t)W * H;
    float *img[ENGINE_OUTPUT_COUNT];
    for (int k = 0; k < ENGINE_OUTPUT_COUNT; k++)
        img[k] = xmalloc(sizeof(float) * n);
    for (const struct technique *const *t = technique_list; *t; t++) {
        if (!technique_is_engine(*t) || check_of(*t)->term_is_ratio)
            continue;
        /* a normal bias against acne where the mode has one (PlayCanvas ignores it for VSM, so its
         * playcanvas_vsm has none) */
        void *settings = settings_of(*t, params_find(*t, "normal_bias") ? "normal_bias=0.02" : NULL);
        const int rc = render_outputs(*t, settings, &s, &ss, img, (1u << ENGINE_OUTPUT_COUNT) - 1);
        CHECK(rc == 0, "%s on %s: rendered", (*t)->name, scene_name);
        float peak = 0;
        for (size_t i = 0; i < n && !rc; i++)
            peak = fmaxf(peak, img[ENGINE_OUT_UNLIT][i]);
        long lit = 0, off = 0, shadowed = 0;
        double worst = 0;
        for (size_t i = 0; i < n && !rc; i++) {
            if (!(img[ENGINE_OUT_UNLIT][i] > 1e-4f * peak))  /* the engine's own light leaves it dark */
                continue;
            lit++;
            const double ratio = (double)img[ENGINE_OUT_LIT][i] / img[ENGINE_OUT_UNLIT][i];
            const double d = fabs(ratio - img[ENGINE_OUT_SHADOW][i]);
            worst = fmax(worst, d);
            if (d > 1e-5 && getenv("SB_TEST_VERBOSE") && off < 4)
                printf("  %s (%zu, %zu): shadow %.6g, lit %.6g, unlit %.6g\n", (*t)->name, i % W, i / W,
                       img[ENGINE_OUT_SHADOW][i], img[ENGINE_OUT_LIT][i], img[ENGINE_OUT_UNLIT][i]);
            off += d > 1e-5;
            shadowed += img[ENGINE_OUT_SHADOW][i] < 0.5f;
        }
        CHECK(!rc && lit > (long)n / 10, "%s on %s: %ld lit pixels", (*t)->name, scene_name, lit);
        CHECK(!rc && shadowed > 0, "%s on %s: a shadow to compare", (*t)->name, scene_name);
        CHECK(!rc && off == 0, "%s on %s: %ld of %ld lit pixels differ from lit/unlit by more than 1e-5 "
              "(worst %.3g)", (*t)->name, scene_name, off, lit, worst);
        printf("%s on %s: shadow term vs lit/unlit on %ld lit pixels: worst %.3g\n", (*t)->name, scene_name, lit,
               worst);
        free(settings);
    }
    for (int k = 0; k < ENGINE_OUTPUT_COUNT; k++)
        free(img[k]);
    scene_setup_free(&ss), scene_free(&s);
}

/* Every mode whose shadow term is lit / unlit: what makes that ratio the
 * engine's shadow factor (see the top of this file). Returns the pixels
 * the truth sees with the light wholly behind them, which the caller
 * wants some of over its scenes. */
static long ratio_is_the_factor(const char *scene_name)
{
    struct scene s = {0};
    struct scene_setup ss = {0};
    long behind_all = 0;
    if (open_scene(&s, &ss, scene_name) != 0) {
        CHECK(false, "%s: set-up", scene_name);
        scene_setup_free(&ss), scene_free(&s);
        return 0;
    }
    const size_t n = (size_t)W * H;
    float *img[ENGINE_OUTPUT_COUNT];
    for (int k = 0; k < ENGINE_OUTPUT_COUNT; k++)
        img[k] = xmalloc(sizeof(float) * n);
    for (const struct technique *const *t = technique_list; *t; t++) {
        if (!technique_is_engine(*t) || !check_of(*t)->term_is_ratio)
            continue;
        void *settings = settings_of(*t, NULL);
        const int rc = render_outputs(*t, settings, &s, &ss, img, (1u << ENGINE_OUTPUT_COUNT) - 1);
        CHECK(rc == 0, "%s on %s: rendered", (*t)->name, scene_name);
        const float *lit = img[ENGINE_OUT_LIT], *unlit = img[ENGINE_OUT_UNLIT], *d = img[ENGINE_OUT_DISTANCE];
        const float tol = metrics_depth_tolerance((*t)->depth_tolerance);
        long behind = 0, behind_bright = 0, front = 0, front_dark = 0, lighted = 0, outside = 0, full = 0,
             full_one = 0, shadowed = 0;
        double worst = 0;
        for (size_t i = 0; i < n && !rc; i++) {
            const float g = ss.gt.distance[i];
            if (g < 0 || !(fabsf(d[i] - g) <= tol * g))
                continue;  /* no surface, or not the truth's (a silhouette) */
            if (ss.gt.h[i] == 0) {
                behind++;
                behind_bright += unlit[i] != 0;
            }
            if (ss.gt.h[i] == 1) {
                front++;
                front_dark += !(unlit[i] > 0);
            }
            if (!(unlit[i] > 0))
                continue;
            lighted++;
            const double ratio = (double)lit[i] / unlit[i];
            if (!(ratio >= 0 && ratio <= 1 + 1e-5)) {
                outside++;
                worst = fmax(worst, fabs(ratio - 0.5) + 0.5);
            }
            shadowed += ratio < 0.5;
            if (ss.gt.mask[i] > 0.5f && ss.gt.v[i] == 1) {
                full++;
                full_one += fabs(ratio - 1) <= 1e-6;
                if (fabs(ratio - 1) > 1e-6 && getenv("SB_TEST_VERBOSE") && full - full_one < 6)
                    printf("  %s (%zu, %zu): fully lit in the truth, lit / unlit %.7g\n", (*t)->name, i % W, i / W,
                           ratio);
            }
        }
        CHECK(!rc && behind_bright == 0, "%s on %s: %ld of %ld pixels with the light wholly behind them are lit "
              "(ambient, emissive or indirect light)", (*t)->name, scene_name, behind_bright, behind);
        CHECK(!rc && front_dark == 0, "%s on %s: %ld of %ld pixels with the light wholly in front are dark (the "
              "light does not reach them)", (*t)->name, scene_name, front_dark, front);
        CHECK(!rc && outside == 0, "%s on %s: %ld of %ld lit pixels have lit / unlit outside [0, 1 + 1e-5] (worst "
              "%.6g)", (*t)->name, scene_name, outside, lighted, worst);
        CHECK(!rc && shadowed > 0, "%s on %s: a shadow to compare", (*t)->name, scene_name);
        CHECK(!rc && full > 0 && full_one * 4 >= full, "%s on %s: of %ld pixels the truth sees fully lit, %ld have "
              "lit / unlit within 1e-6 of 1, under a quarter", (*t)->name, scene_name, full, full_one);
        printf("%s on %s: unlit 0 on %ld of %ld pixels with the light behind, lit on %ld of %ld with it in front; "
               "lit / unlit in [0, 1 + 1e-5] on %ld of %ld lit pixels; 1 within 1e-6 on %ld of %ld fully lit\n",
               (*t)->name, scene_name, behind - behind_bright, behind, front - front_dark, front,
               lighted - outside, lighted, full_one, full);
        behind_all += behind;
        free(settings);
    }
    for (int k = 0; k < ENGINE_OUTPUT_COUNT; k++)
        free(img[k]);
    scene_setup_free(&ss), scene_free(&s);
    return behind_all;
}

/* Where the engine's camera rays and the truth's disagree (one hits and
 * the other not, or both at distances more than tol apart, relative; on the
 * truth's silhouettes, metrics_truth_silhouette, at most the harness's
 * tolerance, as the scored mask takes them): how many such pixels lie on
 * the truth's silhouettes (edge) and how many off them (inner); of the
 * edge ones, how many disagree by more than tol too (far_edge: another
 * surface, whatever the tolerance); of the pixels off the silhouettes where
 * both hit, how many there are (both) and the largest relative difference
 * (worst). */
struct disagreement {
    long edge, far_edge, inner, both;
    double worst;
};

/* Whether the truth's distance g and the engine's e see one surface: both
 * miss, or both hit within tol, relative. */
static bool same_surface(float g, float e, float tol)
{
    return (g >= 0) == (e >= 0) && (g < 0 || fabsf(e - g) <= tol * g);
}

static struct disagreement disagreements(const float *truth, const float *engine, float tol)
{
    struct disagreement r = {0};
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const size_t i = (size_t)y * W + x;
            const float g = truth[i], e = engine[i];
            const bool edge = metrics_truth_silhouette(truth, W, H, x, y);
            const bool agree = same_surface(g, e, edge ? fminf(tol, METRICS_DEPTH_TOLERANCE) : tol);
            r.edge += !agree && edge;
            r.far_edge += edge && !same_surface(g, e, tol);
            r.inner += !agree && !edge;
            if (!edge && g >= 0 && e >= 0) {
                r.both++;
                r.worst = fmax(r.worst, fabs((double)e - g) / g);
            }
            if (!agree && !edge && getenv("SB_TEST_VERBOSE") && r.inner < 5)
                printf("  (%d, %d): truth %.6g, engine %.6g\n", x, y, g, e);
        }
    return r;
}

static void coverage_matches_truth(const struct engine_check *c)
{
    const char *technique = c->edge_mode;
    char **paths = NULL;
    const int count = catalog_shipped(&paths);
    CHECK(count > 10, "the shipped scenes");
    const struct technique *t = technique_find(technique);
    const float tol = metrics_depth_tolerance(t->depth_tolerance);
    void *settings = settings_of(t, NULL);
    float *moved = xmalloc(sizeof(float) * W * H);
    int needs_wider = 0;
    double worst = 0;
    for (int k = 0; k < count; k++) {
        struct scene s = {0};
        struct scene_setup ss = {0};
        struct metrics m = {0};
        if (scene_load(paths[k], &s) != 0 ||
            scene_setup_open(&ss, &s, &(struct scene_setup_desc){.width = W, .height = H, .shadow_map_size = 512,
                                                                  .gt_samples = 16, .programs = &programs}) != 0 ||
            scene_setup_cell(&ss, t, settings, &m) != 0) {
            CHECK(false, "%s: rendered", paths[k]);
        } else {
            long hits = 0;
            for (int i = 0; i < W * H; i++)
                hits += ss.gt.distance[i] >= 0;
            const struct disagreement d = disagreements(ss.gt.distance, ss.distance, tol);
            CHECK(d.inner == 0, "%s, %s: %ld pixels off the silhouettes disagree with the truth's camera rays by "
                  "more than %g (worst %.3g)", technique, s.name, d.inner, (double)tol, d.worst);
            /* at most 1 % of the hits on another surface (seen: 13 of 5878 on thin_features), or the silhouette
             * rule hides a shift (a wider tolerance's own error on the silhouettes, where the harness's stays,
             * is not another surface: Filament's clipped planes, up to 250 of 4721 on cascade_shimmer) */
            CHECK(d.far_edge * 100 <= hits, "%s, %s: %ld silhouette pixels see another surface, over 1 %% of %ld",
                  technique, s.name, d.far_edge, hits);
            CHECK(m.mismatch_pixels == d.edge + d.inner, "%s: the metrics count %ld mismatches, the test %ld", s.name,
                  m.mismatch_pixels, d.edge + d.inner);
            /* the check can fail: the same surfaces 3 tolerances farther along every ray, another surface, are
             * caught wherever both hit off the silhouettes (a distance within tol of the truth's, moved by 3 tol,
             * is over tol from it for any tol under 1/3) */
            for (int i = 0; i < W * H; i++)
                moved[i] = ss.distance[i] >= 0 ? ss.distance[i] * (1 + 3 * tol) : ss.distance[i];
            const struct disagreement other = disagreements(ss.gt.distance, moved, tol);
            CHECK(other.inner == d.both, "%s, %s: of %ld pixels off the silhouettes, %ld disagree with another surface "
                  "3 depth tolerances away", technique, s.name, d.both, other.inner);
            if (tol > METRICS_DEPTH_TOLERANCE)
                needs_wider += disagreements(ss.gt.distance, ss.distance, METRICS_DEPTH_TOLERANCE).inner > 0;
            worst = fmax(worst, d.worst);
            printf("%s, %s: coverage: %ld of %ld hit pixels, %ld silhouette pixels disagree; off them the distance "
                   "within %.2g of the truth's\n", technique, s.name, hits, (long)W * H, d.edge, d.worst);
        }
        scene_setup_free(&ss), scene_free(&s);
    }
    /* a tolerance wider than the harness's rests on a measured error; once no scene shows it, narrow it */
    CHECK(tol <= METRICS_DEPTH_TOLERANCE || needs_wider > 0, "%s: no shipped scene disagrees with the truth's "
          "camera distance by more than %g off its silhouettes: its depth tolerance %g is no longer needed",
          technique, (double)METRICS_DEPTH_TOLERANCE, (double)tol);
    printf("%s: depth tolerance %g; off the silhouettes, the distance within %.3g of the truth's on every shipped "
           "scene, %d of them beyond %g\n", technique, (double)tol, worst, needs_wider,
           (double)METRICS_DEPTH_TOLERANCE);
    free(moved), free(settings);
    catalog_free(paths, count);
}

/* The world point pixel i's camera ray hits (the truth's distance). */
static struct vec3 hit_point(const struct scene *s, const float *distance, int x, int y)
{
    const struct scene_camera *c = &s->camera;
    const float ty = tanf(0.5f * c->yfov_rad), tx = ty * (float)W / (float)H;
    const float px = (2.0f * ((float)x + 0.5f) / W - 1.0f) * tx, py = (1.0f - 2.0f * ((float)y + 0.5f) / H) * ty;
    const struct vec3 dir = v3_normalize(v3_add(v3_add(v3_scale(c->x, px), v3_scale(c->y, py)), v3_scale(c->z, -1)));
    return v3_add(c->pos, v3_scale(dir, distance[(size_t)y * W + x]));
}

/* The first pixel of row y, left to right, where v reaches 0.5 after a
 * pixel below it; -1 without one. */
static int edge_in_row(const float *v, const float *scored, int y)
{
    for (int x = 1; x < W; x++) {
        const size_t i = (size_t)y * W + x;
        if (scored[i] > 0.5f && scored[i - 1] > 0.5f && v[i - 1] < 0.5f && v[i] >= 0.5f)
            return x;
    }
    return -1;
}

static void basic_is_hard(const struct engine_check *c)
{
    const char *technique = c->edge_mode;
    struct scene s = {0};
    struct scene_setup ss = {0};
    if (open_scene(&s, &ss, "parallel_planes") != 0) {
        CHECK(false, "parallel_planes: set-up");
        scene_setup_free(&ss), scene_free(&s);
        return;
    }
    const struct technique *hard = technique_find("hard"), *basic = technique_find(technique);
    void *hs = settings_of(hard, NULL), *bs = settings_of(basic, c->edge_settings);
    const size_t n = (size_t)W * H;
    float *v_hard = xmalloc(sizeof(float) * n);
    struct metrics m;
    int rows = 0;
    double worst = 0;
    if (scene_setup_cell(&ss, hard, hs, &m) == 0) {
        memcpy(v_hard, ss.v, sizeof(float) * n);
        if (scene_setup_cell(&ss, basic, bs, &m) == 0) {
            const struct light_frustum *f = &ss.cascades.map[0].frustum;
            /* a texel of shadowbench's map, whatever the engine's own: PlayCanvas's and Filament's cones make
             * theirs 1.4 to 2 times as wide here, and their filters (a bilinear compare, Castano's tent) are
             * symmetric, which leaves a straight edge's 0.5 crossing where one compare puts it */
            const double texel = light_frustum_texel_world(f, 1024, f->far_world);
            for (int y = 0; y < H; y++) {
                const int a = edge_in_row(v_hard, ss.scored, y), b = edge_in_row(ss.v, ss.scored, y);
                if (a < 1 || b < 1)
                    continue;
                rows++;
                const double gap = v3_length(v3_sub(hit_point(&s, ss.gt.distance, a, y),
                                                    hit_point(&s, ss.gt.distance, b, y)));
                const double pixel = v3_length(v3_sub(hit_point(&s, ss.gt.distance, a, y),
                                                      hit_point(&s, ss.gt.distance, a - 1, y)));
                worst = fmax(worst, gap / (texel + pixel));
                CHECK(gap <= texel + pixel, "row %d: %s's edge %.4g from hard's, more than a texel (%.4g) and a "
                      "pixel (%.4g)", y, technique, gap, texel, pixel);
            }
        }
    }
    CHECK(rows > H / 2, "parallel_planes: %d rows with an edge in both", rows);
    printf("parallel_planes: %s's edge vs hard's over %d rows: at most %.3f of (a texel + a pixel)\n",
           technique, rows, worst);
    free(v_hard), free(hs), free(bs);
    scene_setup_free(&ss), scene_free(&s);
}

int main(void)
{
    bool installed = true;
    for (const struct technique *const *t = technique_list; *t; t++)  /* every engine's */
        installed = installed && (!technique_is_engine(*t) || engine_installed((*t)->engine));
    if (!installed) {
        printf("skipped: the engines are not installed (tools/setup installs them)\n");
        return 77;
    }
    char *shaders = util_printf("%s/shaders", SB_SOURCE_DIR);
    if (gl_context_create(GL_BACKEND_OSMESA) != 0 || shader_init(shaders) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    bool rows = true;  /* every engine has its row of engine_checks */
    for (const struct technique *const *t = technique_list; *t; t++)
        if (technique_is_engine(*t) && !check_of(*t)) {
            CHECK(false, "%s: its engine %s has no row in engine_checks", (*t)->name, (*t)->engine);
            rows = false;
        }
    if (!rows)
        return check_finish();
    shadow_term_is_the_ratio("overlapping_occluders");
    shadow_term_is_the_ratio("sun_contact");
    long behind = 0;
    const char *const ratio_scenes[] = {"overlapping_occluders", "sun_wide", "floating_box_sphere", "sun_grazing"};
    for (int i = 0; i < 4; i++)
        behind += ratio_is_the_factor(ratio_scenes[i]);
    CHECK(behind > 0, "the ratio checks' scenes show surfaces with the light behind them");
    /* each engine's mode nearest one comparison: its camera, and its light's frustum against shadowbench's */
    for (int i = 0; i < ENGINE_CHECKS; i++) {
        coverage_matches_truth(&engine_checks[i]);
        basic_is_hard(&engine_checks[i]);
    }
    programs_free(&programs);
    engine_shutdown();
    gl_context_destroy();
    gt_shutdown();
    free(shaders);  /* shader_init keeps it */
    return check_finish();
}
