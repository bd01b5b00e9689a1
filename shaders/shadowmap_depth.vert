#version 450 core
// Depth product: the scene from the light centre (docs/design.md §5).
#include "shadow_block.glsl"

layout(location = SM_ATTRIB_POSITION) in vec3 a_position;

void main()
{
    gl_Position = sm.light_view_proj * vec4(a_position, 1.0);
}
