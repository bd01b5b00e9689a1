#version 450 core
// The penumbra mask's dilation: a block keeps its lit or umbra class only
// when every block within u_radius blocks (a square) has the same class;
// any other block is penumbra (0.5). Conservative: it widens the region
// that runs the full filter, never narrows it. One layer of the mask.
layout(binding = SM_BINDING_PASS_SOURCE) uniform sampler2DArray source;  // the pre-pass's classes
uniform int u_layer;
uniform int u_radius;  // blocks

layout(location = 0) out float out_class;

void main()
{
    ivec2 p = ivec2(gl_FragCoord.xy), last = textureSize(source, 0).xy - 1;
    float c = texelFetch(source, ivec3(p, u_layer), 0).r;
    for (int dy = -u_radius; dy <= u_radius && c != 0.5; dy++)
        for (int dx = -u_radius; dx <= u_radius; dx++)
            if (texelFetch(source, ivec3(clamp(p + ivec2(dx, dy), ivec2(0), last), u_layer), 0).r != c) {
                c = 0.5;
                break;
            }
    out_class = c;
}
