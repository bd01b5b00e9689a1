/* Protects the sun's cascaded shadow maps (docs/cascades.md):
 *   - the splits are the closed forms of their schemes, and the zero
 *     settings are the one map over the view, bit for bit;
 *   - the sphere fit's window keeps its size when the camera turns, and a
 *     snapped window starts on a whole texel;
 *   - with `--cascade-width world` a penumbra keeps its world width across
 *     a split (the seam metric within 0.005 of the truth's own, and under
 *     a tenth of texel's), with `texel` it jumps (a seam above 0.05:
 *     measured 0.12);
 *   - under a camera moving a quarter pixel a frame, snapping off flickers
 *     more than twice as much as snapping on (measured 5.0 times).
 *   - bad cascade options get one line and exit 2. */
#include "check.h"
#include "read_json.h"
#include "run_cmd.h"
#include "scene/catalog.h"
#include "scene/light_frustum.h"
#include "scene/pose.h"

#include <math.h>
#include <string.h>

static const char *sb;
static char dir[] = "/tmp/sb_test_cascades_XXXXXX";

static struct scene load(const char *name)
{
    char *path = catalog_resolve(name);
    struct scene s;
    CHECK(path && scene_load(path, &s) == 0, "loading %s", name);
    free(path);
    return s;
}

static void splits(void)
{
    struct scene s = load("cascade_distance");
    const float n = s.camera.znear, far = 100.0f;
    float z[CASCADES_MAX + 1];
    struct cascade_settings cs = {.count = 4, .shadow_distance = far, .split = CASCADE_SPLIT_UNIFORM};
    CHECK(light_frustum_splits(&s, 1.0f, &cs, z) == 4, "uniform splits");
    for (int i = 0; i <= 4; i++)
        CHECK(fabs(z[i] - (n + (far - n) * i / 4.0)) <= 1e-4, "uniform split %d: %g", i, (double)z[i]);
    cs.split = CASCADE_SPLIT_LOG;
    CHECK(light_frustum_splits(&s, 1.0f, &cs, z) == 4, "log splits");
    for (int i = 0; i <= 4; i++)
        CHECK(fabs(z[i] - n * pow(far / n, i / 4.0)) <= 1e-3, "log split %d: %g", i, (double)z[i]);
    cs.split = CASCADE_SPLIT_PRACTICAL, cs.lambda = 0.5f;
    CHECK(light_frustum_splits(&s, 1.0f, &cs, z) == 4, "practical splits");
    for (int i = 1; i < 4; i++)
        CHECK(fabs(z[i] - (0.5 * n * pow(far / n, i / 4.0) + 0.5 * (n + (far - n) * i / 4.0))) <= 1e-3,
              "practical split %d: %g", i, (double)z[i]);
    cs.split = CASCADE_SPLIT_FRACTIONS, cs.fractions[0] = 0.125f, cs.fractions[1] = 0.25f, cs.fractions[2] = 0.5f;
    CHECK(light_frustum_splits(&s, 1.0f, &cs, z) == 4 && z[1] == 12.5f && z[2] == 25.0f && z[3] == 50.0f,
          "Filament's split positions: %g %g %g", (double)z[1], (double)z[2], (double)z[3]);
    cs.fractions[0] = 0.0005f;  /* 5 cm: inside the camera's near plane */
    CHECK(light_frustum_splits(&s, 1.0f, &cs, z) == -1, "a split inside the near plane is refused");

    /* Zero settings: one slice, the whole view, the same map bit for bit. */
    struct cascade_settings zero = {0};
    CHECK(light_frustum_splits(&s, 1.0f, &zero, z) == 1 && z[0] == n && isinf(z[1]), "one slice over the view");
    struct light_frustum a, b;
    CHECK(light_frustum_fit(&s, 1.0f, &a) == 0 && light_frustum_fit_cascade(&s, 1.0f, &zero, z, 0, 1024, &b) == 0 &&
              memcmp(&a, &b, sizeof a) == 0,
          "the zero settings' cascade is light_frustum_fit's map");
    scene_free(&s);
}

static void sphere_fit(void)
{
    struct scene s = load("cascade_shimmer");
    struct cascade_settings cs = {.count = 3, .shadow_distance = 60, .fit = CASCADE_FIT_SPHERE, .snap = 1,
                                  .split = CASCADE_SPLIT_UNIFORM};
    float z[CASCADES_MAX + 1];
    struct light_frustum f0, f1;
    CHECK(light_frustum_splits(&s, 1.0f, &cs, z) == 3 && light_frustum_fit_cascade(&s, 1.0f, &cs, z, 1, 512, &f0) == 0,
          "fitting cascade 1");
    struct scene turned;
    scene_posed(&s, &(struct scene_pose){.camera_yaw_rad = 0.3f}, &turned);
    CHECK(light_frustum_fit_cascade(&turned, 1.0f, &cs, z, 1, 512, &f1) == 0, "fitting it turned");
    CHECK_NEAR(f1.r - f1.l, f0.r - f0.l, 1e-5 * (f0.r - f0.l), "the sphere's window keeps its size as the camera turns");
    CHECK(fabsf(f1.l - f0.l) > 0.1f, "and moves with the view (%g)", (double)(f1.l - f0.l));
    const double texel = (f0.r - f0.l) / 512.0, k = f0.l / texel;
    CHECK_NEAR(k, round(k), 1e-3, "a snapped window starts on a whole texel");
    scene_unpose(&turned, &s);
    scene_free(&s);
}

/* metrics.json's depth.seams[0] of technique t on cascade_seam, three
 * cascades split at 0.11 and 0.3 of the view (22 m: mid-shadow). */
static const cJSON *seam_of(const char *width, cJSON **doc)
{
    char *cmd = util_printf("%s run -q --scene cascade_seam --technique pcss_savsm --settings default --width 256 "
                            "--height 256 --frames 1 --warmup 0 --cascades 3 --cascade-split 0.11,0.3 "
                            "--cascade-width %s --out %s/%s --cache %s/cache",
                            sb, width, dir, width, dir);
    struct strbuf err = {0};
    CHECK(run_cmd(cmd, &err, NULL) == 0, "%s: %s", cmd, err.data);
    strbuf_free(&err);
    free(cmd);
    char *path = util_printf("%s/%s/cascade_seam/pcss_savsm/metrics.json", dir, width);
    *doc = read_json(path);
    free(path);
    const cJSON *seams = cJSON_GetObjectItem(cJSON_GetObjectItem(*doc, "depth"), "seams");
    CHECK(cJSON_GetArraySize(seams) == 2, "two splits, two seams");
    return cJSON_GetArrayItem(seams, 0);
}

static void seam(void)
{
    cJSON *wd, *td;
    const cJSON *w = seam_of("world", &wd), *t = seam_of("texel", &td);
    const double ws = cJSON_GetObjectItem(w, "seam")->valuedouble, wg = cJSON_GetObjectItem(w, "gt_seam")->valuedouble;
    const double ts = cJSON_GetObjectItem(t, "seam")->valuedouble;
    /* 0.005: a sixth of the band's rms error here (0.03). What is left
     * with world widths is resolution, not softness: the far cascade's
     * texels are 2.6 times wider (measured 0.0047 against the truth's
     * 0.0007), under a twentieth of the jump texel widths add */
    printf("seam at 22 m: %.4f with world widths (the truth's %.4f), %.4f with texel widths\n", ws, wg, ts);
    CHECK(fabs(ws - wg) <= 0.005, "world widths: the seam %.4f within 0.005 of the truth's %.4f", ws, wg);
    CHECK(ws < 0.1 * ts, "world widths: the seam %.4f under a tenth of texel widths' %.4f", ws, ts);
    CHECK(ts >= 0.05, "texel widths: the penumbra's width jumps at the split (seam %.4f)", ts);
    cJSON_Delete(wd), cJSON_Delete(td);
}

/* stability.csv's flicker of hard under camera_shift, snapping on or off. */
static double shimmer(const char *snap)
{
    char *out = util_printf("%s/shimmer_%s", dir, snap);
    char *cmd = util_printf("%s stability -q --scene cascade_shimmer --technique hard --motion camera_shift=0.25 "
                            "--frames 6 --width 128 --height 128 --shadow-map-size 256 --cascades 4 --cascade-fit "
                            "sphere --shadow-distance 150 --cascade-snap %s --out %s --cache %s/cache",
                            sb, snap, out, dir);
    struct strbuf err = {0};
    CHECK(run_cmd(cmd, &err, NULL) == 0, "%s: %s", cmd, err.data);
    strbuf_free(&err);
    free(cmd);
    char *path = util_printf("%s/stability.json", out);
    cJSON *j = read_json(path);
    double flicker = NAN;
    const cJSON *row;
    cJSON_ArrayForEach(row, cJSON_GetObjectItem(j, "motions"))
        if (!strcmp(cJSON_GetStringValue(cJSON_GetObjectItem(row, "row")), "hard"))
            flicker = cJSON_GetObjectItem(row, "flicker")->valuedouble;
    cJSON_Delete(j);
    free(path), free(out);
    return flicker;
}

static void snapping(void)
{
    const double off = shimmer("off"), on = shimmer("on");
    printf("shimmer: hard's flicker %.5f with snapping off, %.5f on (%.1fx)\n", off, on, off / on);
    CHECK(off > 2 * on, "snapping off flickers more than twice snapping on: %.5f against %.5f (%.1fx)", off, on,
          off / on);
}

static void bad_options(void)
{
    static const char *const bad[][2] = {
        {"--cascades 9", "--cascades: 9 is out of range"},
        {"--cascade-split practical:2", "practical's lambda is a number in [0, 1]"},
        {"--cascade-split 0.5,0.2", "increasing fractions"},
        {"--cascades 3 --cascade-split 0.5", "1 fractions for 3 cascades"},
        {"--shadow-distance -1", "not a distance > 0"},
        {"--cascade-blend 0.7", "not a fraction of a slice in [0, 0.5]"},
        {"--cascade-fit cube", "--cascade-fit"},
        {"--cascade-snap maybe", "--cascade-snap"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof *bad; i++) {
        char *cmd = util_printf("%s run --scene cascade_seam --out %s/bad %s", sb, dir, bad[i][0]);
        struct strbuf err = {0};
        const int rc = run_cmd(cmd, &err, NULL);
        CHECK(rc == 2 && strstr(err.data, bad[i][1]) && strchr(err.data, '\n') == err.data + err.len - 1,
              "%s: exit %d, one line naming '%s': %s", bad[i][0], rc, bad[i][1], err.data);
        strbuf_free(&err);
        free(cmd);
    }
}

TEST_MAIN(dir, splits, sphere_fit, seam, snapping, bad_options)
