#version 450 core
// One triangle covering the viewport, from gl_VertexID alone: the image
// passes of the moments product (a fragment pass writes through the
// rasteriser's tiled path, which on llvmpipe beat imageStore from compute).
void main()
{
    vec2 p = vec2(float((gl_VertexID & 1) << 2) - 1.0, float((gl_VertexID & 2) << 1) - 1.0);
    gl_Position = vec4(p, 0.0, 1.0);
}
