// The shadow-map layer's uniform block. Mirrored by struct shadowmap_block
// in techniques/shadowmap.h: keep in sync (std140). SM_BINDING_*, the
// SAT slots and the enums' values (SM_LIGHT_*, SM_SAT_*) are #defines the
// layer prepends from C (shadowmap_shader_defines).

// A summed-area table's fields, one slot per SAT product (SM_SAT_SLOT_<ID>):
// struct shadowmap_sat_block.
struct SmSatTable {
    int format;            // SM_SAT_* of the table
    float scale;           // SM_SAT_INT32: fixed-point units per 1.0 of depth
    float max_box_texels;  // SM_SAT_INT32: boxes are capped at this side (no overflow)
};

layout(std140, binding = SM_BINDING_BLOCK) uniform ShadowMapBlock {
    mat4 light_view_proj;     // world -> light clip, reversed Z in [0, 1]
    mat4 light_view;          // world -> light space (light looks along -Z)
    vec4 light_pos_world;     // w 1: xyz the area light's centre; w 0: xyz the direction to the sun
    vec4 light_dir_world;     // xyz: emit direction
    vec2 light_size_uv;       // light size in shadow-map UV at the near plane (the sun's: per world unit of depth)
    vec2 texel_size_uv;       // 1 / map size
    vec2 near_window_world;   // frustum window at the near plane (world units; the sun's at every depth)
    float near_world;         // planar depth range of the geometry (world units)
    float far_world;
    float map_size_texels;
    SmSatTable sat[SM_SAT_TABLES];
} sm;
