// One thread per (volume, candidate) test of a batch; hits appended through an atomic
// counter. Steps: 0 boxes in boxes, 1 polygons in boxes, 2 polygons in polygon volumes.
// Boxes come as 6 float bit patterns; polygons as global polygon ids.
layout(std430, binding = 2) readonly buffer Vols { uint vols[]; };
layout(std430, binding = 3) readonly buffer Cands { uint cands[]; };
layout(std430, binding = 4) readonly buffer Groups { uint groups[]; }; // vs, vn, cs, cn, first test
layout(std430, binding = 5) buffer Hits { uint hit_count; uint hit_cap; uint hits[]; };
uniform uint u_step;
uniform uint u_groups;
uniform float u_h;
float half_depth() { return u_h; }

void read_box(uint base, bool vol, out vec3 lo, out vec3 hi) {
    for (int k = 0; k < 3; k++) {
        lo[k] = uintBitsToFloat(vol ? vols[base + uint(k)] : cands[base + uint(k)]);
        hi[k] = uintBitsToFloat(vol ? vols[base + 3u + uint(k)] : cands[base + 3u + uint(k)]);
    }
}

void main() {
    uint t = thread_index();
    // The group holding test t (groups are sorted by their first test).
    uint lo = 0u, hi = u_groups;
    while (hi - lo > 1u) {
        uint mid = (lo + hi) / 2u;
        if (groups[5u * mid + 4u] <= t) lo = mid; else hi = mid;
    }
    uint g = lo;
    uint local = t - groups[5u * g + 4u];
    uint vn = groups[5u * g + 1u], cn = groups[5u * g + 3u];
    if (local >= vn * cn || t >= u_count) return;
    uint vi = groups[5u * g] + local / cn;
    uint ci = groups[5u * g + 2u] + local % cn;
    bool meets;
    if (u_step == 0u) {
        vec3 vlo, vhi, clo, chi;
        read_box(6u * vi, true, vlo, vhi);
        read_box(6u * ci, false, clo, chi);
        meets = boxes_meet(vlo, vhi, clo, chi);
    } else if (u_step == 1u) {
        vec3 vlo, vhi, clo, chi;
        read_box(6u * vi, true, vlo, vhi);
        poly_box(cands[ci], clo, chi);
        meets = boxes_meet(vlo, vhi, clo, chi);
    } else {
        meets = polygon_meets(vols[vi], cands[ci]);
    }
    if (meets) {
        uint k = atomicAdd(hit_count, 1u);
        if (k < hit_cap) {
            hits[2u * k] = vi;
            hits[2u * k + 1u] = ci;
        }
    }
}
