// Where the meshes come from: see meshes.hpp.
#include "meshes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <unordered_map>

namespace peers {

static const double PI = 3.14159265358979323846;

Mesh load_obj(const std::string &path) {
    GlcolObjMesh o;
    if (glcol_obj_load(path.c_str(), &o) != GLCOL_STATUS_OK)
        throw std::runtime_error("cannot read " + path + ": " + glcol_last_error_message());
    Mesh M;
    M.name = path.substr(path.find_last_of('/') + 1);
    if (M.name.size() > 4 && M.name.compare(M.name.size() - 4, 4, ".obj") == 0) M.name.resize(M.name.size() - 4);
    M.rest.assign(o.positions, o.positions + 3 * o.vertex_count);
    M.poly.assign(o.indices, o.indices + 3 * o.polygon_count);
    M.vpp = 3;
    glcol_obj_free(&o);
    M.split_polygons();
    return M;
}

Mesh load_obj(const std::string &dir, const std::string &name) {
    Mesh M = load_obj(dir + "/" + name + ".obj");
    M.name = name;
    return M;
}

void bbox(const Mesh &M, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = HUGE_VAL, hi[k] = -HUGE_VAL;
    for (size_t i = 0; i < M.rest.size(); i++) {
        lo[i % 3] = std::min(lo[i % 3], M.rest[i]);
        hi[i % 3] = std::max(hi[i % 3], M.rest[i]);
    }
}

double extent(const Mesh &M) {
    double lo[3], hi[3];
    bbox(M, lo, hi);
    return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

double diag(const Mesh &M) {
    double lo[3], hi[3];
    bbox(M, lo, hi);
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

size_t farthest_vertex(const Mesh &M, const double d[3]) {
    const std::vector<double> &r = M.rest;
    size_t far = 0;
    for (size_t i = 1; i < M.nv(); i++)
        if (d[0] * r[3 * i] + d[1] * r[3 * i + 1] + d[2] * r[3 * i + 2] >
            d[0] * r[3 * far] + d[1] * r[3 * far + 1] + d[2] * r[3 * far + 2])
            far = i;
    return far;
}

// Vertex clustering on a uniform grid of cell h: the vertices of a cell merge into their
// mean (rounded to float), triangles that lose a corner and duplicate triangles go; unused
// vertices go.
static Mesh cluster(const Mesh &m, double h) {
    double lo[3], hi[3];
    bbox(m, lo, hi);
    std::unordered_map<uint64_t, uint32_t> cell;
    std::vector<uint32_t> cid(m.nv());
    std::vector<double> sum;
    std::vector<uint32_t> cnt;
    for (size_t i = 0; i < m.nv(); i++) {
        uint64_t key = 0;
        for (int k = 0; k < 3; k++) key = key * 2097152u + uint64_t((m.rest[3 * i + k] - lo[k]) / h);
        auto it = cell.find(key);
        uint32_t c;
        if (it == cell.end()) {
            c = uint32_t(cnt.size());
            cell.emplace(key, c);
            cnt.push_back(0);
            sum.insert(sum.end(), {0.0, 0.0, 0.0});
        } else
            c = it->second;
        cid[i] = c;
        cnt[c]++;
        for (int k = 0; k < 3; k++) sum[3 * c + k] += m.rest[3 * i + k];
    }
    std::map<std::array<uint32_t, 3>, int> seen;
    Mesh out;
    out.name = m.name;
    std::vector<int64_t> remap(cnt.size(), -1);
    for (size_t t = 0; t < m.ntri(); t++) {
        uint32_t c[3] = {cid[m.tri[3 * t]], cid[m.tri[3 * t + 1]], cid[m.tri[3 * t + 2]]};
        if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
        std::array<uint32_t, 3> key = {c[0], c[1], c[2]};
        std::sort(key.begin(), key.end());
        if (!seen.emplace(key, 1).second) continue;
        for (int j = 0; j < 3; j++) {
            if (remap[c[j]] < 0) {
                remap[c[j]] = int64_t(out.nv());
                for (int k = 0; k < 3; k++) out.rest.push_back(float(sum[3 * c[j] + k] / cnt[c[j]]));
            }
            out.poly.push_back(uint32_t(remap[c[j]]));
        }
    }
    out.split_polygons();
    return out;
}

Mesh decimate(const Mesh &m, size_t target, std::string *how) {
    double e = extent(m);
    double lo = e * 1e-5, hi = e * 0.5; // tiny cells keep everything, huge ones nothing
    Mesh best;
    double best_h = 0;
    for (int it = 0; it < 40; it++) {
        double h = std::sqrt(lo * hi);
        Mesh c = cluster(m, h);
        if (best.tri.empty() || std::abs(double(c.ntri()) - target) < std::abs(double(best.ntri()) - target))
            best = c, best_h = h;
        if (c.ntri() > target) lo = h;
        else hi = h;
        if (std::abs(double(c.ntri()) - target) < 0.01 * target) break;
    }
    if (how) {
        char buf[200];
        snprintf(buf, sizeof buf, "vertex clustering, cell %.4g (%.3g%% of the extent): %zu -> %zu triangles", best_h,
                 100 * best_h / e, m.ntri(), best.ntri());
        *how = buf;
    }
    return best;
}

Mesh subdivide(const Mesh &m) {
    Mesh out;
    out.name = m.name;
    out.rest = m.rest;
    std::unordered_map<uint64_t, uint32_t> mid;
    auto midpoint = [&](uint32_t i, uint32_t j) {
        uint64_t key = uint64_t(std::min(i, j)) << 32 | std::max(i, j);
        auto it = mid.find(key);
        if (it != mid.end()) return it->second;
        uint32_t n = uint32_t(out.nv());
        for (int k = 0; k < 3; k++) out.rest.push_back(0.5f * (float(m.rest[3 * i + k]) + float(m.rest[3 * j + k])));
        mid.emplace(key, n);
        return n;
    };
    for (size_t t = 0; t < m.ntri(); t++) {
        uint32_t a = m.tri[3 * t], b = m.tri[3 * t + 1], c = m.tri[3 * t + 2];
        uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
        out.poly.insert(out.poly.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    out.split_polygons();
    return out;
}

Mesh sub_mesh(const Mesh &M, size_t f0, size_t f1, const std::string &name) {
    Mesh S;
    S.name = name;
    S.vpp = M.vpp;
    std::map<uint32_t, uint32_t> remap;
    for (size_t p = f0; p < f1; p++)
        for (uint32_t j = 0; j < M.vpp; j++) {
            uint32_t v = M.poly[p * M.vpp + j];
            auto it = remap.find(v);
            if (it == remap.end()) {
                it = remap.emplace(v, uint32_t(S.rest.size() / 3)).first;
                S.rest.insert(S.rest.end(), {M.rest[3 * v], M.rest[3 * v + 1], M.rest[3 * v + 2]});
            }
            S.poly.push_back(it->second);
        }
    S.split_polygons();
    return S;
}

Mesh instrument_local(Mesh M, double length, int to) {
    double lo[3], hi[3];
    bbox(M, lo, hi);
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[ax] - lo[ax]) ax = k;
    double s = length / (hi[ax] - lo[ax]);
    int perm[3];
    for (int k = 0; k < 3; k++) perm[k] = (ax + k - to + 3) % 3; // perm[to] = ax
    std::vector<double> r(M.rest.size());
    for (size_t i = 0; i < M.nv(); i++)
        for (int k = 0; k < 3; k++)
            r[3 * i + k] = (M.rest[3 * i + perm[k]] - (lo[perm[k]] + hi[perm[k]]) / 2) * s;
    M.rest = r;
    return M;
}

// ---- generated shapes ----

Builder::Builder(const std::string &name, uint32_t vpp) {
    m.name = name;
    m.vpp = vpp;
}

uint32_t Builder::v(double x, double y, double z) {
    auto k = std::make_tuple(x, y, z);
    auto it = at.find(k);
    if (it != at.end()) return it->second;
    uint32_t i = uint32_t(m.rest.size() / 3);
    m.rest.insert(m.rest.end(), {x, y, z});
    at.emplace(k, i);
    return i;
}

Mesh Builder::done() {
    m.split_polygons();
    return m;
}

void patch(Builder &b, int nu, int nv, const Surface &fn, bool flip) {
    std::vector<uint32_t> id((nu + 1) * (nv + 1));
    for (int j = 0; j <= nv; j++)
        for (int i = 0; i <= nu; i++) {
            double p[3];
            fn(double(i) / nu, double(j) / nv, p);
            id[j * (nu + 1) + i] = b.v(p[0], p[1], p[2]);
        }
    for (int j = 0; j < nv; j++)
        for (int i = 0; i < nu; i++) {
            uint32_t a = id[j * (nu + 1) + i], c = id[j * (nu + 1) + i + 1],
                     d = id[(j + 1) * (nu + 1) + i + 1], e = id[(j + 1) * (nu + 1) + i];
            if (b.m.vpp == 4) {
                if (flip) b.quad(a, e, d, c); else b.quad(a, c, d, e);
            } else if (flip) {
                b.tri(a, d, c);
                b.tri(a, e, d);
            } else {
                b.tri(a, c, d);
                b.tri(a, d, e);
            }
        }
}

Mesh grid(const std::string &name, int n, const Surface &fn) {
    Builder b(name, 3);
    patch(b, n, n, fn);
    return b.done();
}

Mesh icosphere(const std::string &name, int sub, double r) {
    const double t = (1 + std::sqrt(5.0)) / 2;
    std::vector<std::array<double, 3>> v = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0},
                                            {0, -1, t}, {0, 1, t}, {0, -1, -t}, {0, 1, -t},
                                            {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
    std::vector<std::array<uint32_t, 3>> f = {
        {0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
        {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
        {3, 8, 9},  {4, 9, 5},  {2, 4, 11},  {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
    for (auto &p : v) {
        double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
        for (double &c : p) c /= l;
    }
    for (int s = 0; s < sub; s++) {
        std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
        auto m = [&](uint32_t a, uint32_t b) {
            auto k = std::minmax(a, b);
            auto it = mid.find(k);
            if (it != mid.end()) return it->second;
            std::array<double, 3> p;
            for (int i = 0; i < 3; i++) p[i] = v[a][i] + v[b][i];
            double l = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
            for (double &c : p) c /= l;
            v.push_back(p);
            return mid[k] = uint32_t(v.size() - 1);
        };
        std::vector<std::array<uint32_t, 3>> g;
        for (auto &q : f) {
            uint32_t a = m(q[0], q[1]), b = m(q[1], q[2]), c = m(q[2], q[0]);
            g.insert(g.end(), {{q[0], a, c}, {q[1], b, a}, {q[2], c, b}, {a, b, c}});
        }
        f = g;
    }
    Mesh M;
    M.name = name;
    for (auto &p : v) M.rest.insert(M.rest.end(), {p[0] * r, p[1] * r, p[2] * r});
    for (auto &q : f) M.poly.insert(M.poly.end(), {q[0], q[1], q[2]});
    M.split_polygons();
    return M;
}

// Closed box [-lx/2,lx/2] x [-ly/2,ly/2] x [-lz/2,lz/2], each face an n x n grid, welded.
Mesh box(const std::string &name, double lx, double ly, double lz, int n) {
    Builder b(name, 3);
    double h[3] = {lx / 2, ly / 2, lz / 2};
    for (int ax = 0; ax < 3; ax++)
        for (int s = -1; s <= 1; s += 2) {
            int u = (ax + 1) % 3, w = (ax + 2) % 3;
            patch(b, n, n, [&](double a, double c, double o[3]) {
                o[ax] = s * h[ax];
                o[u] = (2 * a - 1) * h[u];
                o[w] = (2 * c - 1) * h[w];
            }, s < 0);
        }
    return b.done();
}

// Octahedron of radius r around c, turned by angle a about z.
Mesh octahedron(const std::string &name, const double c[3], double r, double a) {
    Builder b(name, 3);
    double ca = std::cos(a), sa = std::sin(a);
    uint32_t eq[4];
    for (int i = 0; i < 4; i++) {
        double x = r * std::cos(i * PI / 2), y = r * std::sin(i * PI / 2);
        eq[i] = b.v(c[0] + ca * x - sa * y, c[1] + sa * x + ca * y, c[2]);
    }
    uint32_t top = b.v(c[0], c[1], c[2] + r), bot = b.v(c[0], c[1], c[2] - r);
    for (int i = 0; i < 4; i++) {
        b.tri(eq[i], eq[(i + 1) % 4], top);
        b.tri(eq[(i + 1) % 4], eq[i], bot);
    }
    return b.done();
}

} // namespace peers
