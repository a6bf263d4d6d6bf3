// The tests every GL_COMPUTE query kernel shares. Box tests are padded (conservative);
// the polygon volume test runs in double precision in a frame whose origin is the
// reference polygon's first vertex, with its planes moved out by u_pad_rel times the
// local size.
// half_depth(): the viewing volume's half depth (query.glsl reads it from the result
// header, where the GPU may raise it).
float half_depth();
uniform float u_pad_rel;

void poly_box(uint p, out vec3 lo, out vec3 hi) {
    lo = vertex_f(polys[4u * p]);
    hi = lo;
    for (uint j = 1u; j < 4u; j++) {
        uint v = polys[4u * p + j];
        if (v == 0xffffffffu) break;
        vec3 q = vertex_f(v);
        lo = min(lo, q);
        hi = max(hi, q);
    }
}

bool boxes_meet(vec3 vlo, vec3 vhi, vec3 clo, vec3 chi) {
    // Grown by h plus 2^-20 of the magnitudes: float rounding can only add pairs.
    vec3 m = max(max(abs(vlo), abs(vhi)), max(abs(clo), abs(chi)));
    vec3 g = vec3(half_depth()) + m * (1.0 / 1048576.0) + vec3(1e-30);
    return all(greaterThanEqual(chi, vlo - g)) && all(greaterThanEqual(vhi + g, clo));
}

dvec3 vertex_d(uint v, dvec3 o) {
    return dvec3(double(pos[3u * v]), double(pos[3u * v + 1u]), double(pos[3u * v + 2u])) - o;
}

// Sutherland-Hodgman clipping of a triangle against up to 6 planes n.x + d >= 0.
dvec4 planes[6];
int plane_count;

bool clip_meets(dvec3 a, dvec3 b, dvec3 c) {
    dvec3 buf0[12];
    dvec3 buf1[12];
    buf0[0] = a; buf0[1] = b; buf0[2] = c;
    int n = 3;
    for (int pi = 0; pi < plane_count; pi++) {
        dvec4 pl = planes[pi];
        int m = 0;
        for (int i = 0; i < n; i++) {
            dvec3 p = (pi % 2 == 0) ? buf0[i] : buf1[i];
            dvec3 q = (pi % 2 == 0) ? buf0[(i + 1) % n] : buf1[(i + 1) % n];
            double dp = dot(pl.xyz, p) + pl.w;
            double dq = dot(pl.xyz, q) + pl.w;
            if (dp >= 0.0) {
                if (pi % 2 == 0) buf1[m] = p; else buf0[m] = p;
                m++;
            }
            if ((dp >= 0.0) != (dq >= 0.0)) {
                dvec3 x = p + (q - p) * (dp / (dp - dq));
                if (pi % 2 == 0) buf1[m] = x; else buf0[m] = x;
                m++;
            }
        }
        if (m == 0) return false;
        n = m;
    }
    return true;
}

// The viewing volume of triangle (0, a, b) with half-depth hd, planes padded by pad.
void triangle_volume(dvec3 a, dvec3 b, double hd, double pad) {
    dvec3 cr = cross(a, b);
    if (dot(cr, cr) > 0.0) {
        dvec3 n = normalize(cr);
        planes[0] = dvec4(n, hd + pad);
        planes[1] = dvec4(-n, hd + pad);
        dvec3 v[3] = dvec3[3](dvec3(0.0), a, b);
        for (int i = 0; i < 3; i++) {
            dvec3 e = v[(i + 1) % 3] - v[i];
            dvec3 m = normalize(cross(n, e));
            planes[2 + i] = dvec4(m, -dot(m, v[i]) + pad);
        }
        plane_count = 5;
        return;
    }
    // A segment or a point: the thin box of half-width hd/sqrt(2) (hd/sqrt(3)).
    dvec3 v[3] = dvec3[3](dvec3(0.0), a, b);
    int p = 0, q = 0;
    double best = 0.0;
    for (int i = 0; i < 3; i++)
        for (int j = i + 1; j < 3; j++) {
            double l = dot(v[j] - v[i], v[j] - v[i]);
            if (l > best) { p = i; q = j; best = l; }
        }
    dvec3 u = best > 0.0 ? normalize(v[q] - v[p]) : dvec3(1.0, 0.0, 0.0);
    double r = best > 0.0 ? hd / sqrt(2.0LF) : hd / sqrt(3.0LF);
    dvec3 k = (abs(u.x) <= abs(u.y) && abs(u.x) <= abs(u.z)) ? dvec3(1, 0, 0)
            : (abs(u.y) <= abs(u.z) ? dvec3(0, 1, 0) : dvec3(0, 0, 1));
    dvec3 w1 = normalize(cross(u, k));
    dvec3 w2 = cross(u, w1);
    double along = best > 0.0 ? 0.0 : r;
    planes[0] = dvec4(u, -dot(u, v[p]) + along + pad);
    planes[1] = dvec4(-u, dot(u, v[q]) + along + pad);
    planes[2] = dvec4(w1, r - dot(w1, v[p]) + pad);
    planes[3] = dvec4(-w1, r + dot(w1, v[p]) + pad);
    planes[4] = dvec4(w2, r - dot(w2, v[p]) + pad);
    planes[5] = dvec4(-w2, r + dot(w2, v[p]) + pad);
    plane_count = 6;
}

bool polygon_meets(uint rp, uint cp) {
    uint r[4];
    uint c[4];
    for (uint j = 0u; j < 4u; j++) { r[j] = polys[4u * rp + j]; c[j] = polys[4u * cp + j]; }
    uint nr = r[3] == 0xffffffffu ? 1u : 2u;
    uint nc = c[3] == 0xffffffffu ? 1u : 2u;
    dvec3 o = dvec3(vertex_f(r[0]));
    for (uint a = 0u; a < nr; a++) {
        // Reference triangles (v0, v1, v2) and (v0, v2, v3): origin v0 for both.
        dvec3 ra = vertex_d(r[1u + a], o);
        dvec3 rb = vertex_d(r[2u + a], o);
        double size = max(max(length(ra), length(rb)), 1e-300);
        for (uint t = 0u; t < nc; t++) {
            dvec3 ca = vertex_d(c[0], o);
            dvec3 cb = vertex_d(c[1u + t], o);
            dvec3 cc = vertex_d(c[2u + t], o);
            double s = max(size, max(length(ca), max(length(cb), length(cc))));
            triangle_volume(ra, rb, double(half_depth()), double(u_pad_rel) * s);
            if (clip_meets(ca, cb, cc)) return true;
        }
    }
    return false;
}
