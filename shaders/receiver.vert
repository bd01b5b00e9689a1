#version 450 core
// Receiver pass: the scene from the camera.
layout(location = SM_ATTRIB_POSITION) in vec3 a_position;
layout(location = SM_ATTRIB_NORMAL) in vec3 a_normal;

uniform mat4 u_camera_view_proj;

out vec3 v_pos_world;
out vec3 v_normal_world;

void main()
{
    v_pos_world = a_position;
    v_normal_world = a_normal;
    gl_Position = u_camera_view_proj * vec4(a_position, 1.0);
}
