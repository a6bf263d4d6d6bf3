// The whole query on the GPU (GL_COMPUTE): steps 1 to 5 as dispatches that read each
// other's output, one thread per test, sized on the GPU (scans over the leaf pairs and
// indirect dispatch), so the CPU reads one buffer once, at the end. Compiled once per
// kernel with KERNEL defined (1: refit + reference root, 2: step 1, 3: sizes of the next
// dispatch, 4: step 2, 5: steps 3 and 4, 6: step 5).
//
// Result buffer (binding 5): a 64-word header, then the step-5 hits as (reference polygon,
// other polygon) global ids. Every counter keeps counting past its capacity (writes past it
// are dropped), so the CPU sees how much room a complete answer needs.
layout(std430, binding = 5) buffer Result {
    uint h_nonfinite;   // 0: 1 + the arena index of a host-buffer mesh with a NaN or infinity
    uint h_l1;          // 1: step-1 hits (other leaves in the reference root)
    uint h_pairs;       // 2: step-2 hits (leaf pairs)
    uint h_list;        // 3: list words allocated for steps 3 and 4
    uint h_hits;        // 4: step-5 hits
    uint h_tests3;      // 5: step-3 tests
    uint h_tests4;      // 6: step-4 tests
    uint h_hits3;       // 7: step-3 hits
    uint h_hits4;       // 8: step-4 hits
    uint h_total34;     // 9: step-3 and step-4 tests (threads of that dispatch)
    uint h_total5;      // 10: step-5 tests (threads of that dispatch)
    uint h_too_many;    // 11: a dispatch would need 2^31 threads or more
    uint h_half_depth;  // 12: the half depth the tests use (float bits)
    uint h_pad1[11];    // 13..23
    uint h_args[12];    // 24..35: indirect dispatch sizes (x, y, z, -): steps 2, 3-4, 5
    uint h_pad2[28];    // 36..63
    uint out_hits[];
};
layout(std430, binding = 9) buffer Boxes { float boxes[]; };
// Root boxes per mesh of the arena (order-preserving keys: min xyz, max xyz).
layout(std430, binding = 8) buffer Roots { uint roots[]; };
float half_depth() { return uintBitsToFloat(h_half_depth); }
// Per global leaf: first and end global polygon.
layout(std430, binding = 10) readonly buffer LeafPolys { uint leaf_polys[]; };

uniform uint u_ref_mesh;
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
// One thread per leaf of one mesh (u_first_leaf on): its box is the min/max of its slots
// (contiguous), and grows the mesh's root. A NaN or infinity names the mesh in the header.
layout(std430, binding = 7) readonly buffer LeafRange { uint leaf_range[]; };
uniform uint u_first_leaf;
void main() {
    if (thread_index() >= u_count) return;
    uint l = u_first_leaf + thread_index();
    vec3 lo = vec3(uintBitsToFloat(0x7f800000u));
    vec3 hi = -lo;
    bool finite = true;
    for (uint i = leaf_range[3u * l]; i < leaf_range[3u * l + 1u]; i++) {
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
    uint mesh = leaf_range[3u * l + 2u];
    if (!finite) {
        atomicCompSwap(h_nonfinite, 0u, mesh + 1u);
        return;
    }
    for (uint k = 0u; k < 3u; k++) {
        atomicMin(roots[6u * mesh + k], key(lo[k]));
        atomicMax(roots[6u * mesh + 3u + k], key(hi[k]));
    }
}
#endif

#if KERNEL == 2 || KERNEL == 3
// Per other mesh of the query: first global leaf, leaves, first thread, arena index.
layout(std430, binding = 11) readonly buffer Others { uint others[]; };
uniform uint u_others;
#endif

#if KERNEL == 2
// Step 1: one thread per leaf of the other meshes: is it in the reference root?
layout(std430, binding = 2) writeonly buffer L1 { uint l1[]; };
void main() {
    uint t = thread_index();
    if (t >= u_count) return;
    uint lo = 0u, hi = u_others;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (others[4u * mid + 2u] <= t) lo = mid; else hi = mid;
    }
    uint leaf = others[4u * lo] + (t - others[4u * lo + 2u]);
    vec3 rlo, rhi, clo, chi;
    for (uint k = 0u; k < 3u; k++) {
        rlo[k] = unkey(roots[6u * u_ref_mesh + k]);
        rhi[k] = unkey(roots[6u * u_ref_mesh + 3u + k]);
    }
    leaf_box(leaf, clo, chi);
    if (boxes_meet(rlo, rhi, clo, chi)) {
        uint k = atomicAdd(h_l1, 1u);
        if (k < u_l1_cap) l1[k] = leaf;
    }
}
#endif

#if KERNEL >= 3
// A leaf pair: other leaf B, reference leaf R, list offset, step-3 and step-4 hit counts,
// first step-3/4 test, first step-5 test, unused.
layout(std430, binding = 3) buffer Pairs { uint pairs[]; };
layout(std430, binding = 4) buffer Lists { uint lists[]; };
const uint PAIR = 8u;

uint leaf_size(uint l) { return leaf_polys[2u * l + 1u] - leaf_polys[2u * l]; }
uint pair_count() { return min(h_pairs, u_pair_cap); }

// A 2D grid of 64-thread workgroups for n threads (at most 65535 a side); 2^31 threads or
// more are refused (h_too_many), so the grid never wraps 32-bit thread indices.
void set_args(uint at, uint n) {
    if (n >= 0x80000000u) {
        h_too_many = 1u;
        n = 0u;
    }
    uint groups = (n + 63u) / 64u;
    uint x = min(groups, 65535u);
    h_args[at] = x;
    h_args[at + 1u] = x == 0u ? 1u : (groups + x - 1u) / x;
    h_args[at + 2u] = 1u;
}

// The pair holding flat test t: the last pair whose first test (word w) is <= t.
uint pair_of(uint t, uint w) {
    uint lo = 0u, hi = pair_count();
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (pairs[PAIR * mid + w] <= t) lo = mid; else hi = mid;
    }
    return lo;
}

// Flat test t of a step over the pairs (first tests in word w): its pair k, the test's
// index i in the pair, the pair's other leaf b, reference leaf r, list offset off, and
// the reference leaf's polygon count nr.
struct PairTest { uint k; uint i; uint b; uint r; uint off; uint nr; };
PairTest pair_test(uint t, uint w) {
    PairTest p;
    p.k = pair_of(t, w);
    p.i = t - pairs[PAIR * p.k + w];
    p.b = pairs[PAIR * p.k];
    p.r = pairs[PAIR * p.k + 1u];
    p.off = pairs[PAIR * p.k + 2u];
    p.nr = leaf_size(p.r);
    return p;
}
#endif

#if KERNEL == 3
// One workgroup sizes the next step. u_src 0: step 2 (every step-1 hit against every
// reference leaf). 1 and 2: an exclusive scan over the pairs of their step-3/4 test counts
// (polygons of both leaves) or step-5 test counts (step-3 hits x step-4 hits), so the next
// step runs one thread per test. 3: the half depth, raised to 2^-20 of the largest extent
// of the query's meshes (from the roots the refit just reduced).
uniform uint u_src;
uniform float u_h_base;
shared uint part[64];
shared uint part_b[64];
shared bool part_over[64];
// A pair's test count; `over` when it does not fit in 32 bits.
uint weight(uint k, out uint nr, inout bool over) {
    uint a, b;
    if (u_src == 1u) {
        a = leaf_size(pairs[PAIR * k + 1u]);
        b = leaf_size(pairs[PAIR * k]);
        nr = a;
        over = over || a + b < a;
        return a + b;
    }
    nr = 0u;
    a = pairs[PAIR * k + 3u];
    b = pairs[PAIR * k + 4u];
    over = over || (a != 0u && b > 0xffffffffu / a);
    return a * b;
}
double extent_of(uint mesh) {
    double e = 0.0;
    for (uint k = 0u; k < 3u; k++) {
        e = max(e, double(unkey(roots[6u * mesh + 3u + k])) - double(unkey(roots[6u * mesh + k])));
    }
    return e;
}
double far_of(uint mesh) {
    double f = 0.0;
    for (uint k = 0u; k < 6u; k++) f = max(f, abs(double(unkey(roots[6u * mesh + k]))));
    return f;
}
void main() {
    uint lane = gl_LocalInvocationID.x;
    if (u_src == 3u) {
        if (lane == 0u) {
            double e = extent_of(u_ref_mesh);
            for (uint i = 0u; i < u_others; i++) e = max(e, extent_of(others[4u * i + 3u]));
            if (e == 0.0) {
                // Every mesh a single point: the largest coordinate magnitude, or 1.
                e = far_of(u_ref_mesh);
                for (uint i = 0u; i < u_others; i++) e = max(e, far_of(others[4u * i + 3u]));
                if (e == 0.0) e = 1.0;
            }
            double h = max(double(u_h_base), e / 2097152.0) * (1.0 + 1e-6);
            h_half_depth = floatBitsToUint(float(h));
        }
        return;
    }
    if (u_src == 0u) {
        if (lane == 0u) {
            uint n = min(h_l1, u_l1_cap);
            // n * u_ref_leaves threads: refused (h_too_many) from 2^31 on.
            if (u_ref_leaves != 0u && n > 0x7fffffffu / u_ref_leaves) {
                h_too_many = 1u;
                n = 0u;
            }
            set_args(0u, n * u_ref_leaves);
        }
        return;
    }
    uint p = pair_count();
    uint chunk = (p + 63u) / 64u;
    uint a = min(lane * chunk, p), e = min(a + chunk, p);
    uint sum = 0u, sum_r = 0u;
    bool over = false;
    for (uint k = a; k < e; k++) {
        uint nr;
        uint w = weight(k, nr, over);
        over = over || sum + w < sum;
        sum += w;
        sum_r += nr;
    }
    part[lane] = sum;
    part_b[lane] = sum_r;
    part_over[lane] = over;
    memoryBarrierShared();
    barrier();
    if (lane == 0u) {
        uint run = 0u, run_r = 0u;
        bool o = false;
        for (uint i = 0u; i < 64u; i++) {
            uint w = part[i];
            o = o || part_over[i] || run + w < run;
            part[i] = run;
            run += w;
            run_r += part_b[i];
        }
        if (o) h_too_many = 1u;
        if (u_src == 1u) {
            h_total34 = o ? 0u : run;
            h_tests3 = run_r;
            h_tests4 = run - run_r;
            set_args(4u, h_total34);
        } else {
            h_total5 = o ? 0u : run;
            set_args(8u, h_total5);
        }
    }
    memoryBarrierShared();
    barrier();
    uint at = part[lane];
    uint word = u_src == 1u ? 5u : 6u;
    bool ignored = false;
    for (uint k = a; k < e; k++) {
        uint nr;
        uint w = weight(k, nr, ignored);
        pairs[PAIR * k + word] = at;
        at += w;
    }
}
#endif

#if KERNEL == 4
// Step 2, one thread per (step-1 hit B, reference leaf R): every pair whose boxes meet is
// appended, with room for its step-3 and step-4 lists.
layout(std430, binding = 2) readonly buffer L1 { uint l1[]; };
void main() {
    uint t = thread_index();
    uint n = min(h_l1, u_l1_cap);
    if (u_ref_leaves == 0u || t / u_ref_leaves >= n) return;
    uint b = l1[t / u_ref_leaves];
    uint r = u_ref_leaf_base + t % u_ref_leaves;
    vec3 blo, bhi, rlo, rhi;
    leaf_box(b, blo, bhi);
    leaf_box(r, rlo, rhi);
    if (!boxes_meet(blo, bhi, rlo, rhi)) return;
    uint k = atomicAdd(h_pairs, 1u);
    uint off = atomicAdd(h_list, leaf_size(r) + leaf_size(b));
    if (k < u_pair_cap) {
        pairs[PAIR * k] = b;
        pairs[PAIR * k + 1u] = r;
        pairs[PAIR * k + 2u] = off;
        pairs[PAIR * k + 3u] = 0u;
        pairs[PAIR * k + 4u] = 0u;
    }
}
#endif

#if KERNEL == 5
// Steps 3 and 4, one thread per (pair (B, R), polygon of R or B): R's polygons inside B's
// box go to the pair's first list, B's polygons inside R's box to its second (which starts
// after room for all of R's polygons).
void main() {
    uint t = thread_index();
    if (t >= h_total34) return;
    PairTest pt = pair_test(t, 5u);
    uint k = pt.k, i = pt.i, b = pt.b, r = pt.r, off = pt.off, nr = pt.nr;
    bool step3 = i < nr;
    uint p = step3 ? leaf_polys[2u * r] + i : leaf_polys[2u * b] + (i - nr);
    vec3 vlo, vhi, plo, phi;
    leaf_box(step3 ? b : r, vlo, vhi);
    poly_box(p, plo, phi);
    if (!boxes_meet(vlo, vhi, plo, phi)) return;
    uint at = atomicAdd(pairs[PAIR * k + (step3 ? 3u : 4u)], 1u);
    if (step3) atomicAdd(h_hits3, 1u); else atomicAdd(h_hits4, 1u);
    if (off + nr + leaf_size(b) <= u_list_cap) lists[off + (step3 ? 0u : nr) + at] = p;
}
#endif

#if KERNEL == 6
// Step 5, one thread per (pair, step-3 hit, step-4 hit): the reference polygon is the
// viewing volume (section 2.3), the other polygon the candidate.
void main() {
    uint t = thread_index();
    if (t >= h_total5) return;
    PairTest pt = pair_test(t, 6u);
    uint k = pt.k, i = pt.i, b = pt.b, off = pt.off, nr = pt.nr;
    if (off + nr + leaf_size(b) > u_list_cap) return;
    uint n4 = pairs[PAIR * k + 4u];
    uint rp = lists[off + i / n4];
    uint cp = lists[off + nr + i % n4];
    if (polygon_meets(rp, cp)) {
        uint at = atomicAdd(h_hits, 1u);
        if (at < u_hit_cap) {
            out_hits[2u * at] = rp;
            out_hits[2u * at + 1u] = cp;
        }
    }
}
#endif
