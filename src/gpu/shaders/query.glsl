// The whole query on the GPU (GL_COMPUTE): steps 1 to 5 as five dispatches that read each
// other's output, sized on the GPU (indirect dispatch), so the CPU reads one buffer once,
// at the end. Compiled once per kernel with KERNEL defined (1: refit + reference root,
// 2: step 1, 3: dispatch sizes, 4: step 2, 5: steps 3 and 4, 6: step 5).
//
// Result buffer (binding 5): a 64-word header, then the step-5 hits as (reference polygon,
// other polygon) global ids. Every counter keeps counting past its capacity (writes past it
// are dropped), so the CPU sees how much room a complete answer needs.
layout(std430, binding = 5) coherent buffer Result {
    uint h_nonfinite;   // 0: a leaf box of a buffer-bound mesh is not finite
    uint h_l1;          // 1: step-1 hits (other leaves in the reference root)
    uint h_pairs;       // 2: step-2 hits (leaf pairs)
    uint h_list;        // 3: list words allocated for steps 3 and 4
    uint h_hits;        // 4: step-5 hits
    uint h_tests3;      // 5: step-3 tests
    uint h_tests4;      // 6: step-4 tests
    uint h_hits3;       // 7: step-3 hits
    uint h_hits4;       // 8: step-4 hits
    uint h_tests5_lo;   // 9, 10: step-5 tests (64 bits)
    uint h_tests5_hi;
    uint h_pad0;        // 11
    uint h_root[6];     // 12..17: reference root, order-preserving keys (min xyz, max xyz)
    uint h_pad1[6];     // 18..23
    uint h_args[8];     // 24..31: indirect dispatch sizes (x, y, z, -) for steps 2 and 3-5
    uint h_pad2[32];    // 32..63
    uint out_hits[];
};
layout(std430, binding = 9) buffer Boxes { float boxes[]; };
// Per global leaf: first and end global polygon.
layout(std430, binding = 10) readonly buffer LeafPolys { uint leaf_polys[]; };

uniform uint u_ref_leaf_base;
uniform uint u_ref_leaves;
uniform uint u_l1_cap;
uniform uint u_pair_cap;
uniform uint u_list_cap;
uniform uint u_hit_cap;

// Float <-> uint keys whose unsigned order is the float order (for atomicMin/atomicMax).
uint key(float f) {
    uint b = floatBitsToUint(f);
    return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}
float unkey(uint k) {
    return uintBitsToFloat((k & 0x80000000u) != 0u ? (k & 0x7fffffffu) : ~k);
}

void leaf_box(uint l, out vec3 lo, out vec3 hi) {
    lo = vec3(boxes[6u * l], boxes[6u * l + 1u], boxes[6u * l + 2u]);
    hi = vec3(boxes[6u * l + 3u], boxes[6u * l + 4u], boxes[6u * l + 5u]);
}

// The work item of a workgroup-per-item dispatch (2D grid of workgroups).
uint item_index() {
    return gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
}

#if KERNEL == 1
// One thread per leaf of every mesh: its box is the min/max of its slots (contiguous); the
// reference's leaves also grow the reference root. A non-finite box raises h_nonfinite.
layout(std430, binding = 7) readonly buffer LeafRange { uint leaf_range[]; };
void main() {
    uint l = thread_index();
    if (l >= u_count) return;
    vec3 lo = vec3(uintBitsToFloat(0x7f800000u));
    vec3 hi = -lo;
    bool finite = true;
    for (uint i = leaf_range[2u * l]; i < leaf_range[2u * l + 1u]; i++) {
        vec3 p = vertex_f(i);
        // On the bits: min/max would hide a NaN, and compilers may assume there is none.
        uvec3 e = floatBitsToUint(p) & 0x7f800000u;
        finite = finite && all(notEqual(e, uvec3(0x7f800000u)));
        lo = min(lo, p);
        hi = max(hi, p);
    }
    for (int k = 0; k < 3; k++) {
        boxes[6u * l + uint(k)] = lo[k];
        boxes[6u * l + 3u + uint(k)] = hi[k];
    }
    if (!finite) atomicOr(h_nonfinite, 1u);
    if (l >= u_ref_leaf_base && l - u_ref_leaf_base < u_ref_leaves && finite) {
        for (int k = 0; k < 3; k++) {
            atomicMin(h_root[k], key(lo[k]));
            atomicMax(h_root[3 + k], key(hi[k]));
        }
    }
}
#endif

#if KERNEL == 2
// Step 1: one thread per leaf of the other meshes: is it in the reference root?
// Others: per other mesh (first global leaf, leaves, first thread).
layout(std430, binding = 11) readonly buffer Others { uint others[]; };
layout(std430, binding = 2) writeonly buffer L1 { uint l1[]; };
uniform uint u_others;
void main() {
    uint t = thread_index();
    if (t >= u_count) return;
    uint lo = 0u, hi = u_others;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (others[3u * mid + 2u] <= t) lo = mid; else hi = mid;
    }
    uint leaf = others[3u * lo] + (t - others[3u * lo + 2u]);
    vec3 rlo, rhi, clo, chi;
    for (int k = 0; k < 3; k++) {
        rlo[k] = unkey(h_root[k]);
        rhi[k] = unkey(h_root[3 + k]);
    }
    leaf_box(leaf, clo, chi);
    if (boxes_meet(rlo, rhi, clo, chi)) {
        uint k = atomicAdd(h_l1, 1u);
        if (k < u_l1_cap) l1[k] = leaf;
    }
}
#endif

#if KERNEL == 3
// One thread: the workgroup grid for one workgroup per item (u_src: 0 the step-1 hits, 1
// the leaf pairs), at most 65535 workgroups a side.
uniform uint u_src;
void main() {
    if (thread_index() != 0u) return;
    uint n = u_src == 0u ? min(h_l1, u_l1_cap) : min(h_pairs, u_pair_cap);
    uint x = min(n, 65535u);
    uint y = x == 0u ? 1u : (n + x - 1u) / x;
    uint at = u_src == 0u ? 0u : 4u;
    h_args[at] = x;
    h_args[at + 1u] = y;
    h_args[at + 2u] = 1u;
}
#endif

#if KERNEL >= 4
// A leaf pair: other leaf, reference leaf, list offset, then the counts of steps 3 and 4.
layout(std430, binding = 3) coherent buffer Pairs { uint pairs[]; };
layout(std430, binding = 4) coherent buffer Lists { uint lists[]; };
#endif

#if KERNEL == 4
// Step 2: one workgroup per step-1 hit B; its threads walk the reference's leaves R and
// append every (B, R) whose boxes meet, with room for its step-3 and step-4 lists.
layout(std430, binding = 2) readonly buffer L1 { uint l1[]; };
void main() {
    uint item = item_index();
    if (item >= min(h_l1, u_l1_cap)) return;
    uint b = l1[item];
    vec3 blo, bhi;
    leaf_box(b, blo, bhi);
    uint nb = leaf_polys[2u * b + 1u] - leaf_polys[2u * b];
    for (uint j = gl_LocalInvocationID.x; j < u_ref_leaves; j += gl_WorkGroupSize.x) {
        uint r = u_ref_leaf_base + j;
        vec3 rlo, rhi;
        leaf_box(r, rlo, rhi);
        if (!boxes_meet(blo, bhi, rlo, rhi)) continue;
        uint k = atomicAdd(h_pairs, 1u);
        uint nr = leaf_polys[2u * r + 1u] - leaf_polys[2u * r];
        uint off = atomicAdd(h_list, nr + nb);
        if (k < u_pair_cap) {
            pairs[6u * k] = b;
            pairs[6u * k + 1u] = r;
            pairs[6u * k + 2u] = off;
            pairs[6u * k + 3u] = 0u;
            pairs[6u * k + 4u] = 0u;
            pairs[6u * k + 5u] = 0u;
        }
    }
}
#endif

#if KERNEL == 5
// Steps 3 and 4, one workgroup per leaf pair (B, R): R's polygons inside B's box go to the
// pair's first list, B's polygons inside R's box to its second (which starts after room
// for all of R's polygons).
void main() {
    uint k = item_index();
    if (k >= min(h_pairs, u_pair_cap)) return;
    uint b = pairs[6u * k], r = pairs[6u * k + 1u], off = pairs[6u * k + 2u];
    uint r0 = leaf_polys[2u * r], nr = leaf_polys[2u * r + 1u] - r0;
    uint b0 = leaf_polys[2u * b], nb = leaf_polys[2u * b + 1u] - b0;
    bool room = off + nr + nb <= u_list_cap;
    if (gl_LocalInvocationID.x == 0u) {
        atomicAdd(h_tests3, nr);
        atomicAdd(h_tests4, nb);
    }
    vec3 blo, bhi, rlo, rhi;
    leaf_box(b, blo, bhi);
    leaf_box(r, rlo, rhi);
    for (uint i = gl_LocalInvocationID.x; i < nr + nb; i += gl_WorkGroupSize.x) {
        bool step3 = i < nr;
        uint p = step3 ? r0 + i : b0 + (i - nr);
        vec3 plo, phi;
        poly_box(p, plo, phi);
        if (step3 ? boxes_meet(blo, bhi, plo, phi) : boxes_meet(rlo, rhi, plo, phi)) {
            uint at = atomicAdd(pairs[6u * k + (step3 ? 3u : 4u)], 1u);
            if (step3) atomicAdd(h_hits3, 1u); else atomicAdd(h_hits4, 1u);
            if (room) lists[off + (step3 ? 0u : nr) + at] = p;
        }
    }
}
#endif

#if KERNEL == 6
// Step 5, one workgroup per leaf pair: each reference polygon of its first list is a
// viewing volume (section 2.3), each polygon of its second list a candidate.
void main() {
    uint k = item_index();
    if (k >= min(h_pairs, u_pair_cap)) return;
    uint r = pairs[6u * k + 1u], off = pairs[6u * k + 2u];
    uint nr = leaf_polys[2u * r + 1u] - leaf_polys[2u * r];
    uint n3 = pairs[6u * k + 3u], n4 = pairs[6u * k + 4u];
    uint b = pairs[6u * k];
    uint nb = leaf_polys[2u * b + 1u] - leaf_polys[2u * b];
    if (off + nr + nb > u_list_cap) return;
    uint n = n3 * n4;
    if (gl_LocalInvocationID.x == 0u && n > 0u) {
        uint old = atomicAdd(h_tests5_lo, n);
        if (old + n < old) atomicAdd(h_tests5_hi, 1u);
    }
    for (uint t = gl_LocalInvocationID.x; t < n; t += gl_WorkGroupSize.x) {
        uint rp = lists[off + t / n4];
        uint cp = lists[off + nr + t % n4];
        if (polygon_meets(rp, cp)) {
            uint at = atomicAdd(h_hits, 1u);
            if (at < u_hit_cap) {
                out_hits[2u * at] = rp;
                out_hits[2u * at + 1u] = cp;
            }
        }
    }
}
#endif
