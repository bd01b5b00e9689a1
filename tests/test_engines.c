/* The engine adapters against what they must equal (docs/engines.md):
 *   - the shadow term alone: what the adapter hands back equals the ratio
 *     of the engine's own lit render with shadows to the same without, on
 *     lit pixels, within 1e-5 (two float32 renders whose only difference
 *     is the one factor: a few ulps), for every mode, on an area-light
 *     scene and a sun scene;
 *   - coverage: on every shipped scene the engine sees a surface exactly
 *     where the ray tracer's camera rays hit one, at the same distance
 *     (METRICS_DEPTH_TOLERANCE), silhouettes aside and counted: a pixel
 *     that disagrees must lie next to a change of the truth's coverage or
 *     a jump of its distance;
 *   - on parallel_planes, three's BasicShadowMap, Babylon's unfiltered
 *     map and PlayCanvas's PCF1 are a hard edge within a texel of
 *     shadowbench's own `hard`: row by row, their edges' world positions
 *     on the receiver differ by at most one shadow-map texel there, plus
 *     the pixel each is found to (the coverage and edge checks take each
 *     engine's one-comparison mode). PlayCanvas's PCF1 is one hardware
 *     compare of a linearly filtered map, a bilinear 2 x 2: across a
 *     straight edge its 0.5 crossing is the nearest compare's step (the
 *     midpoint between the two texel centres either side), so the same
 *     bound holds. The bound stays shadowbench's texel (the test's 1024
 *     map at the fitted far plane) although PlayCanvas's symmetric cone
 *     makes its texels 1.4 to 2.0 times as wide here
 *     (docs/engines.md): the test then says that the coarser map moves no
 *     edge by more than a texel and a pixel of shadowbench's.
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
#include <unistd.h>

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

/* Every mode: shadow == lit / unlit on lit pixels. */
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
        if (!technique_is_engine(*t))
            continue;
        /* a normal bias against acne where the mode has one (PlayCanvas ignores it for VSM, so its
         * playcanvas_vsm has none) */
        void *settings = settings_of(*t, params_find(*t, "normal_bias") ? "normal_bias=0.02" : NULL);
        struct engine_result e = {0};
        memcpy(e.image, img, sizeof img);
        const int rc = engine_render(&(struct engine_request){.t = *t, .settings = settings, .scene = &s,
                                                              .frustum = &ss.cascades.map[0].frustum,
                                                              .label = (*t)->name, .width = W, .height = H,
                                                              .map_size = 1024, .frames = 1,
                                                              .outputs = (1u << ENGINE_OUTPUT_COUNT) - 1},
                                     &e);
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

/* Whether pixel i of the truth lies on a silhouette: a neighbour's ray
 * hits nothing where it hits, or hits at a distance more than 2 % off. */
static bool silhouette(const float *d, int x, int y)
{
    const float c = d[y * W + x];
    for (int dy = -1; dy <= 1; dy++)
        for (int dx = -1; dx <= 1; dx++) {
            const int u = x + dx, v = y + dy;
            if (u < 0 || v < 0 || u >= W || v >= H)
                continue;
            const float e = d[v * W + u];
            if ((e < 0) != (c < 0) || (c >= 0 && fabsf(e - c) > 0.02f * c))
                return true;
        }
    return false;
}

static void coverage_matches_truth(const char *technique)
{
    char **paths = NULL;
    const int count = catalog_shipped(&paths);
    CHECK(count > 10, "the shipped scenes");
    const struct technique *t = technique_find(technique);
    void *settings = settings_of(t, NULL);
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
            long hits = 0, edge = 0, inner = 0;
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    const size_t i = (size_t)y * W + x;
                    const float g = ss.gt.distance[i], e = ss.distance[i];
                    hits += g >= 0;
                    const bool agree = (g >= 0) == (e >= 0) &&
                                       (g < 0 || fabsf(e - g) <= METRICS_DEPTH_TOLERANCE * g);
                    if (!agree)
                        silhouette(ss.gt.distance, x, y) ? edge++ : inner++;
                    if (!agree && getenv("SB_TEST_VERBOSE") && !silhouette(ss.gt.distance, x, y) && inner < 5)
                        printf("  %s (%d, %d): truth %.6g, engine %.6g\n", s.name, x, y, g, e);
                }
            CHECK(inner == 0, "%s: %ld pixels off the silhouettes disagree with the truth's camera rays", s.name,
                  inner);
            /* at most 1 % of the hits (seen: 13 of 5878 on thin_features), or the silhouette rule hides a shift */
            CHECK(edge * 100 <= hits, "%s, %s: %ld silhouette pixels disagree, over 1 %% of %ld", technique, s.name,
                  edge, hits);
            CHECK(m.mismatch_pixels == edge + inner, "%s: the metrics count %ld mismatches, the test %ld", s.name,
                  m.mismatch_pixels, edge + inner);
            printf("%s, %s: coverage: %ld of %ld hit pixels, %ld silhouette pixels disagree\n", technique, s.name, hits,
                   (long)W * H, edge);
        }
        scene_setup_free(&ss), scene_free(&s);
    }
    free(settings);
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

static void basic_is_hard(const char *technique)
{
    struct scene s = {0};
    struct scene_setup ss = {0};
    if (open_scene(&s, &ss, "parallel_planes") != 0) {
        CHECK(false, "parallel_planes: set-up");
        scene_setup_free(&ss), scene_free(&s);
        return;
    }
    const struct technique *hard = technique_find("hard"), *basic = technique_find(technique);
    void *hs = settings_of(hard, NULL), *bs = settings_of(basic, "normal_bias=0.02");
    const size_t n = (size_t)W * H;
    float *v_hard = xmalloc(sizeof(float) * n);
    struct metrics m;
    int rows = 0;
    double worst = 0;
    if (scene_setup_cell(&ss, hard, hs, &m) == 0) {
        memcpy(v_hard, ss.v, sizeof(float) * n);
        if (scene_setup_cell(&ss, basic, bs, &m) == 0) {
            const struct light_frustum *f = &ss.cascades.map[0].frustum;
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
                CHECK(gap <= texel + pixel, "row %d: %s's edge %.4g from hard's, more than a texel (%.4g) and a pixel "
                      "(%.4g)", y, technique, gap, texel, pixel);
            }
        }
    }
    CHECK(rows > H / 2, "parallel_planes: %d rows with an edge in both", rows);
    printf("parallel_planes: %s's edge vs hard's over %d rows: at most %.3f of (a texel + a pixel)\n", technique,
           rows, worst);
    free(v_hard), free(hs), free(bs);
    scene_setup_free(&ss), scene_free(&s);
}

int main(void)
{
    bool installed = access("/usr/bin/chromium", X_OK) == 0;
    for (const struct technique *const *t = technique_list; *t; t++)  /* every engine's packages */
        if (technique_is_engine(*t)) {
            char *lock = util_printf("%s/engines/%s/node_modules/.package-lock.json", SB_SOURCE_DIR, (*t)->engine);
            installed = installed && util_file_exists(lock);
            free(lock);
        }
    if (!installed) {
        printf("skipped: the engines are not installed (tools/setup installs them)\n");
        return 77;
    }
    char *shaders = util_printf("%s/shaders", SB_SOURCE_DIR);
    if (gl_context_create(GL_BACKEND_OSMESA) != 0 || shader_init(shaders) != 0) {
        CHECK(false, "set-up");
        return check_finish();
    }
    shadow_term_is_the_ratio("overlapping_occluders");
    shadow_term_is_the_ratio("sun_contact");
    /* each engine's one-comparison mode: its camera, and its light's frustum against shadowbench's */
    const char *const basic[] = {"three_basic", "babylon_hard", "playcanvas_pcf1"};
    for (size_t i = 0; i < sizeof basic / sizeof *basic; i++) {
        coverage_matches_truth(basic[i]);
        basic_is_hard(basic[i]);
    }
    programs_free(&programs);
    engine_shutdown();
    gl_context_destroy();
    gt_shutdown();
    free(shaders);  /* shader_init keeps it */
    return check_finish();
}
