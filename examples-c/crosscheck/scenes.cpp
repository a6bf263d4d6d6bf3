// crosscheck: the scenes. Real meshes from ../shared/meshes (read with glcol_obj_load) placed
// so they touch, and generated hard cases. Every scene is a reference mesh A and a mesh B,
// each moved per frame by pose() below (warp in the mesh's own frame, then a rigid move).
#include "scenes.hpp"

#include <glcollide.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <tuple>

namespace xc {

static const double PI = 3.14159265358979323846;

void pose(const Body &b, int f, std::vector<float> &fo, std::vector<double> &d) {
    const Mesh &M = b.mesh;
    size_t n = M.nv();
    fo.resize(3 * n);
    d.resize(3 * n);
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {0, 0, 0};
    if (b.place) b.place(f, R, t);
    const Warp &w = b.warp;
    for (size_t i = 0; i < n; i++) {
        double x[3] = {M.rest[3 * i], M.rest[3 * i + 1], M.rest[3 * i + 2]};
        if (w.amp != 0) x[w.shift] += w.sign * w.amp * std::sin(0.35 * f + w.k * x[w.along]);
        for (int r = 0; r < 3; r++) {
            double v = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2] + t[r];
            fo[3 * i + r] = float(v);
            d[3 * i + r] = double(fo[3 * i + r]); // every library sees these exact values
        }
    }
}

// ---- mesh helpers ------------------------------------------------------------------------

static void bbox(const Mesh &M, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = HUGE_VAL, hi[k] = -HUGE_VAL;
    for (size_t i = 0; i < M.rest.size(); i++) {
        lo[i % 3] = std::min(lo[i % 3], M.rest[i]);
        hi[i % 3] = std::max(hi[i % 3], M.rest[i]);
    }
}
static double diag(const Mesh &M) {
    double lo[3], hi[3];
    bbox(M, lo, hi);
    return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                     (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

Mesh load_obj(const std::string &dir, const std::string &name) {
    Mesh M = load_obj_path(dir + "/" + name + ".obj");
    M.name = name;
    return M;
}

Mesh load_obj_path(const std::string &path) {
    GlcolObjMesh o;
    std::string name = path.substr(path.find_last_of('/') + 1);
    if (name.size() > 4 && name.compare(name.size() - 4, 4, ".obj") == 0) name.resize(name.size() - 4);
    if (glcol_obj_load(path.c_str(), &o) != GLCOL_STATUS_OK)
        throw std::runtime_error("cannot read " + path + ": " + glcol_last_error_message());
    Mesh M;
    M.name = name;
    M.rest.assign(o.positions, o.positions + 3 * o.vertex_count);
    M.poly.assign(o.indices, o.indices + 3 * o.polygon_count);
    M.vpp = 3;
    glcol_obj_free(&o);
    M.split_polygons();
    return M;
}

// Faces [f0, f1) of M (0-based) as a mesh of their own.
static Mesh sub_mesh(const Mesh &M, size_t f0, size_t f1, const std::string &name) {
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

// Builds a mesh from generated polygons, welding bit-identical positions.
struct Builder {
    Mesh m;
    std::map<std::tuple<double, double, double>, uint32_t> at;
    explicit Builder(const std::string &name, uint32_t vpp) {
        m.name = name;
        m.vpp = vpp;
    }
    uint32_t v(double x, double y, double z) {
        auto k = std::make_tuple(x, y, z);
        auto it = at.find(k);
        if (it != at.end()) return it->second;
        uint32_t i = uint32_t(m.rest.size() / 3);
        m.rest.insert(m.rest.end(), {x, y, z});
        at.emplace(k, i);
        return i;
    }
    void tri(uint32_t a, uint32_t b, uint32_t c) { m.poly.insert(m.poly.end(), {a, b, c}); }
    void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) {
        m.poly.insert(m.poly.end(), {a, b, c, d});
    }
    Mesh done() {
        m.split_polygons();
        return m;
    }
};

using Fn = std::function<void(double u, double v, double out[3])>;

// An n x n triangulated patch of the parametric surface fn over [0,1]^2.
static void patch(Builder &b, int nu, int nv, const Fn &fn, bool flip = false) {
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

static Mesh grid(const std::string &name, int n, const Fn &fn) {
    Builder b(name, 3);
    patch(b, n, n, fn);
    return b.done();
}

static Mesh icosphere(const std::string &name, int sub, double r) {
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
static Mesh box(const std::string &name, double lx, double ly, double lz, int n) {
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
static Mesh octahedron(const std::string &name, const double c[3], double r, double a) {
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

// ---- scene definitions -------------------------------------------------------------------

static void rot_to(const double d[3], double R[9]) {
    // Columns u, v, w with w = -d: local z points against d (into the organ).
    double w[3] = {-d[0], -d[1], -d[2]};
    double a[3] = {1, 0, 0};
    if (std::fabs(w[0]) > 0.8) a[0] = 0, a[1] = 1;
    double u[3] = {a[1] * w[2] - a[2] * w[1], a[2] * w[0] - a[0] * w[2], a[0] * w[1] - a[1] * w[0]};
    double l = std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
    for (double &c : u) c /= l;
    double v[3] = {w[1] * u[2] - w[2] * u[1], w[2] * u[0] - w[0] * u[2], w[0] * u[1] - w[1] * u[0]};
    for (int r = 0; r < 3; r++) R[3 * r] = u[r], R[3 * r + 1] = v[r], R[3 * r + 2] = w[r];
}

// The instrument centred on its box, its longest axis turned onto z, scaled to length L.
static Mesh instrument_local(Mesh M, double L) {
    double lo[3], hi[3];
    bbox(M, lo, hi);
    int ax = 0;
    for (int k = 1; k < 3; k++)
        if (hi[k] - lo[k] > hi[ax] - lo[ax]) ax = k;
    double s = L / (hi[ax] - lo[ax]);
    int perm[3] = {(ax + 1) % 3, (ax + 2) % 3, ax};
    std::vector<double> r(M.rest.size());
    for (size_t i = 0; i < M.nv(); i++)
        for (int k = 0; k < 3; k++)
            r[3 * i + k] = (M.rest[3 * i + perm[k]] - (lo[perm[k]] + hi[perm[k]]) / 2) * s;
    M.rest = r;
    return M;
}

Scene instrument_vs_organ(const Mesh &ins, const Mesh &organ, const double dir[3], int frames) {
    Scene S;
    S.kind = "instrument-organ";
    S.name = ins.name + " / " + organ.name;
    double D = diag(organ), L = 0.1 * D;
    double d[3] = {dir[0], dir[1], dir[2]};
    double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double &c : d) c /= l;
    // The organ's vertex farthest along d lies on its convex hull: the instrument works there.
    size_t far = 0;
    for (size_t i = 1; i < organ.nv(); i++)
        if (d[0] * organ.rest[3 * i] + d[1] * organ.rest[3 * i + 1] + d[2] * organ.rest[3 * i + 2] >
            d[0] * organ.rest[3 * far] + d[1] * organ.rest[3 * far + 1] + d[2] * organ.rest[3 * far + 2])
            far = i;
    double p[3] = {organ.rest[3 * far], organ.rest[3 * far + 1], organ.rest[3 * far + 2]};
    S.A.mesh = instrument_local(ins, L);
    S.A.warp = {0.01 * L, 2 * PI * 2 / L, +1, 1, 2}; // bends along its length
    double R0[9];
    rot_to(d, R0);
    S.A.place = [=](int f, double R[9], double t[3]) {
        double th = 0.02 * f, c = std::cos(th), s = std::sin(th);
        double Rz[9] = {c, -s, 0, s, c, 0, 0, 0, 1};
        for (int r = 0; r < 3; r++)
            for (int k = 0; k < 3; k++)
                R[3 * r + k] = R0[3 * r] * Rz[k] + R0[3 * r + 1] * Rz[3 + k] + R0[3 * r + 2] * Rz[6 + k];
        double off = L * (0.05 + 0.3 * std::sin(2 * PI * f / 40.0));
        for (int k = 0; k < 3; k++) t[k] = p[k] + d[k] * off;
    };
    S.B.mesh = organ;
    S.B.warp = {0.004 * D, 2 * PI * 3 / D, -1, 1, 0};
    S.frames = frames;
    S.eps = float(1e-3 * L);
    return S;
}

Scene organ_vs_organ(const Mesh &a, const Mesh &b, int frames) {
    Scene S;
    S.kind = "organ-organ";
    S.name = a.name + " / " + b.name;
    double D = std::max(diag(a), diag(b));
    S.A.mesh = a;
    S.B.mesh = b;
    S.A.warp = {0.003 * D, 2 * PI * 3 / D, +1, 1, 0};
    S.B.warp = {0.003 * D, 2 * PI * 3 / D, -1, 1, 0};
    S.frames = frames;
    S.eps = float(1e-3 * diag(a));
    return S;
}

static Scene hard(const std::string &name, Mesh a, Mesh b, double amp, double sign_b, int frames) {
    Scene S;
    S.kind = "generated";
    S.name = name;
    S.A.mesh = std::move(a);
    S.B.mesh = std::move(b);
    S.A.warp = {amp, 2 * PI, +1, 1, 0};
    S.B.warp = {amp, 2 * PI, sign_b, 1, 0};
    S.frames = frames;
    S.eps = 1e-3f;
    return S;
}

std::vector<std::function<Scene()>> all_scenes(const std::string &dir, int frames_override) {
    std::vector<std::function<Scene()>> v;
    auto F = [frames_override](int n) { return frames_override > 0 ? frames_override : n; };
    const char *instruments[] = {"scissors_blade", "forceps_jaw", "dental_instrument"};
    const double dirs[3][3] = {{1, 0.3, 0.2}, {-0.2, 1, 0.4}, {0.3, -0.4, 1}};
    const char *organs[] = {"liver_glt", "gallbladder_glt", "heart_vena_cava", "colon",
                            "small_intestine", "colon_vhf", "colon_100k"};
    for (const char *o : organs)
        for (int i = 0; i < 3; i++) {
            std::string in = instruments[i], on = o;
            std::array<double, 3> d = {dirs[i][0], dirs[i][1], dirs[i][2]};
            int fr = F(100);
            v.push_back([=] { return instrument_vs_organ(load_obj(dir, in), load_obj(dir, on), d.data(), fr); });
        }
    v.push_back([=] { return organ_vs_organ(load_obj(dir, "colon"), load_obj(dir, "small_intestine"), F(100)); });
    v.push_back([=] { return organ_vs_organ(load_obj(dir, "liver_glt"), load_obj(dir, "gallbladder_glt"), F(100)); });
    v.push_back([=] {
        // spine_pelvis.obj header: L5 = faces 34753-43854, S1 = faces 43855-70404 (1-based).
        Mesh sp = load_obj(dir, "spine_pelvis");
        return organ_vs_organ(sub_mesh(sp, 34752, 43854, "spine_L5"),
                              sub_mesh(sp, 43854, 70404, "spine_S1"), F(100));
    });

    // ---- generated hard cases (unit size, epsilon 1e-3) ----
    // The warp shifts y by a function of x only, so every mesh that lies in a plane z = c
    // stays in it: contacts that live in z = 0 stay exact contacts, frame after frame.
    auto plane_grid = [](const std::string &n, int k, double x0, double y0, double x1, double y1,
                         double z, double rot) {
        double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2, c = std::cos(rot), s = std::sin(rot);
        return grid(n, k, [=](double u, double w, double o[3]) {
            double x = x0 + u * (x1 - x0) - cx, y = y0 + w * (y1 - y0) - cy;
            o[0] = cx + c * x - s * y;
            o[1] = cy + s * x + c * y;
            o[2] = z;
        });
    };
    v.push_back([=] {
        return hard("coplanar overlap (grids in z=0)", plane_grid("gridA", 8, 0, 0, 1, 1, 0, 0),
                    plane_grid("gridB", 8, 0.37, 0.21, 1.37, 1.21, 0, 0.3), 0.05, -1, F(100));
    });
    v.push_back([=] {
        return hard("edge touch, coplanar (shared edge x=1)", plane_grid("gridA", 8, 0, 0, 1, 1, 0, 0),
                    plane_grid("gridC", 8, 1, 0, 2, 1, 0, 0), 0.05, -1, F(100));
    });
    v.push_back([=] {
        Mesh c = grid("gridC_folded", 8, [](double u, double w, double o[3]) {
            o[0] = 1 + 0.5 * u; // folded up by 60 degrees about the line x=1, z=0
            o[1] = w;
            o[2] = std::sqrt(0.75) * u;
        });
        return hard("edge touch, folded 60 deg", plane_grid("gridA", 8, 0, 0, 1, 1, 0, 0), c, 0.05, -1, F(100));
    });
    v.push_back([=] {
        double ca[3] = {0.3, 0.4, -0.5}, cb[3] = {0.3, 0.4, 0.5};
        // Apex to apex at (0.3, 0.4, 0); the same warp for both keeps the apexes identical.
        return hard("vertex touch (apex to apex)", octahedron("octA", ca, 0.5, 0),
                    octahedron("octB", cb, 0.5, 0.5), 0.05, +1, F(100));
    });
    v.push_back([=] {
        Builder b("pyramids", 3);
        // Apexes down on z=0: on a grid vertex, on a grid edge, inside a triangle; they slide.
        double apex[3][2] = {{0.5, 0.5}, {0.5625, 0.25}, {0.3, 0.71}};
        for (auto &a : apex) {
            uint32_t t = b.v(a[0], a[1], 0), q[4];
            for (int i = 0; i < 4; i++)
                q[i] = b.v(a[0] + 0.05 * std::cos(i * PI / 2 + 0.3), a[1] + 0.05 * std::sin(i * PI / 2 + 0.3), 0.1);
            for (int i = 0; i < 4; i++) b.tri(q[i], q[(i + 1) % 4], t);
            b.tri(q[0], q[2], q[1]);
            b.tri(q[0], q[3], q[2]);
        }
        return hard("vertex on face (apexes sliding on z=0)", plane_grid("gridA", 8, 0, 0, 1, 1, 0, 0),
                    b.done(), 0.05, -1, F(100));
    });
    v.push_back([=] {
        Scene S = hard("thin blade (1e-4) through a sphere", icosphere("sphere", 3, 1.0),
                       box("blade", 0.8, 0.3, 1e-4, 4), 0.01, -1, F(100));
        S.B.place = [](int f, double R[9], double t[3]) {
            double a = 0.4, c = std::cos(a), s = std::sin(a);
            double M[9] = {c, 0, s, 0, 1, 0, -s, 0, c};
            for (int i = 0; i < 9; i++) R[i] = M[i];
            t[0] = 1.0 + 0.35 * std::sin(2 * PI * f / 50.0);
            t[1] = 0.1;
            t[2] = 0.05;
        };
        return S;
    });
    v.push_back([=] {
        // Quads: a UV sphere (poles are quads with a repeated vertex, so one of their two
        // triangles is a segment) against a non-planar quad sheet cutting through it.
        Builder s("uv_sphere_quads", 4);
        int nu = 16, nv = 10;
        auto P = [&](int i, int j) {
            double th = PI * j / nv, ph = 2 * PI * (i % nu) / nu;
            if (j == 0) return s.v(0, 0, 0.6);
            if (j == nv) return s.v(0, 0, -0.6);
            return s.v(0.6 * std::sin(th) * std::cos(ph), 0.6 * std::sin(th) * std::sin(ph), 0.6 * std::cos(th));
        };
        for (int j = 0; j < nv; j++)
            for (int i = 0; i < nu; i++) s.quad(P(i, j), P(i, j + 1), P(i + 1, j + 1), P(i + 1, j));
        Builder c("sheet_quads", 4);
        patch(c, 12, 12, [](double u, double w, double o[3]) {
            o[0] = -0.9 + 1.8 * u;
            o[1] = -0.9 + 1.8 * w;
            o[2] = 0.2 + 0.15 * std::sin(3 * o[0]) * std::cos(2 * o[1]);
        });
        return hard("quads: UV sphere vs warped sheet", s.done(), c.done(), 0.04, -1, F(100));
    });
    v.push_back([=] {
        // Near misses around the band e/2 = 5e-4: sheets of B parallel to A at z = e/4 and
        // z = e/2 (inside the band), z = -e (outside); no pair intersects exactly.
        Builder b("sheets", 3);
        double zs[3] = {2.5e-4, 5e-4, -1e-3};
        for (int k = 0; k < 3; k++) {
            double z = float(zs[k]), x0 = 0.1 + 0.3 * k;
            patch(b, 3, 6, [=](double u, double w, double o[3]) {
                o[0] = x0 + 0.25 * u;
                o[1] = 0.1 + 0.8 * w;
                o[2] = z;
            });
        }
        return hard("epsilon band (sheets at e/4, e/2, -e)", plane_grid("gridA", 8, 0, 0, 1, 1, 0, 0),
                    b.done(), 0.05, -1, F(100));
    });
    return v;
}

} // namespace xc
