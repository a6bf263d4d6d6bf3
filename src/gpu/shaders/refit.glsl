// One thread per leaf: its box is the min/max of its slots (contiguous). Leaf ranges:
// (first slot, end slot, mesh) per leaf.
layout(std430, binding = 7) readonly buffer LeafRange { uint leaf_range[]; };
layout(std430, binding = 9) writeonly buffer Boxes { float boxes[]; };
void main() {
    uint l = thread_index();
    if (l >= u_count) return;
    vec3 lo = vec3(uintBitsToFloat(0x7f800000u));
    vec3 hi = -lo;
    for (uint i = leaf_range[3u * l]; i < leaf_range[3u * l + 1u]; i++) {
        vec3 p = vertex_f(i);
        lo = min(lo, p);
        hi = max(hi, p);
    }
    for (int k = 0; k < 3; k++) {
        boxes[6u * l + uint(k)] = lo[k];
        boxes[6u * l + 3u + uint(k)] = hi[k];
    }
}
