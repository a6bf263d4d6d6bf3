// contact_cost: what glcol_query_geometry costs next to the query it describes (issue 13:
// at most 15% of the query time), and the peers' contact generation on the same frames:
//   glcollide   CPU backend, threads = 1, epsilon 0: glcol_query (A as the reference), then
//               glcol_query_geometry for all its contacts
//   FCL         BVHModel<AABBd> refit, collide() with unlimited contacts, enable_contact
//               false (pairs only) and true (pos, normal, penetration_depth per pair)
//   Bullet      GImpact quantized BVH refit; find_collision + the exact CGAL test (pairs),
//               and GImpact's own triangle contact generation on the same candidates
//               (find_triangle_collision_clip_method: points, normal, penetration depth;
//               what btGImpactCollisionAlgorithm runs per triangle pair)
// Scenes: the benchmark's heavy case (colon vs small intestine, 20k each) and instrument
// scenes (bench_scenes --quick: scissors blade into face 1k, teapot 4k, gallbladder 15k;
// plus the cross-check's forceps_jaw into colon). Updates are not timed. Each timed call is
// repeated --reps times per frame (the query again before each geometry call, since the
// geometry of one answer is computed once) and the least time kept; the table gives
// medians over the frames and the ratio of the sums. Wall-clock time on a shared machine:
// read the ratios, not the absolute values.
//
//   contact_cost [--meshes DIR] [--frames N] [--reps N] [--only TEXT] [--markdown FILE] [--no-peers]
// (--no-peers: glcollide alone, its columns only meaningful; for profiling and A/B runs)
#include "peer_contacts.hpp"
#include "scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

using namespace peers;

namespace {

void check(GlcolStatus s, const char *what) {
    if (s != GLCOL_STATUS_OK)
        throw std::runtime_error(std::string(what) + ": " + glcol_status_name(s) + ": " + glcol_last_error_message());
}

struct Result {
    std::string name;
    size_t ta = 0, tb = 0;
    int frames = 0;
    double pairs = 0;                   // glcollide contacts per frame (median)
    std::vector<double> q, g;           // glcollide query, geometry (us per frame)
    std::vector<double> fp, fc;         // FCL pairs only, with contacts
    std::vector<double> bq, bn;         // Bullet pairs (+ exact test), native contacts
    size_t fcl_contacts = 0, fcl_zero = 0, fcl_vertex = 0;
    size_t glc_deep = 0, glc_contacts = 0; // glcollide: intersecting pairs with depth > 0
};

double sum(const std::vector<double> &v) {
    double s = 0;
    for (double x : v) s += x;
    return s;
}

Result run(const Scene &S, int frames, int reps, bool peers) {
    Result r;
    r.name = S.name;
    r.ta = S.A.mesh.ntri();
    r.tb = S.B.mesh.ntri();
    r.frames = frames;
    Frame fr;
    S.frame(0, fr);
    GlcolSceneDesc sd;
    glcol_scene_desc_init(&sd);
    sd.backend = GLCOL_BACKEND_CPU;
    sd.epsilon = 0;
    sd.threads = 1;
    GlcolScene *scene = nullptr;
    check(glcol_scene_create(&sd, &scene), "glcol_scene_create");
    GlcolMeshId ids[2];
    const Mesh *ms[2] = {&S.A.mesh, &S.B.mesh};
    for (int m = 0; m < 2; m++) {
        GlcolMeshDesc d;
        glcol_mesh_desc_init(&d);
        d.positions = m ? fr.b.data() : fr.a.data();
        d.vertex_count = ms[m]->nv();
        d.indices = ms[m]->poly.data();
        d.polygon_count = ms[m]->npoly();
        d.vertices_per_polygon = ms[m]->vpp;
        check(glcol_mesh_create(scene, &d, &ids[m]), "glcol_mesh_create");
    }
    std::unique_ptr<Engine> fcl(make_fcl());
    std::unique_ptr<ContactEngine> fclc(make_fcl_contacts());
    std::unique_ptr<BulletEngine> bullet(make_bullet(0, 0, true));
    fcl->build(S.A.mesh, S.B.mesh, fr);
    fclc->build(S.A.mesh, S.B.mesh, fr);
    bullet->build(S.A.mesh, S.B.mesh, fr);
    std::vector<Key> out;
    std::vector<double> npairs;
    for (int f = 0; f < frames; f++) {
        S.frame(f, fr);
        check(glcol_mesh_update_positions(scene, ids[0], fr.a.data(), 0, ms[0]->nv(), 0), "update a");
        check(glcol_mesh_update_positions(scene, ids[1], fr.b.data(), 0, ms[1]->nv(), 0), "update b");
        double tq = HUGE_VAL, tg = HUGE_VAL;
        size_t n = 0;
        for (int k = 0; k < reps; k++) {
            const GlcolContact *c = nullptr;
            Timer t;
            check(glcol_query(scene, ids[0], &c, &n), "glcol_query");
            tq = std::min(tq, t.us());
            const GlcolContactGeometry *g = nullptr;
            size_t gn = 0;
            Timer t2;
            check(glcol_query_geometry(scene, &g, &gn), "glcol_query_geometry");
            tg = std::min(tg, t2.us());
            if (gn != n) throw std::runtime_error("geometry count differs from the contact count");
            if (k == 0)
                for (size_t i = 0; i < gn; i++) {
                    r.glc_contacts++;
                    r.glc_deep += (g[i].flags & GLCOL_CONTACT_INTERSECTING) && g[i].depth > 0;
                }
        }
        r.q.push_back(tq);
        r.g.push_back(tg);
        npairs.push_back(double(n));
        if (!peers) continue;
        // FCL, pairs only and with contacts.
        fcl->prepare(fr);
        fcl->update(fr);
        fclc->update(fr);
        double tp = HUGE_VAL, tc = HUGE_VAL;
        ContactStats cs;
        for (int k = 0; k < reps; k++) {
            Timer t;
            fcl->query(out);
            tp = std::min(tp, t.us());
            Timer t2;
            cs = fclc->query();
            tc = std::min(tc, t2.us());
        }
        r.fp.push_back(tp);
        r.fc.push_back(tc);
        r.fcl_contacts += cs.contacts;
        r.fcl_zero += cs.zero_depth;
        r.fcl_vertex += cs.at_vertex;
        // Bullet: pairs (find_collision + exact test), then GImpact's contacts on the candidates.
        bullet->prepare(fr);
        bullet->update(fr);
        double bq = HUGE_VAL, bn = HUGE_VAL;
        for (int k = 0; k < reps; k++) {
            Timer t;
            bullet->query(out);
            bq = std::min(bq, t.us());
            Timer t2;
            bullet->native(out);
            bn = std::min(bn, t2.us());
        }
        r.bq.push_back(bq);
        r.bn.push_back(bn);
    }
    r.pairs = median(npairs);
    glcol_scene_destroy(scene);
    return r;
}

} // namespace

int main(int argc, char **argv) {
    std::string dir = "../shared/meshes", only, md;
    int frames = 40, reps = 3;
    bool peers = true;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                fprintf(stderr, "%s needs a value\n", a.c_str());
                exit(2);
            }
            return argv[++i];
        };
        if (a == "--meshes") dir = next();
        else if (a == "--frames") frames = atoi(next().c_str());
        else if (a == "--reps") reps = atoi(next().c_str());
        else if (a == "--only") only = next();
        else if (a == "--markdown") md = next();
        else if (a == "--no-peers") peers = false;
        else {
            fprintf(stderr, "usage: contact_cost [--meshes DIR] [--frames N] [--reps N] [--only TEXT] [--markdown FILE] [--no-peers]\n");
            return 2;
        }
    }
    if (frames < 1 || reps < 1) {
        fprintf(stderr, "--frames and --reps must be >= 1\n");
        return 2;
    }
    std::vector<Result> rs;
    try {
        std::vector<Scene> scenes = bench_scenes(dir, only, true);
        const double d1[3] = {-0.2, 1, 0.4};
        if (only.empty() || std::string("forceps_jaw / colon").find(only) != std::string::npos)
            scenes.push_back(instrument_vs_organ(load_obj(dir, "forceps_jaw"), load_obj(dir, "colon"), d1, 100));
        for (auto &S : scenes) {
            if (!only.empty() && S.name.find(only) == std::string::npos) continue;
            rs.push_back(run(S, frames, reps, peers));
            fprintf(stderr, "%s done\n", S.name.c_str());
        }
    } catch (const std::exception &e) {
        fprintf(stderr, "contact_cost: %s\n", e.what());
        return 1;
    }
    std::string o;
    char buf[1024];
    snprintf(buf, sizeof buf,
             "| scene | triangles A x B | frames | pairs/frame | glcollide query us | + geometry us | geometry / query | "
             "FCL collide us | FCL + contacts us | FCL contacts / pairs-only | FCL depth = 0 | Bullet pairs us | "
             "GImpact contacts us |\n|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    o += buf;
    for (auto &r : rs) {
        snprintf(buf, sizeof buf,
                 "| %s | %zu x %zu | %d | %.0f | %.2f | %.2f | %.1f%% (sums %.1f%%) | %.1f | %.1f | %.2fx | %.0f%% | %.1f | "
                 "%.1f |\n",
                 r.name.c_str(), r.ta, r.tb, r.frames, r.pairs, median(r.q), median(r.g),
                 100 * median(r.g) / median(r.q), 100 * sum(r.g) / sum(r.q), median(r.fp), median(r.fc),
                 median(r.fc) / median(r.fp), r.fcl_contacts ? 100.0 * double(r.fcl_zero) / double(r.fcl_contacts) : 0.0,
                 median(r.bq), median(r.bn));
        o += buf;
    }
    o += "\nglcollide intersecting pairs with depth > 0, FCL contact positions on a triangle vertex:\n\n";
    for (auto &r : rs) {
        snprintf(buf, sizeof buf, "- %s: glcollide %zu of %zu pairs with depth > 0; FCL %zu of %zu positions on a vertex\n",
                 r.name.c_str(), r.glc_deep, r.glc_contacts, r.fcl_vertex, r.fcl_contacts);
        o += buf;
    }
    fputs(o.c_str(), stdout);
    if (!md.empty()) {
        FILE *f = fopen(md.c_str(), "w");
        if (!f) {
            fprintf(stderr, "cannot write %s\n", md.c_str());
            return 1;
        }
        fputs(o.c_str(), f);
        fclose(f);
    }
    return 0;
}
