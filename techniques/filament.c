/* Filament's shadow maps as they ship (npm filament 1.53.4, its WebAssembly
 * build), rendered by Filament itself in headless Chromium
 * (engines/filament/adapter.js; docs/engines.md).
 *
 * One mode: what Filament's JavaScript bindings can ask for. They bind
 * neither View::setShadowType nor View::setSoftShadowOptions nor
 * View::setVsmShadowOptions (the TypeScript declarations list them; the
 * wasm of 1.53.4, 1.53.1 and 1.44.0 registers none of them), and
 * LightManager::ShadowOptions cannot be passed at all: Builder.shadowOptions
 * and LightManager.setShadowOptions throw embind's UnboundTypeError (a
 * field's type is not registered). So the shadow type is the default, PCF,
 * and the options are Filament's defaults (include/filament/LightManager.h):
 * mapSize 1024 whatever --shadow-map-size says, constantBias 0.001 (world
 * units towards the light), normalBias 1 (times the texel size at the
 * receiver), polygonOffsetConstant 0.5 and polygonOffsetSlope 2 in the map,
 * one cascade, LiSPSM on for the sun, no stable fit. DPCF, PCSS and VSM
 * (filament_dpcf, filament_pcss, filament_vsm) are not cells: no page can
 * select them.
 *
 * What PCF does (shaders/src/shadowing.fs, as Filament compiles it here:
 * docs/engines.md): the receiver moved along its normal by normalBias
 * times the texel size at it, then 4 bilinear hardware-compare taps
 * weighted as Castaño's 3 x 3 tent (ShadowSample_PCF_Low), which reads 4 x 4
 * texels: the edge is blurred over 2 texels on either side.
 *
 * The one set-up choice a Filament user makes that reaches the shadow, as
 * three's and Babylon's cells have it:
 *   shadow_side  double: every material instance double-sided and not
 *                culled, so both faces are drawn into the map (and lit
 *                from either side), shadowbench's own choice; engine:
 *                gltfio's default for the file's material (glTF's default
 *                material is single-sided: back faces culled, in the map
 *                too): a closed mesh's faces turned from the light leave
 *                the map, and the front faces' depths decide. */
#include "param_rows.h"

static const char *const filament_sides[] = {"double", "engine", NULL};

struct filament_pcf_settings {
    int shadow_side;  /* index into filament_sides */
};

static const struct technique_param filament_pcf_params[] = {
    {"shadow_side", "faces drawn: double (both, shadowbench's choice) or engine (gltfio's culling of the file's "
     "single-sided material, in the map too)", offsetof(struct filament_pcf_settings, shadow_side), PARAM_ENUM, 0,
     0, 0, filament_sides, NULL},
    {NULL},
};

/* The faces away from their default where they act: closed meshes, whose back faces then leave the map (no
 * change on thin_features: its plate faces the light). */
static const struct technique_cell filament_pcf_cells[] = {
    {"curved_receivers", {"shadow_side=engine"}},
    {NULL},
};

ENGINE_TECHNIQUE(filament_pcf, filament, "filament", .regression = filament_pcf_cells,
                 .summary = "Filament ShadowType::PCF at its default ShadowOptions (all its JS bindings reach)");
