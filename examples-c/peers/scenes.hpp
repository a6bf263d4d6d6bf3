// The scenes of both drivers (scenes.cpp): how two meshes are placed and moved frame by
// frame, and each driver's list of scenes.
#pragma once

#include "meshes.hpp"

#include <functional>

namespace peers {

// Motion of one body per frame f, absolute from its rest pose: a deformation in the mesh's
// own frame (warp, changes x in place), then a rigid move x' = R x + t (place; R and t
// start as the identity). Either may be empty.
using Warp = std::function<void(int f, double x[3])>;
using Place = std::function<void(int f, double R[9], double t[3])>;

struct Body {
    Mesh mesh;
    Warp warp;
    Place place;
};

// The warps. axis_warp: x[shift] += sign * amp * sin(0.35 f + k x[along]) (the cross-check's,
// as in ../shared/peers/BUILD.md: A and B get opposite signs, since with the same warp the set
// of intersecting pairs hardly changes). wave_warp: every coordinate,
// x += amp sin(ph + k y), y += amp sin(1.3 ph + k z), z += amp sin(0.7 ph + k x), ph = rate f
// (the benchmark's: every vertex moves every frame).
Warp axis_warp(double amp, double k, double sign, int shift, int along);
Warp wave_warp(double amp, double k, double rate);

struct Scene {
    std::string name;
    std::string kind;  // instrument-organ | organ-organ | generated
    std::string group; // the benchmark's table: paper | instrument | heavy | scaling
    std::string how;   // the benchmark's: where the meshes come from and what was done to them
    Body A, B;         // A is glcollide's reference mesh (the instrument, or the first organ)
    int frames = 100;  // the cross-check's frame count (the benchmark chooses its own)
    float eps = 0;     // the cross-check's epsilon for glcollide's second run
    double extent = 0; // the benchmark's: largest side of the scene's box at rest
    double depth = 0;  // the benchmark's instrument scenes: how far the instrument is pushed in
    // Positions of both bodies at frame f.
    void frame(int f, Frame &out) const;
};

// Positions of body b at frame f: computed in double, rounded to float (what glcollide
// takes), and those floats widened back to double (what everyone else takes).
void pose(const Body &b, int f, std::vector<float> &fo, std::vector<double> &d);

// ---- the cross-check's scenes ----
// Instrument `ins` (longest axis onto the direction of work, scaled to 1/10 of the organ's
// diagonal) centred on the organ's vertex farthest along dir, moving in and out along dir
// (-0.25..0.35 of its length) and spinning, bending along its length; the organ gets the
// opposite-signed warp (0.4% of its diagonal). epsilon = 1e-3 x instrument length.
Scene instrument_vs_organ(const Mesh &ins, const Mesh &organ, const double dir[3], int frames);
// Two meshes in their shared frame, opposite warps (0.3% of the larger diagonal);
// epsilon = 1e-3 x A's diagonal.
Scene organ_vs_organ(const Mesh &a, const Mesh &b, int frames);
// Every scene, built lazily (meshes are loaded when the scene runs).
std::vector<std::function<Scene()>> crosscheck_scenes(const std::string &dir, int frames_override);

// ---- the benchmark's scenes ----
// The paper set, the 52k jaw, the scaling set and the heavy case (bench/README.md), the
// instrument scenes with their depth tuned (glcollide's CPU backend counts the pairs).
// only: the scenes whose name contains it; quick: the three small paper scenes and the heavy
// case.
std::vector<Scene> bench_scenes(const std::string &dir, const std::string &only, bool quick);

} // namespace peers
