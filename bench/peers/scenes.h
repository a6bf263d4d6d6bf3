#pragma once
#include "common.h"

struct SceneDef {
  std::string name, group;  // group: paper | instrument | heavy | scaling
  std::string how;          // where the meshes come from and what was done to them
  Mesh a, b;                // rest poses; a is the reference (the instrument, or colon)
  double extent = 0;        // largest side of the scene's box at rest
  bool instrument = true;
  double amp = 0, k = 0;    // organ warp amplitude and wave number
  double depth = 0, slide = 0;
  double anchor[3] = {0, 0, 0};
  int frames = 0;
  void frame(int f, Frame& out) const;
};

Mesh load_obj(const std::string& path);
Mesh decimate(const Mesh& m, size_t target, std::string* how);
Mesh subdivide(const Mesh& m);
// Places the instrument `ins` at the organ's outermost (+x) point, its long axis along x,
// tilted, scaled to `rel_len` of the organ's extent; `depth` is set later by tune_depth.
SceneDef instrument_scene(const std::string& name, const std::string& group, const Mesh& ins,
                          const Mesh& organ, double rel_len);
SceneDef heavy_scene(const std::string& name, const Mesh& a, const Mesh& b);
// Chooses the depth so that the median number of colliding pairs over a few frames is
// about `target` (exact answer, counted with glcollide's CPU backend).
void tune_depth(SceneDef& s, int target);
