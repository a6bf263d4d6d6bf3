// crosscheck: glcollide against FCL and Bullet (from Debian) and an exact CGAL reference.
//
// For every scene (two meshes, A = glcollide's reference mesh, and B; same vertices, same
// placement and the same deformation for every library, frame by frame) it asks for the set
// of intersecting polygon pairs (a of A, b of B):
//   exact      sweep over exact boxes + CGAL::do_intersect, exact predicates (exact.cpp)
//   exact      (on small scenes every 10th frame is also checked against brute force)
//   glc e=0    glcollide, CPU backend, epsilon 0: documented as exactly `exact`; asked with
//              A as the reference, and again with B ("B-ref", pairs swapped back)
//   glc e      glcollide, CPU backend, epsilon e > 0: documented as a superset of `exact`
//              whose extra pairs lie within e/2 of each other
//   FCL        BVHModel<AABB>, refit each frame, all contacts (fcl_engine.cpp)
//   Bullet     GImpact quantized BVH, refit each frame (rebuilt when a mesh leaves its
//              quantization frame), find_collision + exact test (bullet_engine.cpp)
//   Bullet refit-only   the same, never rebuilt (finding only)
//   GImpact native      the same candidates through GImpact's own triangle test (finding only)
// Every pair on which a library and `exact` disagree is judged on its own with exact
// rationals (exact.cpp: judge): cross (truly intersecting), touch (touching: shared
// vertex/edge, contact on the boundary, coplanar overlap), band (apart, distance <= e/2),
// apart (distance > e/2). glcollide fails on any disagreement at e=0, and at e on any
// missed pair or any extra pair outside the band; the peers' disagreements are findings.
//
// Quads: glcollide gets the quads; the peers and the reference get triangles 2q = (v0,v1,v2)
// and 2q+1 = (v0,v2,v3) of quad q (glcollide's documented split), and a triangle pair
// (s, t) counts as polygon pair (s/2, t/2).
//
// The engines, the scenes and the exact judge are the peer harness (../peers, README.md
// there), which the benchmark (bench/peers) shares.
//
//   crosscheck [--meshes DIR] [--frames N] [--only TEXT] [--examples N] [--markdown FILE]
#include "scenes.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

using namespace peers;

namespace {

enum Lib { L_EXACT, L_GLC0, L_GLC0R, L_GLCE, L_FCL, L_BULLET, L_BULLET_RO, L_NATIVE, NLIB };
const char *lib_name[NLIB] = {"exact",  "glc e=0", "glc e=0 B-ref", "glc e",
                              "FCL",    "Bullet",  "Bullet refit-only", "GImpact native"};
// glcollide's own verdicts: any disagreement at e=0 (either mesh as the reference); at e > 0
// a missed pair or an extra pair farther apart than e/2.
bool is_failure(int lib, bool missed, Class c) {
    if (lib == L_GLC0 || lib == L_GLC0R) return true;
    if (lib == L_GLCE) return missed || c == APART;
    return false;
}

struct Example {
    int frame;
    Key pair;
    bool missed;
    Verdict v;
    std::string repro; // for glcollide failures: both polygons' float corners, exactly
};

// The corners of polygon p as glcollide got them (C99 hex floats: exact, and valid C).
std::string corners(const Mesh &M, const std::vector<float> &pos, uint32_t p) {
    std::ostringstream o;
    char buf[160];
    for (uint32_t j = 0; j < M.vpp; j++) {
        uint32_t v = M.poly[size_t(p) * M.vpp + j];
        snprintf(buf, sizeof buf, "%s{%a, %a, %a}", j ? ", " : "", double(pos[3 * v]), double(pos[3 * v + 1]),
                 double(pos[3 * v + 2]));
        o << buf;
    }
    return o.str();
}

struct LibStats {
    long long pairs = 0;
    long long miss[NCLASS] = {}, extra[NCLASS] = {};
    std::vector<Example> examples;
    std::vector<double> us;
    bool any() const {
        for (int c = 0; c < NCLASS; c++)
            if (miss[c] || extra[c]) return true;
        return false;
    }
};

struct SceneResult {
    std::string name, kind;
    size_t npa, npb;
    uint32_t vpa, vpb;
    int frames;
    float eps;
    LibStats lib[NLIB];
    long long exact_touch = 0, exact_coplanar = 0;
    double glce_max_extra = 0; // largest exact distance of glc e's extra pairs
    int bullet_rebuilds = 0, bullet_out_of_frame = 0;
    long long glc_fail = 0;
    double seconds = 0;
};

void to_poly(const Mesh &A, const Mesh &B, const std::vector<Key> &tri_pairs, std::vector<Key> &out) {
    out.clear();
    out.reserve(tri_pairs.size());
    for (Key k : tri_pairs) out.push_back(key(A.tri_poly[key_a(k)], B.tri_poly[key_b(k)]));
    sort_unique(out);
}

std::string fmt_disagree(const LibStats &s) {
    std::ostringstream o;
    const char *sep = "";
    for (int c = 0; c < NCLASS; c++)
        if (s.miss[c]) o << sep << "-" << s.miss[c] << " " << class_name[c], sep = ", ";
    for (int c = 0; c < NCLASS; c++)
        if (s.extra[c]) o << sep << "+" << s.extra[c] << " " << class_name[c], sep = ", ";
    std::string r = o.str();
    return r.empty() ? "0" : r;
}

SceneResult run(const Scene &S, size_t max_examples, bool classify_exact, bool inject) {
    Timer total;
    SceneResult R;
    R.name = S.name;
    R.kind = S.kind;
    R.npa = S.A.mesh.npoly();
    R.npb = S.B.mesh.npoly();
    R.vpa = S.A.mesh.vpp;
    R.vpb = S.B.mesh.vpp;
    R.frames = S.frames;
    R.eps = S.eps;
    R.exact_touch = classify_exact ? 0 : -1;
    const Mesh &A = S.A.mesh, &B = S.B.mesh;
    const double half = double(S.eps) / 2;

    // Every library starts from frame 0 and, from frame 1 on, gets each frame (prepare) and
    // refits (update) before it is asked; the times are of prepare + update + query.
    Frame fr;
    S.frame(0, fr);
    std::unique_ptr<GlcolEngine> g0(make_glcol(GLCOL_BACKEND_CPU, 0.0f, 0)), ge(make_glcol(GLCOL_BACKEND_CPU, S.eps, 0));
    std::unique_ptr<Engine> fcl(make_fcl());
    std::unique_ptr<BulletEngine> bul(make_bullet(0, 0, true)), bro(make_bullet(0, 0, false));
    Engine *all[] = {g0.get(), ge.get(), fcl.get(), bul.get(), bro.get()};
    for (Engine *e : all) e->build(A, B, fr);

    std::vector<Key> set[NLIB], tmp;
    for (int f = 0; f < S.frames; f++) {
        if (f > 0) S.frame(f, fr);
        const std::vector<float> &fa = fr.a, &fb = fr.b;
        const double *da = fr.ad.data(), *db = fr.bd.data();
        auto ask = [&](Engine &e, int lib, std::vector<Key> &out) {
            Timer t;
            if (f > 0) {
                e.prepare(fr);
                e.update(fr);
            }
            e.query(out);
            R.lib[lib].us.push_back(t.us());
        };
        {
            Timer t;
            exact_pairs(A, da, B, db, tmp);
            to_poly(A, B, tmp, set[L_EXACT]);
            R.lib[L_EXACT].us.push_back(t.us());
            if (f % 10 == 0 && A.ntri() * B.ntri() <= 400000) { // small scenes: sweep vs brute force
                std::vector<Key> all;
                for (uint32_t i = 0; i < A.ntri(); i++)
                    for (uint32_t j = 0; j < B.ntri(); j++)
                        if (exact_tri_intersect(da, &A.tri[3 * i], db, &B.tri[3 * j])) all.push_back(key(i, j));
                if (all != tmp) throw std::runtime_error("exact reference: the sweep lost or invented pairs");
            }
        }
        ask(*g0, L_GLC0, set[L_GLC0]);
        sort_unique(set[L_GLC0]); // sorted and unique by contract (A as reference); cheap
        g0->query_from_b(set[L_GLC0R]);
        sort_unique(set[L_GLC0R]);
        ask(*ge, L_GLCE, set[L_GLCE]);
        sort_unique(set[L_GLCE]);
        if (inject && !set[L_GLCE].empty()) { // self-test of the checker: lose one pair
            set[L_GLC0].erase(set[L_GLC0].begin());
            set[L_GLCE].erase(set[L_GLCE].begin());
        }
        ask(*fcl, L_FCL, tmp);
        to_poly(A, B, tmp, set[L_FCL]);
        ask(*bul, L_BULLET, tmp); // find_collision + the exact test
        to_poly(A, B, tmp, set[L_BULLET]);
        bul->native(tmp); // GImpact's own test on the same candidates
        to_poly(A, B, tmp, set[L_NATIVE]);
        ask(*bro, L_BULLET_RO, tmp);
        to_poly(A, B, tmp, set[L_BULLET_RO]);

        // Judge every pair on which a library and the exact reference disagree.
        std::unordered_map<Key, Verdict> cache;
        auto verdict = [&](Key k) {
            auto it = cache.find(k);
            if (it != cache.end()) return it->second;
            Verdict v = judge(A, da, key_a(k), B, db, key_b(k), half);
            cache.emplace(k, v);
            return v;
        };
        const std::vector<Key> &ex = set[L_EXACT];
        R.lib[L_EXACT].pairs += long(ex.size());
        if (classify_exact)
            for (Key k : ex) {
                Verdict v = verdict(k);
                if (v.cls == TOUCH) R.exact_touch++;
                if (v.coplanar) R.exact_coplanar++;
            }
        for (int l = L_GLC0; l < NLIB; l++) {
            LibStats &st = R.lib[l];
            const std::vector<Key> &s = set[l];
            st.pairs += long(s.size());
            std::vector<Key> miss, extra;
            std::set_difference(ex.begin(), ex.end(), s.begin(), s.end(), std::back_inserter(miss));
            std::set_difference(s.begin(), s.end(), ex.begin(), ex.end(), std::back_inserter(extra));
            for (int pass = 0; pass < 2; pass++)
                for (Key k : pass == 0 ? miss : extra) {
                    Verdict v = verdict(k);
                    bool met = v.cls == CROSS || v.cls == TOUCH;
                    if (met != (pass == 0))
                        throw std::runtime_error("the exact reference and the judge disagree on a pair");
                    (pass == 0 ? st.miss : st.extra)[v.cls]++;
                    if (l == L_GLCE && pass == 1) R.glce_max_extra = std::max(R.glce_max_extra, v.dist);
                    bool fail = is_failure(l, pass == 0, v.cls);
                    if (fail) R.glc_fail++;
                    if (st.examples.size() < max_examples || (fail && st.examples.size() < 4 * max_examples))
                        st.examples.push_back({f, k, pass == 0, v,
                                               fail ? "A: " + corners(A, fa, key_a(k)) + "\n        B: " +
                                                          corners(B, fb, key_b(k))
                                                    : std::string()});
                }
        }
    }
    R.bullet_rebuilds = bul->rebuilds();
    R.bullet_out_of_frame = bro->rebuilds();
    R.seconds = total.us() / 1e6;
    return R;
}

std::string shape(const SceneResult &r) {
    std::ostringstream o;
    o << r.npa << (r.vpa == 4 ? "q" : "") << " x " << r.npb << (r.vpb == 4 ? "q" : "");
    return o.str();
}

void table(FILE *out, const std::vector<SceneResult> &rs) {
    fprintf(out, "| scene | polygons A x B | frames | e | exact (touching) |");
    for (int l = L_GLC0; l < NLIB; l++) fprintf(out, " %s |", lib_name[l]);
    fprintf(out, " glc e: farthest extra / (e/2) |");
    fprintf(out, "\n|---|---|--:|--:|--:|");
    for (int l = L_GLC0; l < NLIB; l++) fprintf(out, "--:|");
    fprintf(out, "--:|");
    fprintf(out, "\n");
    for (const auto &r : rs) {
        fprintf(out, "| %s | %s | %d | %.3g | %lld", r.name.c_str(), shape(r).c_str(), r.frames, double(r.eps),
                r.lib[L_EXACT].pairs);
        if (r.exact_touch >= 0) fprintf(out, " (%lld)", r.exact_touch);
        fprintf(out, " |");
        for (int l = L_GLC0; l < NLIB; l++) fprintf(out, " %lld |", r.lib[l].pairs);
        fprintf(out, " %.3f |\n", r.glce_max_extra / (double(r.eps) / 2));
    }
}

void disagreement_table(FILE *out, const std::vector<SceneResult> &rs) {
    fprintf(out, "| scene |");
    for (int l = L_GLC0; l < NLIB; l++) fprintf(out, " %s |", lib_name[l]);
    fprintf(out, "\n|---|");
    for (int l = L_GLC0; l < NLIB; l++) fprintf(out, "---|");
    fprintf(out, "\n");
    for (const auto &r : rs) {
        fprintf(out, "| %s |", r.name.c_str());
        for (int l = L_GLC0; l < NLIB; l++) fprintf(out, " %s |", fmt_disagree(r.lib[l]).c_str());
        fprintf(out, "\n");
    }
}

void timing_table(FILE *out, const std::vector<SceneResult> &rs) {
    fprintf(out, "| scene | exact | glc e=0 | glc e | FCL | Bullet (+exact) | Bullet rebuilds | "
                 "refit-only: frames out of frame | wall s |\n");
    fprintf(out, "|---|--:|--:|--:|--:|--:|--:|--:|--:|\n");
    for (const auto &r : rs) {
        fprintf(out, "| %s |", r.name.c_str());
        for (int l : {L_EXACT, L_GLC0, L_GLCE, L_FCL, L_BULLET}) fprintf(out, " %.2f |", median(r.lib[l].us) / 1e3);
        fprintf(out, " %d | %d | %.1f |\n", r.bullet_rebuilds, r.bullet_out_of_frame, r.seconds);
    }
}

} // namespace

const char *usage =
    "usage: crosscheck [options]\n"
    "  --meshes DIR      real meshes (default ../shared/meshes)\n"
    "  --frames N        frames per scene (default: each scene's own, >= 100)\n"
    "  --only TEXT       only the scenes whose name contains TEXT\n"
    "  --pair A.obj B.obj  instead of the built-in scenes: A and B as they are (a shared frame),\n"
    "                    opposite warps; repeatable\n"
    "  --tool T.obj O.obj  instead of the built-in scenes: instrument T placed into O's surface\n"
    "                    (scaled to 1/10 of O's diagonal), moving and bending; repeatable\n"
    "  --examples N      judged examples printed per library and scene (default 3)\n"
    "  --no-classify     do not classify the exact pairs (touching count)\n"
    "  --inject          self-test: drop one glcollide pair per frame; must exit 1\n"
    "  --markdown FILE   also write the two summary tables there\n";

int main(int argc, char **argv) {
    std::string dir = "../shared/meshes", only, md;
    int frames = 0;
    size_t examples = 3;
    bool classify = true, inject = false;
    std::vector<std::function<Scene()>> custom;
    for (int i = 1; i < argc; i++) {
        std::string a = argv[i];
        auto next = [&]() -> std::string {
            if (i + 1 >= argc) {
                fprintf(stderr, "%s needs a value\n%s", a.c_str(), usage);
                exit(2);
            }
            return argv[++i];
        };
        if (a == "--meshes") dir = next();
        else if (a == "--frames") frames = atoi(next().c_str());
        else if (a == "--only") only = next();
        else if (a == "--examples") examples = size_t(atoi(next().c_str()));
        else if (a == "--markdown") md = next();
        else if (a == "--no-classify") classify = false;
        else if (a == "--inject") inject = true;
        else if (a == "--pair" || a == "--tool") {
            std::string x = next(), y = next();
            bool tool = a == "--tool";
            custom.push_back([x, y, tool, &frames] {
                int fr = frames > 0 ? frames : 100;
                Mesh mx = load_obj(x), my = load_obj(y);
                static const double d[3] = {1, 0.3, 0.2};
                return tool ? instrument_vs_organ(mx, my, d, fr) : organ_vs_organ(mx, my, fr);
            });
        } else {
            fprintf(stderr, "%s", usage);
            return 2;
        }
    }
    printf("crosscheck: glcollide %s against FCL 0.7 (BVHModel<AABB>), Bullet 3.24 (GImpact, double) and CGAL exact\n",
           glcol_version());
    std::vector<SceneResult> rs;
    long long fails = 0;
    try {
        for (auto &make : custom.empty() ? crosscheck_scenes(dir, frames) : custom) {
            Scene S = make();
            if (!only.empty() && S.name.find(only) == std::string::npos) continue;
            SceneResult r = run(S, examples, classify, inject);
            fails += r.glc_fail;
            printf("%-44s %3d fr  exact %7lld  glc0 %7lld  glcE %7lld  fcl %7lld  bullet %7lld  native %7lld  %5.1fs%s\n",
                   r.name.c_str(), r.frames, r.lib[L_EXACT].pairs, r.lib[L_GLC0].pairs, r.lib[L_GLCE].pairs,
                   r.lib[L_FCL].pairs, r.lib[L_BULLET].pairs, r.lib[L_NATIVE].pairs, r.seconds,
                   r.glc_fail ? "  GLCOLLIDE DISAGREES" : "");
            fflush(stdout);
            rs.push_back(std::move(r));
        }
    } catch (const std::exception &e) {
        fprintf(stderr, "crosscheck: error: %s\n", e.what());
        return 2;
    }

    printf("\n## Pairs per library (summed over all frames)\n\n");
    table(stdout, rs);
    printf("\n## Disagreements with the exact reference, judged pair by pair "
           "(-N missed, +N extra; cross / touch / band = within e/2 / apart = farther than e/2)\n\n");
    disagreement_table(stdout, rs);
    printf("\n## Median milliseconds per frame (refit + query; exact = sweep + CGAL)\n\n");
    timing_table(stdout, rs);

    printf("\n## Judged disagreements (examples: frame, polygon of A, polygon of B, class, exact distance)\n\n");
    for (const auto &r : rs)
        for (int l = L_GLC0; l < NLIB; l++) {
            const LibStats &s = r.lib[l];
            if (!s.any()) continue;
            printf("%s, %s: %s\n", r.name.c_str(), lib_name[l], fmt_disagree(s).c_str());
            for (const auto &e : s.examples)
                printf("    frame %d  (%u, %u)  %s  %s%s  distance %.3g%s\n", e.frame, key_a(e.pair), key_b(e.pair),
                       e.missed ? "missed" : "extra", class_name[e.v.cls], e.v.coplanar ? " (coplanar)" : "",
                       e.v.dist, is_failure(l, e.missed, e.v.cls) ? "  <- glcollide FAILS" : "");
            for (const auto &e : s.examples)
                if (!e.repro.empty()) printf("      frame %d  (%u, %u):\n        %s\n", e.frame, key_a(e.pair),
                                              key_b(e.pair), e.repro.c_str());
        }
    if (!md.empty()) {
        FILE *f = fopen(md.c_str(), "w");
        if (f) {
            table(f, rs);
            fprintf(f, "\n");
            disagreement_table(f, rs);
            fclose(f);
        }
    }
    if (fails) {
        printf("\nFAIL: %lld glcollide pair verdicts outside its documented semantics\n", fails);
        return 1;
    }
    printf("\nOK: glcollide agrees with the exact reference on every scene (e=0: identical sets, either mesh "
           "as the reference; e>0: superset, every extra pair within e/2)\n");
    return 0;
}
