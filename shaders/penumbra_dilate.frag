#version 450 core
// The penumbra mask's dilation: a block keeps its lit or umbra class only
// when every block within its radius (a square) has the same class; any
// other block is penumbra (0.5). Conservative: it widens the region that
// runs the full filter, never narrows it. One layer of the mask.
//
// The radius is u_radius blocks, or with u_radius_world > 0 that world
// radius in blocks at the block's view depth d (a block spans
// d * u_block_angle), if more, up to MASK_MAX_DILATE_BLOCKS: seed 003's
// distance-dependent radius, which keeps the margin a world width as the
// camera nears a penumbra (a fixed count of blocks shrinks with it).
layout(binding = SM_BINDING_PASS_SOURCE) uniform sampler2DArray source;  // the pre-pass's classes, distances
uniform int u_layer;
uniform int u_radius;          // blocks
uniform float u_radius_world;  // world units; 0: off
uniform float u_block_angle;   // a block's side at view depth 1

layout(location = 0) out float out_class;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(source, 0).xy - 1;
    vec2 own = texelFetch(source, ivec3(p, u_layer), 0).rg;
    float c = own.r;
    int radius = u_radius;
    if (u_radius_world > 0.0 && own.g > 0.0)  // no geometry (depth 0): penumbra already
        radius = max(radius, int(min(ceil(u_radius_world / (own.g * u_block_angle)), float(MASK_MAX_DILATE_BLOCKS))));
    for (int dy = -radius; dy <= radius && c != 0.5; dy++)
        for (int dx = -radius; dx <= radius; dx++)
            if (texelFetch(source, ivec3(clamp(p + ivec2(dx, dy), ivec2(0), last), u_layer), 0).r != c) {
                c = 0.5;
                break;
            }
    out_class = c;
}
