#include "scenes.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <stdexcept>
#include <unordered_map>

#include "../../include/glcollide.h"

Mesh load_obj(const std::string& path) {
  GlcolObjMesh o;
  if (glcol_obj_load(path.c_str(), &o) != GLCOL_STATUS_OK)
    throw std::runtime_error("cannot load " + path + ": " + glcol_last_error_message());
  Mesh m;
  m.v.assign(o.positions, o.positions + 3 * o.vertex_count);
  m.t.assign(o.indices, o.indices + 3 * o.polygon_count);
  glcol_obj_free(&o);
  return m;
}

static void bbox(const Mesh& m, double lo[3], double hi[3]) {
  for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
  for (size_t i = 0; i < m.nv(); i++)
    for (int k = 0; k < 3; k++) lo[k] = std::min(lo[k], double(m.v[3 * i + k])), hi[k] = std::max(hi[k], double(m.v[3 * i + k]));
}
static double extent_of(const Mesh& m) {
  double lo[3], hi[3];
  bbox(m, lo, hi);
  return std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
}

// Vertex clustering on a uniform grid of cell h: the vertices of a cell merge into their
// mean, triangles that lose a corner and duplicate triangles go; unused vertices go.
static Mesh cluster(const Mesh& m, double h) {
  double lo[3], hi[3];
  bbox(m, lo, hi);
  std::unordered_map<uint64_t, uint32_t> cell;
  std::vector<uint32_t> cid(m.nv());
  std::vector<double> sum;
  std::vector<uint32_t> cnt;
  for (size_t i = 0; i < m.nv(); i++) {
    uint64_t key = 0;
    for (int k = 0; k < 3; k++) key = key * 2097152u + uint64_t((m.v[3 * i + k] - lo[k]) / h);
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
    for (int k = 0; k < 3; k++) sum[3 * c + k] += m.v[3 * i + k];
  }
  std::map<std::array<uint32_t, 3>, int> seen;
  Mesh out;
  std::vector<int64_t> remap(cnt.size(), -1);
  for (size_t t = 0; t < m.nt(); t++) {
    uint32_t c[3] = {cid[m.t[3 * t]], cid[m.t[3 * t + 1]], cid[m.t[3 * t + 2]]};
    if (c[0] == c[1] || c[1] == c[2] || c[0] == c[2]) continue;
    std::array<uint32_t, 3> key = {c[0], c[1], c[2]};
    std::sort(key.begin(), key.end());
    if (!seen.emplace(key, 1).second) continue;
    for (int j = 0; j < 3; j++) {
      if (remap[c[j]] < 0) {
        remap[c[j]] = int64_t(out.nv());
        for (int k = 0; k < 3; k++) out.v.push_back(float(sum[3 * c[j] + k] / cnt[c[j]]));
      }
      out.t.push_back(uint32_t(remap[c[j]]));
    }
  }
  return out;
}

Mesh decimate(const Mesh& m, size_t target, std::string* how) {
  double e = extent_of(m);
  double lo = e * 1e-5, hi = e * 0.5;  // tiny cells keep everything, huge ones nothing
  Mesh best;
  double best_h = 0;
  for (int it = 0; it < 40; it++) {
    double h = std::sqrt(lo * hi);
    Mesh c = cluster(m, h);
    if (best.t.empty() || std::abs(double(c.nt()) - target) < std::abs(double(best.nt()) - target)) best = c, best_h = h;
    if (c.nt() > target) lo = h; else hi = h;
    if (std::abs(double(c.nt()) - target) < 0.01 * target) break;
  }
  if (how) {
    char buf[200];
    snprintf(buf, sizeof buf, "vertex clustering, cell %.4g (%.3g%% of the extent): %zu -> %zu triangles", best_h,
             100 * best_h / e, m.nt(), best.nt());
    *how = buf;
  }
  return best;
}

Mesh subdivide(const Mesh& m) {
  Mesh out;
  out.v = m.v;
  std::unordered_map<uint64_t, uint32_t> mid;
  auto midpoint = [&](uint32_t i, uint32_t j) {
    uint64_t key = uint64_t(std::min(i, j)) << 32 | std::max(i, j);
    auto it = mid.find(key);
    if (it != mid.end()) return it->second;
    uint32_t n = uint32_t(out.nv());
    for (int k = 0; k < 3; k++) out.v.push_back(0.5f * (m.v[3 * i + k] + m.v[3 * j + k]));
    mid.emplace(key, n);
    return n;
  };
  for (size_t t = 0; t < m.nt(); t++) {
    uint32_t a = m.t[3 * t], b = m.t[3 * t + 1], c = m.t[3 * t + 2];
    uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
    out.t.insert(out.t.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
  }
  return out;
}

static void warp(const double p[3], double amp, double k, double ph, double out[3]) {
  out[0] = p[0] + amp * std::sin(ph + k * p[1]);
  out[1] = p[1] + amp * std::sin(1.3 * ph + k * p[2]);
  out[2] = p[2] + amp * std::sin(0.7 * ph + k * p[0]);
}

static void warp_mesh(const Mesh& m, double amp, double k, double ph, std::vector<float>& f, std::vector<double>& d) {
  f.resize(m.v.size());
  d.resize(m.v.size());
  for (size_t i = 0; i < m.nv(); i++) {
    double p[3] = {m.v[3 * i], m.v[3 * i + 1], m.v[3 * i + 2]}, q[3];
    warp(p, amp, k, ph, q);
    for (int j = 0; j < 3; j++) {
      f[3 * i + j] = float(q[j]);
      d[3 * i + j] = double(f[3 * i + j]);
    }
  }
}

void SceneDef::frame(int f, Frame& out) const {
  if (!instrument) {
    warp_mesh(a, amp, k, 0.1 * f, out.a, out.ad);
    warp_mesh(b, -amp, k, 0.1 * f, out.b, out.bd);
    return;
  }
  double ph = 0.05 * f;
  warp_mesh(b, amp, k, ph, out.b, out.bd);
  double moved[3];
  warp(anchor, amp, k, ph, moved);
  double d = depth * (1.0 + 0.3 * std::sin(0.21 * f));
  double s = slide * std::sin(0.13 * f);
  double t[3] = {moved[0] - anchor[0] - d, moved[1] - anchor[1] + s, moved[2] - anchor[2] + 0.5 * s};
  out.a.resize(a.v.size());
  out.ad.resize(a.v.size());
  for (size_t i = 0; i < a.v.size(); i++) {
    out.a[i] = float(double(a.v[i]) + t[i % 3]);
    out.ad[i] = out.a[i];
  }
}

SceneDef instrument_scene(const std::string& name, const std::string& group, const Mesh& ins, const Mesh& organ,
                          double rel_len) {
  SceneDef s;
  s.name = name;
  s.group = group;
  s.b = organ;
  s.extent = extent_of(organ);
  s.amp = 0.002 * s.extent;
  s.k = 6.0 / s.extent;
  // anchor: the organ's outermost vertex along +x
  size_t far = 0;
  for (size_t i = 0; i < organ.nv(); i++)
    if (organ.v[3 * i] > organ.v[3 * far]) far = i;
  for (int k = 0; k < 3; k++) s.anchor[k] = organ.v[3 * far + k];
  double lo[3], hi[3];
  bbox(ins, lo, hi);
  int L = 0;
  for (int k = 1; k < 3; k++)
    if (hi[k] - lo[k] > hi[L] - lo[L]) L = k;
  double len = hi[L] - lo[L], scale = rel_len * s.extent / len;
  double c[3] = {(lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2};
  double cz = std::cos(0.35), sz = std::sin(0.35), cy = std::cos(0.25), sy = std::sin(0.25);
  std::vector<double> p(ins.v.size());
  for (size_t i = 0; i < ins.nv(); i++) {
    double q[3];
    for (int k = 0; k < 3; k++) q[k] = (ins.v[3 * i + (L + k) % 3] - c[(L + k) % 3]) * scale;
    double x = cz * q[0] - sz * q[1], y = sz * q[0] + cz * q[1], z = q[2];
    p[3 * i] = cy * x + sy * z;
    p[3 * i + 1] = y;
    p[3 * i + 2] = -sy * x + cy * z;
  }
  size_t tip = 0;
  for (size_t i = 0; i < ins.nv(); i++)
    if (p[3 * i] < p[3 * tip]) tip = i;
  double off[3] = {s.anchor[0] - p[3 * tip], s.anchor[1] - p[3 * tip + 1], s.anchor[2] - p[3 * tip + 2]};
  s.a.t = ins.t;
  s.a.v.resize(ins.v.size());
  for (size_t i = 0; i < p.size(); i++) s.a.v[i] = float(p[i] + off[i % 3]);
  s.slide = 0.01 * rel_len * s.extent;
  s.depth = 0;
  char buf[160];
  snprintf(buf, sizeof buf, "instrument scaled to %.0f%% of the organ's extent, pushed in at the organ's +x extreme", rel_len * 100);
  s.how = buf;
  return s;
}

SceneDef heavy_scene(const std::string& name, const Mesh& a, const Mesh& b) {
  SceneDef s;
  s.name = name;
  s.group = "heavy";
  s.a = a;
  s.b = b;
  s.instrument = false;
  Mesh both = a;
  both.v.insert(both.v.end(), b.v.begin(), b.v.end());
  s.extent = extent_of(both);
  s.amp = 0.004 * s.extent;
  s.k = 8.0 / s.extent;
  s.how = "both at rest in their shared CT frame (they overlap), opposite warps";
  return s;
}

void tune_depth(SceneDef& s, int target) {
  std::unique_ptr<Engine> e(make_glcol(GLCOL_BACKEND_CPU, 0.0f, 0));
  Frame fr;
  s.depth = 0;
  s.frame(0, fr);
  e->build(s.a, s.b, fr);
  const int samples[] = {0, 7, 15, 23, 31};
  std::vector<Pair> out;
  auto count = [&](double d) {
    s.depth = d;
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
  bbox(s.a, lo, hi);
  double dlo = 0, dhi = 0.5 * (hi[0] - lo[0]);
  for (int it = 0; it < 18; it++) {
    double d = 0.5 * (dlo + dhi);
    if (count(d) >= size_t(target)) dhi = d; else dlo = d;
  }
  s.depth = dhi;
}
