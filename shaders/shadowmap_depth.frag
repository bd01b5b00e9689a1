#version 450 core
// Depth only: the rasteriser writes gl_FragCoord.z to the D32F attachment.
void main() {}
