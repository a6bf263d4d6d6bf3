#version 430
// Shared by the GL_COMPUTE shaders. Positions: xyz floats per vertex, all meshes in one
// arena. Polygons: 4 global vertex ids each (the 4th is 0xffffffff for a triangle).
layout(local_size_x = 64) in;
layout(std430, binding = 0) buffer Pos { float pos[]; };
layout(std430, binding = 1) readonly buffer Polys { uint polys[]; };
uniform uint u_count;

uint thread_index() {
    return gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x + gl_GlobalInvocationID.x;
}
vec3 vertex_f(uint v) { return vec3(pos[3u * v], pos[3u * v + 1u], pos[3u * v + 2u]); }
