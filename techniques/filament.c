/* Filament's shadow maps as they ship (npm filament 1.53.4, its WebAssembly
 * build), rendered by Filament itself in headless Chromium
 * (engines/filament/adapter.js; docs/engines.md).
 *
 * One mode: the shadow type Filament's JavaScript bindings can ask for.
 * They bind neither View::setShadowType nor View::setSoftShadowOptions nor
 * View::setVsmShadowOptions (the TypeScript declarations list them; the
 * wasm of no npm release, 1.4.5 to 1.53.4, registers them), so the type is
 * the default, PCF, and DPCF, PCSS and VSM (filament_dpcf, filament_pcss,
 * filament_vsm) are not cells. The light's LightManager::ShadowOptions are
 * bound but cannot be passed as 1.53.4 ships (one field's type, a float
 * quaternion, is never registered); the adapter supplies that one binding
 * type (docs/engines.md, "ShadowOptions"), and the options are this mode's
 * parameters, under Filament's names, at Filament's defaults
 * (include/filament/LightManager.h, struct ShadowOptions; passed as they
 * are, every pixel is as with no ShadowOptions at all).
 *
 * What PCF does (shaders/src/shadowing.fs, as Filament compiles it here:
 * docs/engines.md): the receiver moved along its normal by normalBias
 * times the texel size at it, then 4 bilinear hardware-compare taps
 * weighted as Castaño's 3 x 3 tent (ShadowSample_PCF_Low), which reads 4 x 4
 * texels: the edge is blurred over 2 texels on either side. The map is
 * DEPTH16 (Filament's format for PCF), drawn with glPolygonOffset, its
 * depths moved away from the light by constantBias.
 *
 * Parameters (each measured to act where it is said to: docs/engines.md):
 *   constant_bias            constantBias: the map's depths moved away from
 *                            the light, world units. On a spot map, whose
 *                            near plane Filament puts at 0.01, a 16-bit
 *                            depth step is a few centimetres at a few
 *                            metres, so small values change nothing there.
 *   normal_bias              normalBias: the receiver moved along its
 *                            normal by this times the map's texel size at
 *                            it, scaled by sin(N, L). The spot's only: on
 *                            the sun no value changes a pixel (measured;
 *                            as read, Filament takes the sun's from light
 *                            component 0, not the light's own).
 *   polygon_offset_constant  polygonOffsetConstant, polygon_offset_slope
 *   polygon_offset_slope     polygonOffsetSlope: glPolygonOffset's units and
 *                            factor when the map is drawn (depth-resolution
 *                            steps; slope: times the depth slope).
 *   map_size                 mapSize, texels a side; 0: the run's
 *                            --shadow-map-size, so that the cells compare
 *                            with shadowbench's own at one resolution.
 *                            Filament clamps it to [8, 2048] (a run's 4096
 *                            is drawn at 2048), takes any size in between
 *                            as it is (no power of two), and draws into
 *                            all but a 1-texel border.
 *   lispsm                   lispsm: the sun's map warped by light-space
 *                            perspective towards the camera (the sun only).
 *                            On by default, as Filament ships: the sun's
 *                            cell is one warped map over the view, not
 *                            shadowbench's one orthographic map.
 *   stable                   stable: the sun's map fitted to a bounding
 *                            sphere and snapped to whole texels, LiSPSM
 *                            off (the sun only).
 *   shadow_side              double: every material instance double-sided
 *                            and not culled, so both faces are drawn into
 *                            the map (and lit from either side),
 *                            shadowbench's own choice; engine: gltfio's
 *                            default for the file's material (glTF's
 *                            default material is single-sided: back faces
 *                            culled, in the map too): a closed mesh's faces
 *                            turned from the light leave the map, and the
 *                            front faces' depths decide.
 * The other fields stay at Filament's defaults: one cascade, the camera's
 * far plane as shadowFar, LiSPSM's near and far hints (which a spot's map
 * ignores: its near plane is 0.01, its far the light's falloff), no
 * screen-space contact shadows. */
#include "param_rows.h"

#include <stdio.h>

/* Filament's own limits on ShadowOptions::mapSize (LightManager::setShadowOptions). */
#define FILAMENT_MAP_SIZE_MIN 8
#define FILAMENT_MAP_SIZE_MAX 2048

struct filament_pcf_settings {
    float constant_bias;            /* world units, [0, 2] (Filament's clamp) */
    float normal_bias;              /* texels at the receiver, [0, 3] (Filament's clamp) */
    float polygon_offset_constant;  /* depth-resolution steps */
    float polygon_offset_slope;     /* times the depth slope */
    int map_size;                   /* texels a side; 0: the run's */
    int lispsm, stable;             /* bool */
    int shadow_side;                /* index into filament_sides */
};

static const struct technique_param filament_pcf_params[] = {
    {"constant_bias", "ShadowOptions.constantBias: the map's depths moved away from the light, world units",
     offsetof(struct filament_pcf_settings, constant_bias), PARAM_FLOAT, 0.001, 0.0, 2.0, NULL,
     TUNE(0.0, 0.001, 0.003, 0.01, 0.03, 0.1)},
    {"normal_bias", "ShadowOptions.normalBias: the receiver moved along its normal, texels of the map at it "
     "(the spot only)", offsetof(struct filament_pcf_settings, normal_bias), PARAM_FLOAT, 1.0, 0.0, 3.0, NULL,
     TUNE(0.0, 0.5, 1.0, 2.0, 3.0)},
    {"polygon_offset_constant", "ShadowOptions.polygonOffsetConstant: glPolygonOffset units in the map, "
     "depth-resolution steps", offsetof(struct filament_pcf_settings, polygon_offset_constant), PARAM_FLOAT, 0.5,
     0.0, 64.0, NULL, TUNE(0.0, 0.5, 1.0, 2.0, 4.0)},
    {"polygon_offset_slope", "ShadowOptions.polygonOffsetSlope: glPolygonOffset factor in the map, times the "
     "depth slope", offsetof(struct filament_pcf_settings, polygon_offset_slope), PARAM_FLOAT, 2.0, 0.0, 64.0,
     NULL, TUNE(0.0, 1.0, 2.0, 4.0, 8.0)},
    PARAM_ROW_ENGINE_MAP_SIZE(struct filament_pcf_settings, "ShadowOptions.mapSize (at most "
                              UTIL_STR(FILAMENT_MAP_SIZE_MAX) ")", FILAMENT_MAP_SIZE_MAX),
    {"lispsm", "ShadowOptions.lispsm: the sun's map warped by light-space perspective (the sun only)",
     offsetof(struct filament_pcf_settings, lispsm), PARAM_BOOL, 1, 0, 1, NULL, TUNE_CHOICES},
    {"stable", "ShadowOptions.stable: the sun's map fitted to a sphere and snapped to texels, no LiSPSM (the sun "
     "only)", offsetof(struct filament_pcf_settings, stable), PARAM_BOOL, 0, 0, 1, NULL, TUNE_CHOICES},
    PARAM_ROW_ENGINE_SIDE(struct filament_pcf_settings,
                          "gltfio's culling of the file's single-sided material, in the map too"),
    {NULL},
};

/* A map size Filament would change is refused rather than recorded as what it is not. */
static int filament_pcf_check(const void *settings, char *why, size_t why_size)
{
    const struct filament_pcf_settings *s = settings;
    if (s->map_size > 0 && s->map_size < FILAMENT_MAP_SIZE_MIN) {
        snprintf(why, why_size, "map_size %d: Filament raises it to %d texels a side", s->map_size,
                 FILAMENT_MAP_SIZE_MIN);
        return -1;
    }
    return 0;
}

/* Each parameter away from its default where it acts (measured: docs/engines.md): the biases and the map's
 * polygon offset where acne and the spot's 16-bit depth show (grazing_receiver) or the sun's
 * (sun_contact); LiSPSM and the stable fit on the sun; the faces on closed meshes, whose back faces then
 * leave the map (no change on thin_features: its plate faces the light). */
static const struct technique_cell filament_pcf_cells[] = {
    {"grazing_receiver", {"normal_bias=0", "polygon_offset_constant=4", "polygon_offset_slope=0", "map_size=512"}},
    {"sun_contact", {"constant_bias=0.01", "lispsm=false", "stable=true"}},
    {"curved_receivers", {"shadow_side=engine"}},
    {NULL},
};

/* The scored mask's depth tolerance (technique.h). Filament's camera
 * distance is its depth buffer's (engines/filament/readback.js), and
 * SwiftShader draws a triangle clipped at the camera's near plane, much
 * larger than the near distance, with its depth off: the cascade scenes'
 * 120 x 240 ground is 0.35 % short at every pixel at 256 x 256 (the same
 * ground cut where the camera stands, so that no visible triangle is
 * clipped: 0.01 % near the camera), whatever the near distance, and the
 * error moves erratically with the image's height; on top, about 1/50 of a
 * pixel's change of depth everywhere, 0.3 % on average towards the horizon.
 * Measured off the silhouettes (all of a plane's pixels whose neighbours
 * see the same plane) on cascade_distance and sun_parallel_planes at 64
 * image sizes from 16 x 16 to 1024 x 768 (the other cascade scenes, the same
 * ground and camera, at 7 of them: the same): at most 1.62e-2 at every
 * height of 60 pixels or more (6.1e-3 at the runs' 256 x 256, 9.3e-3 at
 * test_engines' 96 x 72), up to 3.3e-2 below (4.7e-2 at 16 x 16), where
 * some of their ground is counted as mismatches. 2e-2 takes them all in;
 * it applies off the truth's silhouettes only (metrics_score_mask), where
 * the harness's METRICS_DEPTH_TOLERANCE stays, so a pixel where Filament may
 * see another surface is never scored (docs/engines.md). */
#define FILAMENT_DEPTH_TOLERANCE 2e-2f

ENGINE_TECHNIQUE(filament_pcf, filament, "filament", .check = filament_pcf_check,
                 .regression = filament_pcf_cells, .depth_tolerance = FILAMENT_DEPTH_TOLERANCE,
                 .summary = "Filament ShadowType::PCF with its LightManager::ShadowOptions");
