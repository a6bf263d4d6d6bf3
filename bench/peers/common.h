// glcol_peers: glcollide (C API) against FCL, Bullet GImpact and Embree rtcCollide on the
// same scenes and the same deformation frames, in one process. See bench/README.md.
#pragma once
#include <array>
#include <chrono>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

struct Mesh {
  std::vector<float> v;     // x, y, z per vertex
  std::vector<uint32_t> t;  // 3 indices per triangle
  size_t nv() const { return v.size() / 3; }
  size_t nt() const { return t.size() / 3; }
};

// (reference triangle, other triangle); the reference is mesh A.
using Pair = std::pair<uint32_t, uint32_t>;

// One frame's positions of both meshes, in float (what glcollide takes) and the same
// values in double (what the peers take); the conversion is not timed.
struct Frame {
  std::vector<float> a, b;
  std::vector<double> ad, bd;
};

struct Engine {
  virtual ~Engine() {}
  virtual std::string name() const = 0;
  // Builds the structures for the rest pose (not timed in the per-frame medians).
  virtual void build(const Mesh& a, const Mesh& b, const Frame& f0) = 0;
  // Untimed: puts the frame's positions where the library reads them from (the caller's
  // arrays in the library's own type).
  virtual void prepare(const Frame&) {}
  // The library's update calls for both meshes after their vertices changed.
  virtual void update(const Frame& f) = 0;
  // The collision query plus whatever narrow phase gives the exact pair list (unsorted).
  virtual void query(std::vector<Pair>& out) = 0;
  // Bytes of the structures the library holds for the two meshes (see memory notes).
  virtual size_t bytes() const = 0;
  virtual std::string memory_note() const { return ""; }
};

// Exact closed triangle-triangle intersection (CGAL, exact predicates).
bool tri_exact(const double* a0, const double* a1, const double* a2, const double* b0,
               const double* b1, const double* b2);
// Distance between two triangles (CGAL, double).
double tri_distance(const double* a0, const double* a1, const double* a2, const double* b0,
                    const double* b1, const double* b2);
// The exact answer: every pair of triangles whose boxes overlap (a sweep over the x axis),
// tested with CGAL. Sorted.
std::vector<Pair> reference_pairs(const Mesh& a, const std::vector<double>& av, const Mesh& b,
                                  const std::vector<double>& bv);

inline double now_us() {
  using namespace std::chrono;
  return duration<double, std::micro>(steady_clock::now().time_since_epoch()).count();
}

Engine* make_fcl();
Engine* make_bullet(double margin_a, double margin_b);
Engine* make_embree();
// backend: 1 CPU, 2 GL_SELECT, 3 GL_COMPUTE (GlcolBackend values).
Engine* make_glcol(int backend, float epsilon, uint32_t leaf);
// A headless EGL context (Mesa surfaceless), current on this thread; false if none.
bool gl_context_init(std::string& renderer);
