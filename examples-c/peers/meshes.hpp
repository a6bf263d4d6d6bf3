// Where the meshes come from (meshes.cpp): OBJ files read with glcollide's own reader, what
// is done to them (decimation, subdivision, cut-outs, normalising an instrument) and the
// generated shapes of the cross-check's hard cases.
#pragma once

#include "common.hpp"

#include <functional>
#include <map>
#include <string>
#include <tuple>

namespace peers {

Mesh load_obj(const std::string &path);                         // name: the file's, less .obj
Mesh load_obj(const std::string &dir, const std::string &name); // dir/name.obj

void bbox(const Mesh &M, double lo[3], double hi[3]); // of the rest pose
double extent(const Mesh &M);                         // largest side of the box
double diag(const Mesh &M);                           // diagonal of the box
// Index of the vertex farthest along d (the first of equals): it lies on the convex hull.
size_t farthest_vertex(const Mesh &M, const double d[3]);

// Vertex clustering on a uniform grid (cell size found by bisection) to about `target`
// triangles; positions stay floats. `how` (if given) says what was done.
Mesh decimate(const Mesh &m, size_t target, std::string *how);
// Midpoint subdivision: every triangle into four (float midpoints).
Mesh subdivide(const Mesh &m);
// Faces [f0, f1) of M (0-based) as a mesh of their own.
Mesh sub_mesh(const Mesh &M, size_t f0, size_t f1, const std::string &name);
// The instrument M centred on its box, its longest axis turned onto axis `to` (the other two
// following cyclically), scaled to `length` along it. Positions in double, not rounded.
Mesh instrument_local(Mesh M, double length, int to);

// ---- generated shapes ----
// Builds a mesh from generated polygons, welding bit-identical positions.
struct Builder {
    Mesh m;
    std::map<std::tuple<double, double, double>, uint32_t> at;
    Builder(const std::string &name, uint32_t vpp);
    uint32_t v(double x, double y, double z);
    void tri(uint32_t a, uint32_t b, uint32_t c) { m.poly.insert(m.poly.end(), {a, b, c}); }
    void quad(uint32_t a, uint32_t b, uint32_t c, uint32_t d) { m.poly.insert(m.poly.end(), {a, b, c, d}); }
    Mesh done();
};
using Surface = std::function<void(double u, double v, double out[3])>;
// An nu x nv patch (triangles or quads, as the builder's vpp) of the parametric surface fn
// over [0,1]^2.
void patch(Builder &b, int nu, int nv, const Surface &fn, bool flip = false);
Mesh grid(const std::string &name, int n, const Surface &fn);
Mesh icosphere(const std::string &name, int sub, double r);
// Closed box [-lx/2,lx/2] x [-ly/2,ly/2] x [-lz/2,lz/2], each face an n x n grid, welded.
Mesh box(const std::string &name, double lx, double ly, double lz, int n);
// Octahedron of radius r around c, turned by angle a about z.
Mesh octahedron(const std::string &name, const double c[3], double r, double a);

} // namespace peers
