// glcol_peers: see bench/README.md. Writes <out>/peers.csv (one row per scene x engine x
// configuration) and, with --dump DIR, the scenes' frames and exact answers for the parry
// bench (benches/parry.rs), so both programs time the same frames. The engines, the scenes
// and the exact answer are the peer harness (examples-c/peers, README.md there), which the
// cross-check (examples-c/crosscheck) shares.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <set>
#include <stdexcept>

#include "scenes.hpp"

using namespace peers;

namespace {
struct Opts {
  std::string meshes = "../shared/meshes", out = "bench-results", dump, only;
  double scale = 1.0;   // frame counts are multiplied by this
  double budget = 60;   // seconds per (scene, engine) run at most
  bool quick = false, gl = true, sweeps = true, peers = true;
} opt;

struct Row {
  std::string scene, group, engine;
  double eps_rel = 0, eps_abs = 0;
  uint32_t leaf = 0;
  size_t tris_a = 0, tris_b = 0;
  int frames = 0;
  double update_us = NAN, query_us = NAN, total_us = NAN, pairs = NAN;
  int check_frames = 0;
  size_t ref_pairs = 0, missed = 0, extra = 0;
  double max_extra_dist = 0;
  size_t bytes = 0;
  std::string note;
};
std::vector<Row> rows;

std::string csv_escape(const std::string& s) {
  std::string o = "\"";
  for (char c : s) o += c == '"' ? std::string("\"\"") : std::string(1, c);
  return o + "\"";
}

void write_csv() {
  std::string path = opt.out + "/peers.csv";
  FILE* f = fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("cannot write " + path);
  fprintf(f, "scene,group,engine,eps_rel,eps_abs,leaf,tris_a,tris_b,frames,update_us,query_us,total_us,pairs_median,"
             "check_frames,ref_pairs,missed,extra,max_extra_dist,max_extra_dist_rel,bytes,bytes_per_polygon,note\n");
  for (auto& r : rows) {
    double ext = 0;
    fprintf(f, "%s,%s,%s,%g,%g,%u,%zu,%zu,%d,%.3f,%.3f,%.3f,%.1f,%d,%zu,%zu,%zu,%.6g,%.6g,%zu,%.2f,%s\n", r.scene.c_str(),
            r.group.c_str(), r.engine.c_str(), r.eps_rel, r.eps_abs, r.leaf, r.tris_a, r.tris_b, r.frames, r.update_us,
            r.query_us, r.total_us, r.pairs, r.check_frames, r.ref_pairs, r.missed, r.extra, r.max_extra_dist,
            (ext = r.eps_abs > 0 ? r.eps_abs / r.eps_rel : 0, r.max_extra_dist / (ext > 0 ? ext : 1)), r.bytes,
            r.bytes ? double(r.bytes) / double(r.tris_a + r.tris_b) : 0.0, csv_escape(r.note).c_str());
  }
  fclose(f);
}

struct Checks {
  std::vector<int> frames;
  std::vector<std::vector<Key>> ref;  // triangle pairs, sorted
};

Checks reference(const Scene& s, int frames, int n) {
  Checks c;
  Frame fr;
  n = std::min(n, frames);
  for (int i = 0; i < n; i++) {
    int f = int(int64_t(i) * frames / n);
    if (!c.frames.empty() && c.frames.back() == f) continue;
    s.frame(f, fr);
    c.frames.push_back(f);
    c.ref.emplace_back();
    exact_pairs(s.A.mesh, fr.ad.data(), s.B.mesh, fr.bd.data(), c.ref.back());
  }
  return c;
}

Row run(const Scene& s, Engine* e, int frames, const Checks& chk, double eps_rel = 0, double eps_abs = 0,
        uint32_t leaf = 0) {
  Row r;
  r.scene = s.name;
  r.group = s.group;
  r.engine = e->name();
  r.eps_rel = eps_rel;
  r.eps_abs = eps_abs;
  r.leaf = leaf;
  const Mesh &A = s.A.mesh, &B = s.B.mesh;
  r.tris_a = A.ntri();
  r.tris_b = B.ntri();
  Frame fr;
  s.frame(0, fr);
  try {
    e->build(A, B, fr);
  } catch (std::exception& ex) {
    r.note = std::string("unavailable: ") + ex.what();
    fprintf(stderr, "  %s: %s\n", r.engine.c_str(), r.note.c_str());
    return r;
  }
  r.bytes = e->bytes();
  std::vector<double> up, q, tot, np;
  std::vector<Key> out;
  double start = now_us();
  // two untimed warm-up frames
  for (int f = 0; f < std::min(2, frames); f++) {
    s.frame(f, fr);
    e->prepare(fr);
    e->update(fr);
    e->query(out);
  }
  size_t ci = 0;
  for (int f = 0; f < frames; f++) {
    s.frame(f, fr);
    e->prepare(fr);
    double t0 = now_us();
    e->update(fr);
    double t1 = now_us();
    e->query(out);
    double t2 = now_us();
    up.push_back(t1 - t0);
    q.push_back(t2 - t1);
    tot.push_back(t2 - t0);
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    np.push_back(double(out.size()));
    r.frames = f + 1;
    while (ci < chk.frames.size() && chk.frames[ci] < f) ci++;
    if (ci < chk.frames.size() && chk.frames[ci] == f) {
      const auto& ref = chk.ref[ci];
      std::vector<Key> miss, extra;
      std::set_difference(ref.begin(), ref.end(), out.begin(), out.end(), std::back_inserter(miss));
      std::set_difference(out.begin(), out.end(), ref.begin(), ref.end(), std::back_inserter(extra));
      r.check_frames++;
      r.ref_pairs += ref.size();
      r.missed += miss.size();
      r.extra += extra.size();
      for (Key k : extra) {  // the exact distance (triangle meshes: polygon = triangle)
        double d = judge(A, fr.ad.data(), key_a(k), B, fr.bd.data(), key_b(k), 0.0).dist;
        r.max_extra_dist = std::max(r.max_extra_dist, d);
      }
    }
    if ((now_us() - start) * 1e-6 > opt.budget && f + 1 >= 3) {
      r.note = "stopped after " + std::to_string(f + 1) + " frames (time budget)";
      break;
    }
  }
  r.update_us = median(up);
  r.query_us = median(q);
  r.total_us = median(tot);
  r.pairs = median(np);
  if (r.note.empty()) r.note = e->memory_note();
  fprintf(stderr, "  %-22s eps=%-8g leaf=%-4u frames=%-4d update %10.1f us  query %10.1f us  total %10.1f us  pairs %6.0f  missed %zu extra %zu (max dist %.3g)\n",
          r.engine.c_str(), eps_abs, leaf, r.frames, r.update_us, r.query_us, r.total_us, r.pairs, r.missed, r.extra,
          r.max_extra_dist);
  return r;
}

void dump(const Scene& s, int frames, const Checks& chk) {
  std::string path = opt.dump + "/" + s.name + ".scene";
  std::ofstream f(path, std::ios::binary);
  auto u64 = [&](uint64_t x) { f.write(reinterpret_cast<const char*>(&x), 8); };
  auto f64 = [&](double x) { f.write(reinterpret_cast<const char*>(&x), 8); };
  f.write("GLCSCN01", 8);
  const Mesh &A = s.A.mesh, &B = s.B.mesh;
  u64(A.nv());
  u64(A.ntri());
  u64(B.nv());
  u64(B.ntri());
  u64(uint64_t(frames));
  u64(chk.frames.size());
  f64(s.extent);
  std::string g = s.group;
  g.resize(16, ' ');
  f.write(g.data(), 16);
  f.write(reinterpret_cast<const char*>(A.tri.data()), A.tri.size() * 4);
  f.write(reinterpret_cast<const char*>(B.tri.data()), B.tri.size() * 4);
  Frame fr;
  for (int i = 0; i < frames; i++) {
    s.frame(i, fr);
    f.write(reinterpret_cast<const char*>(fr.a.data()), fr.a.size() * 4);
    f.write(reinterpret_cast<const char*>(fr.b.data()), fr.b.size() * 4);
  }
  for (size_t i = 0; i < chk.frames.size(); i++) {
    u64(uint64_t(chk.frames[i]));
    u64(chk.ref[i].size());
    for (Key k : chk.ref[i]) {  // (u32 triangle of A, u32 triangle of B)
      uint32_t ab[2] = {key_a(k), key_b(k)};
      f.write(reinterpret_cast<const char*>(ab), 8);
    }
  }
}

int frames_for(size_t tris, int base) {
  int f = int(base * opt.scale);
  if (tris > 500000) f = int(12 * opt.scale);
  else if (tris > 150000) f = int(40 * opt.scale);
  return std::max(f, 3);
}
}  // namespace

int main(int argc, char** argv) {
  for (int i = 1; i < argc; i++) {
    std::string a = argv[i];
    auto next = [&]() -> std::string {
      if (i + 1 >= argc) throw std::runtime_error(a + " needs a value");
      return argv[++i];
    };
    if (a == "--meshes") opt.meshes = next();
    else if (a == "--out") opt.out = next();
    else if (a == "--dump") opt.dump = next();
    else if (a == "--only") opt.only = next();
    else if (a == "--scale") opt.scale = atof(next().c_str());
    else if (a == "--budget") opt.budget = atof(next().c_str());
    else if (a == "--quick") opt.quick = true;
    else if (a == "--no-gl") opt.gl = false;
    else if (a == "--no-sweeps") opt.sweeps = false;
    else if (a == "--no-peers") opt.peers = false;
    else {
      fprintf(stderr,
              "usage: glcol_peers [--meshes DIR] [--out DIR] [--dump DIR] [--only NAME] [--scale X] [--budget S]\n"
              "                   [--quick] [--no-gl] [--no-sweeps] [--no-peers]\n");
      return 2;
    }
  }
  std::string renderer;
  bool have_gl = opt.gl && gl_context_init(renderer);
  fprintf(stderr, "glcollide %s; GL: %s\n", glcol_version(), have_gl ? renderer.c_str() : "none");

  std::vector<Scene> scenes = bench_scenes(opt.meshes, opt.only, opt.quick);
  for (auto& s : scenes) {
    fprintf(stderr, "scene %s (%s): %zu vs %zu triangles, extent %.4g, depth %.4g; %s\n", s.name.c_str(), s.group.c_str(),
            s.A.mesh.ntri(), s.B.mesh.ntri(), s.extent, s.depth, s.how.c_str());
  }
  if (!opt.dump.empty()) {
    FILE* f = fopen((opt.dump + "/scenes.txt").c_str(), "w");
    for (auto& s : scenes) fprintf(f, "%s\t%s\t%zu\t%zu\t%s\n", s.name.c_str(), s.group.c_str(), s.A.mesh.ntri(), s.B.mesh.ntri(), s.how.c_str());
    fclose(f);
  }
  {
    FILE* f = fopen((opt.out + "/scenes.tsv").c_str(), "w");
    fprintf(f, "scene\tgroup\ttris_a\ttris_b\textent\thow\n");
    for (auto& s : scenes) fprintf(f, "%s\t%s\t%zu\t%zu\t%g\t%s\n", s.name.c_str(), s.group.c_str(), s.A.mesh.ntri(), s.B.mesh.ntri(), s.extent, s.how.c_str());
    fprintf(f, "# GL: %s\n", have_gl ? renderer.c_str() : "none");
    fclose(f);
  }

  int nchk = opt.quick ? 2 : 8;
  for (auto& s : scenes) {
    bool instrument = s.kind == "instrument-organ";
    int frames = instrument ? frames_for(s.B.mesh.ntri(), 200) : frames_for(s.B.mesh.ntri(), 60);
    if (opt.quick) frames = 3;
    fprintf(stderr, "== %s: %d frames, exact answer on %d of them\n", s.name.c_str(), frames, std::min(nchk, frames));
    Checks chk = reference(s, frames, nchk);
    if (!opt.dump.empty()) dump(s, frames, chk);
    std::vector<std::function<Engine*()>> engines = {[] { return make_glcol(GLCOL_BACKEND_CPU, 0.0f, 0); }};
    if (opt.peers) {
      // a full quantum of Bullet's 16-bit frame (box padded by 1.0): at least half a quantum
      double ma = (extent(s.A.mesh) + 2.0 + 0.02 * s.extent) / 65535.0, mb = (s.extent + 2.0) / 65535.0;
      engines.push_back([] { return make_fcl(); });
      engines.push_back([ma, mb] { return make_bullet(ma, mb, false); });  // refit only
      engines.push_back([] { return make_embree(); });
    }
    for (auto& mk : engines) {
      std::unique_ptr<Engine> e(mk());
      rows.push_back(run(s, e.get(), frames, chk));
    }
    // speed against error: the epsilon sweep on every backend (instrument vs 52k, heavy)
    bool sweep_here = opt.sweeps && (opt.quick ? s.name == "blade_vs_face1k"
                                                 : (s.name == "blade_vs_spine52k" || s.group == "heavy"));
    if (sweep_here) {
      for (int be : {GLCOL_BACKEND_CPU, GLCOL_BACKEND_GL_SELECT, GLCOL_BACKEND_GL_COMPUTE}) {
        if (be != GLCOL_BACKEND_CPU && !have_gl) {
          Row r;
          r.scene = s.name;
          r.group = s.group;
          r.engine = be == GLCOL_BACKEND_GL_SELECT ? "glcollide_gl_select" : "glcollide_gl_compute";
          r.note = "unavailable: no GL context";
          rows.push_back(r);
          continue;
        }
        for (double er : {0.0, 1e-5, 1e-4, 1e-3, 1e-2}) {
          // llvmpipe takes seconds per heavy-case query: two epsilons there
          if (be != GLCOL_BACKEND_CPU && !instrument && er != 0.0 && er != 1e-3) continue;
          float ea = float(er * s.extent);
          std::unique_ptr<Engine> e(make_glcol(be, ea, 0, gl_get_proc));
          int fr = be == GLCOL_BACKEND_CPU ? frames : std::min(frames, opt.quick || !instrument ? 3 : 20);
          Row r = run(s, e.get(), fr, chk, er, ea);
          r.group = "eps_sweep";
          rows.push_back(r);
        }
      }
    }
    // Figure 2: polygons per box
    if (opt.sweeps && s.group == "paper") {
      for (uint32_t leaf : {4u, 8u, 16u, 32u, 64u, 128u, 256u, 512u, 1024u, 2048u}) {
        if (opt.quick && leaf != 16 && leaf != 256) continue;
        std::unique_ptr<Engine> e(make_glcol(GLCOL_BACKEND_CPU, 0.0f, leaf));
        Row r = run(s, e.get(), opt.quick ? 3 : std::max(3, int(100 * opt.scale)), chk, 0, 0, leaf);
        r.group = "leaf_sweep";
        rows.push_back(r);
      }
    }
    write_csv();
  }
  write_csv();
  fprintf(stderr, "wrote %s/peers.csv\n", opt.out.c_str());
  return 0;
}
