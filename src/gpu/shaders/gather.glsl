// Copies a mesh's positions from the host's buffer (any offset/stride) into the arena's
// slots (a vertex used by several leaves has a slot in each; slot_vertex maps them back).
layout(std430, binding = 6) readonly buffer Src { float src[]; };
layout(std430, binding = 8) readonly buffer SlotVertex { uint slot_vertex[]; };
uniform uint u_src_offset; // in floats
uniform uint u_src_stride; // in floats
uniform uint u_dst_vertex;
void main() {
    uint i = thread_index();
    if (i >= u_count) return;
    uint s = u_src_offset + slot_vertex[u_dst_vertex + i] * u_src_stride;
    uint d = 3u * (u_dst_vertex + i);
    pos[d] = src[s];
    pos[d + 1u] = src[s + 1u];
    pos[d + 2u] = src[s + 2u];
}
