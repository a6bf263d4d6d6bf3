// crosscheck: scene definitions (see scenes.cpp).
#pragma once

#include "common.hpp"

#include <array>
#include <functional>

namespace xc {

// Deformation, absolute from the rest pose, in the mesh's own frame:
// x[shift] += sign * amp * sin(0.35 f + k x[along]). A and B get opposite signs (as in
// ../shared/peers/BUILD.md): with the same warp the set of intersecting pairs hardly changes.
struct Warp {
    double amp = 0, k = 0, sign = 1;
    int shift = 1, along = 0;
};

struct Body {
    Mesh mesh;
    Warp warp;
    // Rigid placement at frame f (applied after the warp): x' = R x + t. Empty = identity.
    std::function<void(int f, double R[9], double t[3])> place;
};

struct Scene {
    std::string name, kind;
    Body A, B;    // A is glcollide's reference mesh
    int frames = 100;
    float eps = 0; // glcollide's second run uses this epsilon
};

// Positions of body b at frame f: computed in double, rounded to float (what glcollide
// takes), and those floats widened back to double (what FCL, Bullet and CGAL take), so all
// libraries see exactly the same coordinates.
void pose(const Body &b, int f, std::vector<float> &fo, std::vector<double> &d);

Mesh load_obj(const std::string &dir, const std::string &name); // dir/name.obj
Mesh load_obj_path(const std::string &path);

// Instrument `ins` (longest axis onto the direction of work, scaled to 1/10 of the organ's
// diagonal) centred on the organ's vertex farthest along dir, moving in and out along dir
// (-0.25..0.35 of its length) and spinning, bending along its length; the organ gets the
// opposite-signed warp (0.4% of its diagonal). epsilon = 1e-3 x instrument length.
Scene instrument_vs_organ(const Mesh &ins, const Mesh &organ, const double dir[3], int frames);
// Two meshes in their shared frame, opposite warps (0.3% of the larger diagonal);
// epsilon = 1e-3 x A's diagonal.
Scene organ_vs_organ(const Mesh &a, const Mesh &b, int frames);

// Every scene, built lazily (meshes are loaded when the scene runs).
std::vector<std::function<Scene()>> all_scenes(const std::string &dir, int frames_override);

} // namespace xc
