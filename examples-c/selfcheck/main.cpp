// selfcheck: glcol_query_all's self-collision pairs against CGAL's
// Polygon_mesh_processing::self_intersections (Epeck kernel), equal sets at epsilon 0, on
// real simulation frames, the crumpled 92k cloth of bench/data and adversarial folds. Uses
// only glcollide's C header.
//
//   cargo build --release && make -C examples-c/selfcheck && examples-c/selfcheck/build/selfcheck
//   selfcheck [--meshes DIR] [--inject] [--only NAME] [--time] [--obj FILE]...
// --obj checks (and with --time times) the given OBJ meshes instead of the built-in cases,
// e.g. the 92k rolled cloth that `DUMP=DIR SCENE=rolled cargo bench --bench scene` writes.
// --time also times CGAL with Epick (and checks it gives Epeck's set), glcollide alone
// (one thread, median of 3 queries) and, built with `make EMBREE=1`, Embree's rtcCollide.
//
// CGAL's notion of adjacency (CGAL 5.5, self_intersections.h, do_faces_intersect) and
// docs/API.md's ("polygons sharing a vertex index are reported only when they meet beyond what
// they share") agree on proper triangles:
// - sharing an edge: CGAL reports the pair iff the four points are coplanar and the two
//   third vertices lie on the same side of the edge; for proper triangles that is exactly
//   "they meet beyond the edge" (off the plane they meet along the edge only; in one plane
//   on opposite sides along the edge only, on the same side with area);
// - sharing one vertex p: CGAL reports iff the edge opposite p in one meets the other
//   triangle; for proper triangles that is "they meet beyond p" (the rule-1 argument of
//   glcollide's src/geom/adjacent/mod.rs: every ray from p into a triangle leaves it through
//   the opposite edge);
// - sharing nothing: plain exact intersection.
// They may differ on degenerate triangles (collinear corners: CGAL's triangle predicates
// require proper triangles) and CGAL's mesh must be manifold (a Surface_mesh); so pairs with
// a degenerate face are left out of the comparison (and counted), and only manifold meshes
// are checked. Sharing is by vertex index on both sides: the mesh is built from the same
// index list, one CGAL vertex per index.
//
// Coordinates are float (glcollide's input), widened exactly to double for CGAL: both see
// the same points. Each case runs glcollide with threads 0 and 1, with the default leaf
// size and with 7 polygons per leaf (other leaf boundaries), and with the case's mesh
// created first or after a far-away decoy mesh (another creation order). --inject drops
// one glcollide pair per case and must make the program fail (exit status 1).

#include <glcollide.h>

#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Surface_mesh.h>

#ifdef WITH_EMBREE
#include <embree3/rtcore.h>
#endif

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <set>
#include <string>
#include <utility>
#include <vector>

namespace {

using K = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = K::Point_3;
using SM = CGAL::Surface_mesh<Point>;
// Exact predicates, inexact constructions: the kernel most users would pick (the test uses
// predicates only, so it is exact too); timed beside Epeck and checked to give the same set.
using Ki = CGAL::Exact_predicates_inexact_constructions_kernel;
using SMi = CGAL::Surface_mesh<Ki::Point_3>;
using PairSet = std::set<std::pair<uint32_t, uint32_t>>;

struct Mesh {
    std::string name;
    std::vector<float> xyz;
    std::vector<uint32_t> tri;
    size_t vertices() const { return xyz.size() / 3; }
    size_t triangles() const { return tri.size() / 3; }
};

bool ok(GlcolStatus s, const char *call) {
    if (s != GLCOL_STATUS_OK)
        std::fprintf(stderr, "%s: %s: %s\n", call, glcol_status_name(s), glcol_last_error_message());
    return s == GLCOL_STATUS_OK;
}

bool load(const std::string &path, Mesh &m) {
    GlcolObjMesh obj;
    if (!ok(glcol_obj_load(path.c_str(), &obj), path.c_str())) return false;
    m.xyz.assign(obj.positions, obj.positions + 3 * obj.vertex_count);
    m.tri.assign(obj.indices, obj.indices + 3 * obj.polygon_count);
    glcol_obj_free(&obj);
    return true;
}

// glcollide's self pairs of `m` (epsilon 0, CPU backend).
bool glcol_self(const Mesh &m, uint32_t threads, uint32_t per_box, bool decoy_first, PairSet &out) {
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.threads = threads;
    sd.max_polygons_per_box = per_box;
    GlcolScene *scene = nullptr;
    if (!ok(glcol_scene_create(&sd, &scene), "glcol_scene_create")) return false;
    // A small far-away triangle, self-colliding too (it has no pairs).
    const float far_xyz[] = {1e30f, 1e30f, 1e30f, 1e30f, 1e30f, 1.0001e30f, 1e30f, 1.0001e30f, 1e30f};
    const uint32_t far_tri[] = {0, 1, 2};
    auto add = [&](const float *xyz, size_t nv, const uint32_t *tri, size_t nt, GlcolMeshId *id) {
        GlcolMeshDesc md;
        glcol_mesh_desc_init(&md);
        md.positions = xyz;
        md.vertex_count = nv;
        md.indices = tri;
        md.polygon_count = nt;
        md.vertices_per_polygon = 3;
        return ok(glcol_mesh_create(scene, &md, id), "glcol_mesh_create") &&
               ok(glcol_mesh_set_self_collision(scene, *id, true), "glcol_mesh_set_self_collision");
    };
    GlcolMeshId id = 0, decoy = 0;
    bool good = true;
    if (decoy_first) good = add(far_xyz, 3, far_tri, 1, &decoy);
    good = good && add(m.xyz.data(), m.vertices(), m.tri.data(), m.triangles(), &id);
    if (good && !decoy_first) good = add(far_xyz, 3, far_tri, 1, &decoy);
    const GlcolPair *pairs = nullptr;
    size_t n = 0;
    good = good && ok(glcol_query_all(scene, &pairs, &n), "glcol_query_all");
    for (size_t i = 0; good && i < n; i++) {
        const GlcolPair &p = pairs[i];
        if (p.mesh_a != id || p.mesh_b != id || p.polygon_a >= p.polygon_b) {
            std::fprintf(stderr, "%s: unexpected pair (%u %u, %u %u)\n", m.name.c_str(), p.mesh_a,
                         p.polygon_a, p.mesh_b, p.polygon_b);
            good = false;
        }
        out.insert({p.polygon_a, p.polygon_b});
    }
    glcol_scene_destroy(scene);
    return good;
}

// Median seconds of glcol_query_all on `m` alone, self-colliding, one thread, epsilon 0
// (3 queries after a first one; the positions re-sent before each, as a simulator does).
double glcol_seconds(const Mesh &m) {
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.threads = 1;
    GlcolScene *scene = nullptr;
    if (!ok(glcol_scene_create(&sd, &scene), "glcol_scene_create")) return -1;
    GlcolMeshDesc md;
    glcol_mesh_desc_init(&md);
    md.positions = m.xyz.data();
    md.vertex_count = m.vertices();
    md.indices = m.tri.data();
    md.polygon_count = m.triangles();
    md.vertices_per_polygon = 3;
    GlcolMeshId id = 0;
    std::vector<double> t;
    if (ok(glcol_mesh_create(scene, &md, &id), "glcol_mesh_create") &&
        ok(glcol_mesh_set_self_collision(scene, id, true), "glcol_mesh_set_self_collision")) {
        for (int i = 0; i < 4; i++) {
            auto t0 = std::chrono::steady_clock::now();
            const GlcolPair *pairs = nullptr;
            size_t n = 0;
            if (!ok(glcol_mesh_update_positions(scene, id, m.xyz.data(), 0, m.vertices(), 0), "update") ||
                !ok(glcol_query_all(scene, &pairs, &n), "glcol_query_all"))
                break;
            if (i) t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
        }
    }
    glcol_scene_destroy(scene);
    if (t.empty()) return -1;
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}

// CGAL (Epick) self-intersecting pairs of a manifold `m`, and the seconds it took.
double cgal_epick(const Mesh &m, PairSet &out) {
    auto t0 = std::chrono::steady_clock::now();
    SMi sm;
    std::vector<SMi::Vertex_index> v;
    v.reserve(m.vertices());
    for (size_t i = 0; i < m.vertices(); i++)
        v.push_back(sm.add_vertex(Ki::Point_3(double(m.xyz[3 * i]), double(m.xyz[3 * i + 1]), double(m.xyz[3 * i + 2]))));
    for (size_t f = 0; f < m.triangles(); f++) sm.add_face(v[m.tri[3 * f]], v[m.tri[3 * f + 1]], v[m.tri[3 * f + 2]]);
    std::vector<std::pair<SMi::Face_index, SMi::Face_index>> found;
    CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(found));
    for (auto &p : found) {
        uint32_t a = uint32_t(p.first.idx()), b = uint32_t(p.second.idx());
        out.insert({std::min(a, b), std::max(a, b)});
    }
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

#ifdef WITH_EMBREE
// CGAL's adjacency rule (do_faces_intersect of CGAL 5.5, see the top of this file) on two
// faces of `m` given by index, with Epick's exact predicates: the narrow phase of the
// Embree peer below.
bool faces_meet(const Mesh &m, uint32_t f, uint32_t g) {
    using P = Ki::Point_3;
    auto pt = [&](uint32_t v) { return P(double(m.xyz[3 * v]), double(m.xyz[3 * v + 1]), double(m.xyz[3 * v + 2])); };
    const uint32_t *a = &m.tri[3 * f], *b = &m.tri[3 * g];
    int shared = 0, ia = -1, ib = -1;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            if (a[i] == b[j]) shared++, ia = i, ib = j;
    Ki::Triangle_3 ta(pt(a[0]), pt(a[1]), pt(a[2])), tb(pt(b[0]), pt(b[1]), pt(b[2]));
    if (shared == 0) return CGAL::do_intersect(ta, tb);
    if (shared == 1) {
        Ki::Segment_3 sa(pt(a[(ia + 1) % 3]), pt(a[(ia + 2) % 3])), sb(pt(b[(ib + 1) % 3]), pt(b[(ib + 2) % 3]));
        return CGAL::do_intersect(ta, sb) || CGAL::do_intersect(tb, sa);
    }
    if (shared == 2) {
        // The third vertices; coplanar and on the same side of the edge: overlap.
        uint32_t wa = 0, wb = 0, e0 = 0, e1 = 0;
        int n = 0;
        for (int i = 0; i < 3; i++) {
            bool in_b = a[i] == b[0] || a[i] == b[1] || a[i] == b[2];
            if (!in_b) wa = a[i];
            else (n++ ? e1 : e0) = a[i];
        }
        for (int j = 0; j < 3; j++)
            if (b[j] != e0 && b[j] != e1) wb = b[j];
        return CGAL::coplanar(pt(e0), pt(e1), pt(wa), pt(wb)) &&
               CGAL::coplanar_orientation(pt(e0), pt(e1), pt(wa), pt(wb)) == CGAL::POSITIVE;
    }
    return false;
}

// Embree 3 rtcCollide of a scene with itself (its cloth tutorial's way to self-collide):
// one user geometry (REFIT quality, LOW-quality scene, bounds rounded outward to float),
// candidates with primID0 < primID1, then faces_meet. Median seconds of 3 queries (commit
// + collide + narrow phase) after a first; the pairs in `out`.
struct EmbreeGeo {
    const Mesh *m;
};
void embree_bounds(const RTCBoundsFunctionArguments *args) {
    const Mesh &m = *static_cast<const EmbreeGeo *>(args->geometryUserPtr)->m;
    const uint32_t *t = &m.tri[3 * args->primID];
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = std::min({m.xyz[3 * t[0] + k], m.xyz[3 * t[1] + k], m.xyz[3 * t[2] + k]});
        hi[k] = std::max({m.xyz[3 * t[0] + k], m.xyz[3 * t[1] + k], m.xyz[3 * t[2] + k]});
    }
    RTCBounds *b = args->bounds_o;
    b->lower_x = lo[0], b->lower_y = lo[1], b->lower_z = lo[2];
    b->upper_x = hi[0], b->upper_y = hi[1], b->upper_z = hi[2];
}
struct EmbreeRun {
    const Mesh *m;
    std::vector<std::pair<uint32_t, uint32_t>> cand;
};
void embree_cb(void *user, RTCCollision *c, unsigned n) {
    auto *r = static_cast<EmbreeRun *>(user);
    for (unsigned i = 0; i < n; i++)
        if (c[i].primID0 < c[i].primID1) r->cand.push_back({c[i].primID0, c[i].primID1});
}
double embree_self(const Mesh &m, PairSet &out) {
    RTCDevice dev = rtcNewDevice("threads=1");
    RTCScene sc = rtcNewScene(dev);
    rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_LOW);
    RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
    EmbreeGeo g{&m};
    rtcSetGeometryUserPrimitiveCount(geo, unsigned(m.triangles()));
    rtcSetGeometryUserData(geo, &g);
    rtcSetGeometryBoundsFunction(geo, embree_bounds, nullptr);
    rtcSetGeometryBuildQuality(geo, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(geo);
    rtcAttachGeometry(sc, geo);
    std::vector<double> t;
    for (int i = 0; i < 4; i++) {
        auto t0 = std::chrono::steady_clock::now();
        rtcCommitGeometry(geo);
        rtcCommitScene(sc);
        EmbreeRun r{&m, {}};
        rtcCollide(sc, sc, embree_cb, &r);
        out.clear();
        for (auto &p : r.cand)
            if (faces_meet(m, p.first, p.second)) out.insert(p);
        if (i) t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    rtcReleaseGeometry(geo);
    rtcReleaseScene(sc);
    rtcReleaseDevice(dev);
    std::sort(t.begin(), t.end());
    return t[t.size() / 2];
}
#endif

// CGAL's self-intersecting face pairs of `m`, and its degenerate faces. False (with a
// message) when the mesh is not manifold.
bool cgal_self(const Mesh &m, PairSet &out, std::set<uint32_t> &degenerate) {
    SM sm;
    std::vector<SM::Vertex_index> v;
    v.reserve(m.vertices());
    for (size_t i = 0; i < m.vertices(); i++)
        v.push_back(sm.add_vertex(Point(double(m.xyz[3 * i]), double(m.xyz[3 * i + 1]), double(m.xyz[3 * i + 2]))));
    for (size_t f = 0; f < m.triangles(); f++) {
        const uint32_t *t = &m.tri[3 * f];
        SM::Face_index fi = sm.add_face(v[t[0]], v[t[1]], v[t[2]]);
        if (fi == SM::null_face() || size_t(fi.idx()) != f) {
            std::fprintf(stderr, "%s: face %zu: not a manifold mesh for CGAL\n", m.name.c_str(), f);
            return false;
        }
        if (CGAL::collinear(sm.point(v[t[0]]), sm.point(v[t[1]]), sm.point(v[t[2]]))) degenerate.insert(uint32_t(f));
    }
    std::vector<std::pair<SM::Face_index, SM::Face_index>> found;
    CGAL::Polygon_mesh_processing::self_intersections(sm, std::back_inserter(found));
    for (auto &p : found) {
        uint32_t a = uint32_t(p.first.idx()), b = uint32_t(p.second.idx());
        out.insert({std::min(a, b), std::max(a, b)});
    }
    return true;
}

std::string hexpoint(const Mesh &m, uint32_t vtx) {
    char buf[128];
    std::snprintf(buf, sizeof buf, "(%a, %a, %a)", double(m.xyz[3 * vtx]), double(m.xyz[3 * vtx + 1]),
                  double(m.xyz[3 * vtx + 2]));
    return buf;
}

void show(const Mesh &m, const char *what, std::pair<uint32_t, uint32_t> p) {
    std::fprintf(stderr, "  %s: triangles %u [%u %u %u] and %u [%u %u %u]\n", what, p.first, m.tri[3 * p.first],
                 m.tri[3 * p.first + 1], m.tri[3 * p.first + 2], p.second, m.tri[3 * p.second],
                 m.tri[3 * p.second + 1], m.tri[3 * p.second + 2]);
    for (uint32_t f : {p.first, p.second})
        std::fprintf(stderr, "    %u: %s %s %s\n", f, hexpoint(m, m.tri[3 * f]).c_str(),
                     hexpoint(m, m.tri[3 * f + 1]).c_str(), hexpoint(m, m.tri[3 * f + 2]).c_str());
}

struct Totals {
    int cases = 0, failed = 0;
    size_t pairs = 0, adjacent = 0, excluded = 0;
};

// Compares glcollide with CGAL on `m`; prints one line. False on any difference.
bool check(const Mesh &m, bool inject, bool timed, Totals &tot) {
    auto t0 = std::chrono::steady_clock::now();
    PairSet want;
    std::set<uint32_t> degenerate;
    tot.cases++;
    if (!cgal_self(m, want, degenerate)) {
        tot.failed++;
        return false;
    }
    double cgal_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    auto keep = [&](const std::pair<uint32_t, uint32_t> &p) {
        return !degenerate.count(p.first) && !degenerate.count(p.second);
    };
    PairSet want_kept;
    for (auto &p : want)
        if (keep(p)) want_kept.insert(p);
    size_t adjacent = 0;
    for (auto &p : want_kept) {
        const uint32_t *a = &m.tri[3 * p.first], *b = &m.tri[3 * p.second];
        bool shares = false;
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) shares |= a[i] == b[j];
        adjacent += shares;
    }
    bool good = true;
    size_t excluded = 0;
    for (uint32_t threads : {0u, 1u}) {
        for (uint32_t per_box : {0u, 7u}) {
            bool decoy_first = per_box == 7;
            PairSet got, got_kept;
            if (!glcol_self(m, threads, per_box, decoy_first, got)) {
                good = false;
                continue;
            }
            if (inject && !got.empty()) got.erase(got.begin());
            for (auto &p : got)
                if (keep(p)) got_kept.insert(p);
            excluded = std::max(excluded, got.size() - got_kept.size());
            if (got_kept != want_kept) {
                good = false;
                std::fprintf(stderr, "%s: threads %u, %u polygons per box: glcollide %zu pairs, CGAL %zu\n",
                             m.name.c_str(), threads, per_box, got_kept.size(), want_kept.size());
                int shown = 0;
                for (auto &p : got_kept)
                    if (!want_kept.count(p) && shown++ < 3) show(m, "glcollide only", p);
                shown = 0;
                for (auto &p : want_kept)
                    if (!got_kept.count(p) && shown++ < 3) show(m, "CGAL only", p);
            }
        }
    }
    excluded = std::max(excluded, want.size() - want_kept.size());
    char timing[256] = "";
    if (timed) {
        // Epick must agree with Epeck (where no face is degenerate: CGAL's triangle tests
        // assume proper triangles).
        PairSet epick;
        double epick_s = cgal_epick(m, epick);
        if (degenerate.empty() && epick != want) {
            good = false;
            std::fprintf(stderr, "%s: CGAL Epick %zu pairs, Epeck %zu\n", m.name.c_str(), epick.size(), want.size());
        }
        double glcol_s = glcol_seconds(m);
        std::snprintf(timing, sizeof timing, "  s: CGAL Epeck %.4f Epick %.4f, glcollide %.4f", cgal_s, epick_s,
                      glcol_s);
#ifdef WITH_EMBREE
        PairSet emb;
        double emb_s = embree_self(m, emb);
        PairSet emb_kept;
        for (auto &p : emb)
            if (keep(p)) emb_kept.insert(p);
        std::printf("    Embree rtcCollide self + CGAL rule: %.4f s, %s\n", emb_s,
                    emb_kept == want_kept ? "equal to CGAL" : "DIFFERENT from CGAL (peer finding, not a failure)");
#endif
    }
    std::printf("%-44s %7zu triangles %6zu pairs (%5zu adjacent) %s%s%s\n", m.name.c_str(), m.triangles(),
                want_kept.size(), adjacent, good ? "equal" : "DIFFERENT",
                degenerate.empty() ? "" : (" (" + std::to_string(degenerate.size()) + " degenerate faces left out)").c_str(),
                timing);
    tot.pairs += want_kept.size();
    tot.adjacent += adjacent;
    tot.excluded += excluded;
    if (!good) tot.failed++;
    return good;
}

// ---- Adversarial meshes ----------------------------------------------------------------

// An n x n grid of the unit square (z = 0), two triangles per cell, alternating diagonals.
Mesh grid(int n) {
    Mesh m;
    for (int j = 0; j <= n; j++)
        for (int i = 0; i <= n; i++) {
            m.xyz.push_back(float(i) / float(n));
            m.xyz.push_back(float(j) / float(n));
            m.xyz.push_back(0.0f);
        }
    auto at = [&](int i, int j) { return uint32_t(j * (n + 1) + i); };
    for (int j = 0; j < n; j++)
        for (int i = 0; i < n; i++) {
            uint32_t a = at(i, j), b = at(i + 1, j), c = at(i + 1, j + 1), d = at(i, j + 1);
            if ((i + j) % 2) {
                m.tri.insert(m.tri.end(), {a, b, c, a, c, d});
            } else {
                m.tri.insert(m.tri.end(), {a, b, d, b, c, d});
            }
        }
    return m;
}

// The grid folded along x = 1/2: the half beyond it laid back over the other half, rising
// with slope `slope` (0: flat onto it), lowered by `drop` (> 0: it pierces the other half).
Mesh fold(int n, double slope, double drop) {
    Mesh m = grid(n);
    for (size_t i = 0; i < m.vertices(); i++) {
        double x = m.xyz[3 * i];
        if (x > 0.5) {
            m.xyz[3 * i] = float(1.0 - x);
            m.xyz[3 * i + 2] = float((x - 0.5) * slope - drop * (x - 0.5) * (x - 0.5) * 4.0);
        }
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "fold slope %g drop %g", slope, drop);
    m.name = buf;
    return m;
}

// The grid with vertex (i, j) pushed by (dx, dy, dz) grid cells: through its neighbours.
Mesh pushed(int n, int i, int j, double dx, double dy, double dz) {
    Mesh m = grid(n);
    size_t v = size_t(j * (n + 1) + i);
    m.xyz[3 * v] += float(dx / n);
    m.xyz[3 * v + 1] += float(dy / n);
    m.xyz[3 * v + 2] += float(dz / n);
    char buf[96];
    std::snprintf(buf, sizeof buf, "pushed vertex (%g, %g, %g) cells", dx, dy, dz);
    m.name = buf;
    return m;
}

// The grid folded (slope 1e-2) with one vertex of the upper half lowered exactly onto the
// lower half: onto a vertex of it, or half a cell along x, onto the middle of an edge.
// Its triangles touch non-neighbours at that point only.
Mesh pinched(int n, bool edge_middle) {
    Mesh m = fold(n, 1e-2, 0.0);
    int i = 3 * n / 4, j = n / 2;
    size_t v = size_t(j * (n + 1) + i);
    m.xyz[3 * v + 2] = 0.0f;
    if (edge_middle) m.xyz[3 * v] += 0.5f / float(n);
    m.name = std::string("pinched onto ") + (edge_middle ? "an edge" : "a vertex");
    return m;
}

// A fan of `k` slivers around a centre: a cone of height `h` over the unit circle, with
// the centre then moved to (cx, 0, cz); plus a second fan crossing it.
Mesh slivers(int k, double h, double cx, double cz) {
    Mesh m;
    auto fan = [&](double ox, double oy, double oz, double height, double tilt) {
        uint32_t c = uint32_t(m.vertices());
        m.xyz.insert(m.xyz.end(), {float(ox + cx), float(oy), float(oz + height + cz)});
        for (int s = 0; s < k; s++) {
            double a = 2 * M_PI * s / k;
            m.xyz.insert(m.xyz.end(), {float(ox + std::cos(a)), float(oy + std::sin(a)),
                                       float(oz + tilt * std::cos(a))});
        }
        for (int s = 0; s < k; s++) m.tri.insert(m.tri.end(), {c, c + 1 + s, c + 1 + (s + 1) % k});
    };
    fan(0, 0, 0, h, 0.0);
    fan(0.5, 0.2, 0.0, -h, 0.3);
    char buf[96];
    std::snprintf(buf, sizeof buf, "%d slivers h %g centre (%g, 0, %g)", k, h, cx, cz);
    m.name = buf;
    return m;
}

Mesh transformed(Mesh m, double scale, double offset) {
    for (float &x : m.xyz) x = float(double(x) * scale + offset);
    char buf[64];
    std::snprintf(buf, sizeof buf, " x%g +%g", scale, offset);
    m.name += buf;
    return m;
}

// The grid rolled into a spiral of three turns whose layers carry waves out of phase from
// one layer to the next (amplitude `amp` of the layer spacing: above 0.5 neighbouring layers
// cross along bands), as the scene bench's 92k rolled cloth: flat patches that glcollide
// proves free of self-intersection in bulk, next to real crossings.
Mesh rolled(int n, double amp) {
    Mesh m = grid(n);
    const double tau = 6.283185307179586, d = 0.02;
    for (size_t i = 0; i < m.vertices(); i++) {
        double u = m.xyz[3 * i], v = m.xyz[3 * i + 1];
        double th = 3.0 * tau * u;
        double r = 0.2 + d * th / tau + amp * d * std::sin(8.0 * tau * v + 2.5 * th);
        m.xyz[3 * i] = float(r * std::cos(th));
        m.xyz[3 * i + 1] = float(r * std::sin(th));
        m.xyz[3 * i + 2] = float(4.0 * (v - 0.5));
    }
    char buf[96];
    std::snprintf(buf, sizeof buf, "rolled, wave %g of the spacing", amp);
    m.name = buf;
    return m;
}

std::vector<Mesh> adversarial() {
    std::vector<Mesh> base;
    for (double slope : {1e-3, 1e-5, 1e-7, 0.0}) base.push_back(fold(16, slope, 0.0));
    base.push_back(fold(16, 1e-3, 1e-4));
    base.push_back(fold(16, 1e-7, 1e-7));
    for (auto d : {std::vector<double>{1.5, 0.3, 0.0}, {0.7, 0.7, 1e-6}, {0.0, 0.0, -1e-7}, {1.0, 1.0, 0.0},
                   {-2.2, 0.4, 1e-3}})
        base.push_back(pushed(12, 5, 6, d[0], d[1], d[2]));
    base.push_back(pinched(16, false));
    base.push_back(pinched(16, true));
    base.push_back(slivers(400, 0.2, 0.0, 0.0));
    base.push_back(slivers(400, 1e-5, 1.3, 0.0));
    base.push_back(slivers(1000, 0.0, 0.0, 0.0));
    base.push_back(rolled(60, 0.52));
    base.push_back(rolled(60, 0.45));
    std::vector<Mesh> all;
    for (const Mesh &m : base) {
        all.push_back(m);
        all.back().name += " x1";
        all.push_back(transformed(m, 1e-4, 0.0));
        all.push_back(transformed(m, 1e4, 0.0));
        all.push_back(transformed(m, 1.0, 1e5));
    }
    return all;
}

}  // namespace

int main(int argc, char **argv) {
    std::string dir = "../shared/meshes";
    std::string only;
    bool inject = false, timed = false;
    std::vector<std::string> objs;
    for (int i = 1; i < argc; i++) {
        if (!std::strcmp(argv[i], "--meshes") && i + 1 < argc) {
            dir = argv[++i];
        } else if (!std::strcmp(argv[i], "--only") && i + 1 < argc) {
            only = argv[++i];
        } else if (!std::strcmp(argv[i], "--inject")) {
            inject = true;
        } else if (!std::strcmp(argv[i], "--time")) {
            timed = true;
        } else if (!std::strcmp(argv[i], "--obj") && i + 1 < argc) {
            objs.push_back(argv[++i]);
        } else {
            std::fprintf(stderr, "usage: %s [--meshes DIR] [--only NAME] [--inject] [--time] [--obj FILE]...\n",
                         argv[0]);
            return 2;
        }
    }
    if (glcol_abi_version() != GLCOL_ABI_VERSION) {
        std::fprintf(stderr, "library and header differ\n");
        return 2;
    }
    std::vector<Mesh> cases;
    for (const std::string &path : objs) {
        Mesh m;
        m.name = path;
        if (!load(path, m)) return 2;
        cases.push_back(std::move(m));
    }
    const char *sims[][3] = {{"cloth-funnel", "227", "0123"}, {"cloth-funnel", "228", "0"},
                             {"armadillo-rollers", "326", "0"}, {"rod-twist", "3036", "0"}};
    for (auto &s : sims) {
        if (!objs.empty()) break;
        for (const char *part = s[2]; *part; part++) {
            Mesh m;
            m.name = std::string(s[0]) + " " + s[1] + " part0" + *part;
            if (!only.empty() && m.name.find(only) == std::string::npos) continue;
            std::string path = dir + "/sim/" + s[0] + "/frame" + s[1] + "_part0" + *part + ".obj";
            if (!load(path, m)) return 2;
            cases.push_back(std::move(m));
        }
    }
    // The 92k-triangle cloth crumpled over a ball (bench/data/crumpled-cloth, in the
    // repository: raw little-endian float positions of a 216 x 216 vertex grid, its README
    // gives the triangulation): 78,000 intersecting pairs, the heavy self-contact workload
    // of the benchmarks. Read relative to the current directory (the repository's root,
    // where the test script runs); skipped when absent.
    for (int f = 0; f < 2 && objs.empty(); f++) {
        Mesh m;
        m.name = "crumpled cloth frame" + std::to_string(f);
        if (!only.empty() && m.name.find(only) == std::string::npos) continue;
        std::FILE *in = std::fopen(("bench/data/crumpled-cloth/frame" + std::to_string(f) + ".f32").c_str(), "rb");
        if (!in) continue;
        const uint32_t n = 216;
        m.xyz.resize(3 * n * n);
        size_t got = std::fread(m.xyz.data(), sizeof(float), m.xyz.size(), in);
        std::fclose(in);
        if (got != m.xyz.size()) {
            std::fprintf(stderr, "%s: short read (%zu of %zu floats)\n", m.name.c_str(), got, m.xyz.size());
            return 2;
        }
        for (uint32_t j = 0; j + 1 < n; j++)
            for (uint32_t i = 0; i + 1 < n; i++) {
                uint32_t v = j * n + i;
                m.tri.insert(m.tri.end(), {v, v + 1, v + n + 1, v, v + n + 1, v + n});
            }
        cases.push_back(std::move(m));
    }
    // A real cloth tangled: every vertex of the cloth of frame 227 moved by a pseudo-random
    // step of up to 0.6 of its mean edge length (folds, pushed-through vertices, crossings
    // between neighbours, all on real connectivity).
    for (size_t c = 0; c < cases.size(); c++) {
        if (cases[c].name != "cloth-funnel 227 part00") continue;
        Mesh m = cases[c];
        double sum = 0;
        for (size_t f = 0; f < m.triangles(); f++)
            for (int k = 0; k < 3; k++) {
                const float *a = &m.xyz[3 * m.tri[3 * f + k]], *b = &m.xyz[3 * m.tri[3 * f + (k + 1) % 3]];
                sum += std::sqrt(double((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                                        (a[2] - b[2]) * (a[2] - b[2])));
            }
        double step = 0.6 * sum / double(3 * m.triangles());
        uint64_t seed = 0x9E3779B97F4A7C15ull;
        for (float &x : m.xyz) {
            seed ^= seed << 13, seed ^= seed >> 7, seed ^= seed << 17;
            x = float(double(x) + step * (double(seed >> 11) / double(1ull << 53) - 0.5) * 2.0);
        }
        m.name += " jittered";
        cases.push_back(std::move(m));
        break;
    }
    for (Mesh &m : adversarial())
        if (objs.empty() && (only.empty() || m.name.find(only) != std::string::npos)) cases.push_back(std::move(m));
    Totals tot;
    for (const Mesh &m : cases) check(m, inject, timed, tot);
    std::printf("selfcheck: %d meshes, %zu self pairs (%zu adjacent), %zu pairs with a degenerate face left "
                "out; %d different\n",
                tot.cases, tot.pairs, tot.adjacent, tot.excluded, tot.failed);
    return tot.failed ? 1 : 0;
}
