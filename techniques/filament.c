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
 * The spot light's map (filament/src/ShadowMap.cpp, updateSpot and
 * updatePunctual): a perspective map around the cone, field of view twice
 * the outer cone angle, near 0.01, far the light's falloff radius. So the
 * one parameter that reaches it:
 *   falloff  LightManager::Builder::falloff, world units: the spot's
 *            falloff radius, which is also its map's far plane (its depth
 *            precision); 0: the fitted frustum's farthest corner, a little
 *            beyond (the least that lights every scored point). No effect on
 *            the sun. The light's attenuation it also sets cancels in the
 *            shadow factor (lit / unlit). */
#include "param_rows.h"

struct filament_pcf_settings {
    float falloff;  /* world units; 0: derived */
};

static const struct technique_param filament_pcf_params[] = {
    {"falloff", "LightManager falloff radius of the spot, world units: its map's far plane; 0: the fitted "
     "frustum's farthest corner", offsetof(struct filament_pcf_settings, falloff), PARAM_FLOAT, 0.0, 0.0, 1000.0,
     NULL, NULL},
    {NULL},
};

/* The falloff away from its default where it acts: a spot scene. */
static const struct technique_cell filament_pcf_cells[] = {
    {"contact_hardening", {"falloff=50"}},
    {NULL},
};

ENGINE_TECHNIQUE(filament_pcf, filament, "filament", .regression = filament_pcf_cells,
                 .summary = "Filament ShadowType::PCF at its default ShadowOptions (all its JS bindings reach)");
