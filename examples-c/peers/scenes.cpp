// The scenes of both drivers (scenes.hpp). The cross-check's: every real mesh of
// ../shared/meshes placed so they touch, and generated hard cases; every body is moved per
// frame by pose() (warp in the mesh's own frame, then a rigid move). The benchmark's: the
// paper's set (§3), an instrument pushed into an organ to a depth of about 12 pairs, and the
// heavy organ-organ case, with the same pose().
#include "scenes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <memory>

namespace peers {

static const double PI = 3.14159265358979323846;

Warp axis_warp(double amp, double k, double sign, int shift, int along) {
    return [=](int f, double x[3]) {
        if (amp != 0) x[shift] += sign * amp * std::sin(0.35 * f + k * x[along]);
    };
}

Warp wave_warp(double amp, double k, double rate) {
    return [=](int f, double x[3]) {
        double ph = rate * f, p[3] = {x[0], x[1], x[2]};
        x[0] = p[0] + amp * std::sin(ph + k * p[1]);
        x[1] = p[1] + amp * std::sin(1.3 * ph + k * p[2]);
        x[2] = p[2] + amp * std::sin(0.7 * ph + k * p[0]);
    };
}

void pose(const Body &b, int f, std::vector<float> &fo, std::vector<double> &d) {
    const Mesh &M = b.mesh;
    size_t n = M.nv();
    fo.resize(3 * n);
    d.resize(3 * n);
    double R[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, t[3] = {0, 0, 0};
    if (b.place) b.place(f, R, t);
    for (size_t i = 0; i < n; i++) {
        double x[3] = {M.rest[3 * i], M.rest[3 * i + 1], M.rest[3 * i + 2]};
        if (b.warp) b.warp(f, x);
        for (int r = 0; r < 3; r++) {
            double v = R[3 * r] * x[0] + R[3 * r + 1] * x[1] + R[3 * r + 2] * x[2] + t[r];
            fo[3 * i + r] = float(v);
            d[3 * i + r] = double(fo[3 * i + r]); // every library sees these exact values
        }
    }
}

void Scene::frame(int f, Frame &out) const {
    pose(A, f, out.a, out.ad);
    pose(B, f, out.b, out.bd);
}

// ---- the cross-check's scenes ------------------------------------------------------------

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

Scene instrument_vs_organ(const Mesh &ins, const Mesh &organ, const double dir[3], int frames) {
    Scene S;
    S.kind = "instrument-organ";
    S.name = ins.name + " / " + organ.name;
    double D = diag(organ), L = 0.1 * D;
    double d[3] = {dir[0], dir[1], dir[2]};
    double l = std::sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    for (double &c : d) c /= l;
    // The organ's vertex farthest along d lies on its convex hull: the instrument works there.
    size_t far = farthest_vertex(organ, d);
    double p[3] = {organ.rest[3 * far], organ.rest[3 * far + 1], organ.rest[3 * far + 2]};
    S.A.mesh = instrument_local(ins, L, 2);
    S.A.warp = axis_warp(0.01 * L, 2 * PI * 2 / L, +1, 1, 2); // bends along its length
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
    S.B.warp = axis_warp(0.004 * D, 2 * PI * 3 / D, -1, 1, 0);
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
    S.A.warp = axis_warp(0.003 * D, 2 * PI * 3 / D, +1, 1, 0);
    S.B.warp = axis_warp(0.003 * D, 2 * PI * 3 / D, -1, 1, 0);
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
    S.A.warp = axis_warp(amp, 2 * PI, +1, 1, 0);
    S.B.warp = axis_warp(amp, 2 * PI, sign_b, 1, 0);
    S.frames = frames;
    S.eps = 1e-3f;
    return S;
}

std::vector<std::function<Scene()>> crosscheck_scenes(const std::string &dir, int frames_override) {
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

// ---- the benchmark's scenes --------------------------------------------------------------

// The instrument `ins` scaled to rel_len of the organ's extent, its long axis along x,
// tilted, its tip at the organ's outermost +x vertex (the anchor). Per frame the organ warps
// (0.2% of its extent), the instrument follows the anchor, pushed in by the depth (+-30%) and
// sliding sideways. The depth is chosen by bisection so that the median number of colliding
// pairs over a few frames is about `target` (the exact answer, counted with glcollide's CPU
// backend).
static Scene pushed_in(const std::string &name, const std::string &group, const Mesh &ins, const Mesh &organ,
                       double rel_len, int target) {
    Scene s;
    s.name = name;
    s.kind = "instrument-organ";
    s.group = group;
    s.B.mesh = organ;
    s.extent = extent(organ);
    s.B.warp = wave_warp(0.002 * s.extent, 6.0 / s.extent, 0.05);
    const double plus_x[3] = {1, 0, 0};
    size_t far = farthest_vertex(organ, plus_x);
    std::array<double, 3> anchor = {organ.rest[3 * far], organ.rest[3 * far + 1], organ.rest[3 * far + 2]};
    Mesh q = instrument_local(ins, rel_len * s.extent, 0);
    double cz = std::cos(0.35), sz = std::sin(0.35), cy = std::cos(0.25), sy = std::sin(0.25);
    std::vector<double> p(q.rest.size());
    for (size_t i = 0; i < q.nv(); i++) {
        const double *r = &q.rest[3 * i];
        double x = cz * r[0] - sz * r[1], y = sz * r[0] + cz * r[1], z = r[2];
        p[3 * i] = cy * x + sy * z;
        p[3 * i + 1] = y;
        p[3 * i + 2] = -sy * x + cy * z;
    }
    size_t tip = 0;
    for (size_t i = 0; i < q.nv(); i++)
        if (p[3 * i] < p[3 * tip]) tip = i;
    double off[3] = {anchor[0] - p[3 * tip], anchor[1] - p[3 * tip + 1], anchor[2] - p[3 * tip + 2]};
    for (size_t i = 0; i < p.size(); i++) q.rest[i] = float(p[i] + off[i % 3]);
    s.A.mesh = std::move(q);
    double slide = 0.01 * rel_len * s.extent;
    Warp organ_warp = s.B.warp;
    auto at = [=](double depth) -> Place {
        return [=](int f, double *, double t[3]) {
            double moved[3] = {anchor[0], anchor[1], anchor[2]};
            organ_warp(f, moved);
            double d = depth * (1.0 + 0.3 * std::sin(0.21 * f));
            double sl = slide * std::sin(0.13 * f);
            t[0] = moved[0] - anchor[0] - d;
            t[1] = moved[1] - anchor[1] + sl;
            t[2] = moved[2] - anchor[2] + 0.5 * sl;
        };
    };
    // the depth
    std::unique_ptr<Engine> e(make_glcol(GLCOL_BACKEND_CPU, 0.0f, 0));
    Frame fr;
    s.A.place = at(0);
    s.frame(0, fr);
    e->build(s.A.mesh, s.B.mesh, fr);
    const int samples[] = {0, 7, 15, 23, 31};
    std::vector<Key> out;
    auto count = [&](double d) {
        s.A.place = at(d);
        std::vector<size_t> n;
        for (int f : samples) {
            s.frame(f, fr);
            e->update(fr);
            e->query(out);
            n.push_back(out.size());
        }
        std::sort(n.begin(), n.end());
        return n[n.size() / 2];
    };
    double lo[3], hi[3];
    bbox(s.A.mesh, lo, hi);
    double dlo = 0, dhi = 0.5 * (hi[0] - lo[0]);
    for (int it = 0; it < 18; it++) {
        double d = 0.5 * (dlo + dhi);
        if (count(d) >= size_t(target)) dhi = d;
        else dlo = d;
    }
    s.depth = dhi;
    s.A.place = at(dhi);
    char buf[160];
    snprintf(buf, sizeof buf, "instrument scaled to %.0f%% of the organ's extent, pushed in at the organ's +x extreme",
             rel_len * 100);
    s.how = buf;
    return s;
}

// Two organs at rest in their shared frame, opposite warps (0.4% of the scene's extent).
static Scene heavy(const std::string &name, const Mesh &a, const Mesh &b) {
    Scene s;
    s.name = name;
    s.kind = "organ-organ";
    s.group = "heavy";
    s.A.mesh = a;
    s.B.mesh = b;
    double la[3], ha[3], lb[3], hb[3];
    bbox(a, la, ha);
    bbox(b, lb, hb);
    for (int k = 0; k < 3; k++) s.extent = std::max(s.extent, std::max(ha[k], hb[k]) - std::min(la[k], lb[k]));
    double amp = 0.004 * s.extent, k = 8.0 / s.extent;
    s.A.warp = wave_warp(amp, k, 0.1);
    s.B.warp = wave_warp(-amp, k, 0.1);
    s.how = "both at rest in their shared CT frame (they overlap), opposite warps";
    return s;
}

std::vector<Scene> bench_scenes(const std::string &dir, const std::string &only, bool quick) {
    auto M = [&](const char *n) { return load_obj(dir, n); };
    std::vector<Scene> scenes;
    Mesh blade = M("scissors_blade"), jaw = M("forceps_jaw");
    auto add_instrument = [&](const std::string &name, const std::string &group, const Mesh &ins, const Mesh &organ,
                              const std::string &how) {
        if (!only.empty() && name.find(only) == std::string::npos) return;
        Scene s = pushed_in(name, group, ins, organ, 0.12, 12);
        s.how = how + "; " + s.how;
        scenes.push_back(std::move(s));
    };
    std::string how;
    {
        Mesh face = M("face");
        Mesh f12 = decimate(face, 1252, &how);
        add_instrument("blade_vs_face1k", "paper", blade, f12, "face.obj " + how);
    }
    add_instrument("blade_vs_teapot4k", "paper", blade, M("teapot"), "teapot.obj as is");
    Mesh gall = M("gallbladder_glt");
    add_instrument("blade_vs_gallbladder15k", "paper", blade, gall,
                   "gallbladder_glt.obj as is (stands for the airways, 14,436)");
    if (!quick) {
        Mesh c32 = decimate(M("colon_100k"), 32375, &how);
        add_instrument("blade_vs_colon32k", "paper", blade, c32, "colon_100k.obj " + how);
        Mesh s52 = decimate(M("spine_pelvis"), 51910, &how);
        std::string h52 = "spine_pelvis.obj " + how;
        add_instrument("blade_vs_spine52k", "paper", blade, s52, h52);
        add_instrument("jaw_vs_spine52k", "instrument", jaw, s52, h52);
        Mesh g = gall;
        const char *names[] = {"blade_vs_gallbladder59k", "blade_vs_gallbladder235k", "blade_vs_gallbladder941k"};
        for (int k = 0; k < 3; k++) {
            g = subdivide(g);
            add_instrument(names[k], "scaling", blade, g,
                           "gallbladder_glt.obj, midpoint subdivision x" + std::to_string(k + 1) + " (" +
                               std::to_string(g.ntri()) + " triangles)");
        }
    }
    if (only.empty() || std::string("colon_vs_small_intestine").find(only) != std::string::npos)
        scenes.push_back(heavy("colon_vs_small_intestine", M("colon"), M("small_intestine")));
    return scenes;
}

} // namespace peers
