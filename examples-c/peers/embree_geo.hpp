// Embree 3 user geometry for a mesh's triangles, shared by the pair engine
// (embree_engine.cpp) and the whole-scene one (bench/scene_peers/embree_scene.cpp):
// the mesh and the frame's positions, and the bounds callback, each triangle's box rounded
// outward to float (the sound configuration of ../shared/peers/REPORT.md §4).
#pragma once

#include "common.hpp"

#include <embree3/rtcore.h>

#include <algorithm>
#include <cmath>

namespace peers {

struct EmbreeGeo {
    const Mesh *mesh = nullptr;
    const double *v = nullptr; // the frame's positions, 3 per vertex
};

// RTCBoundsFunction for a geometry whose user data is an EmbreeGeo.
inline void embree_bounds(const RTCBoundsFunctionArguments *args) {
    const EmbreeGeo *g = static_cast<const EmbreeGeo *>(args->geometryUserPtr);
    const uint32_t *t = &g->mesh->tri[3 * args->primID];
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int c = 0; c < 3; c++)
        for (int k = 0; k < 3; k++) {
            double x = g->v[3 * t[c] + k];
            lo[k] = std::min(lo[k], x);
            hi[k] = std::max(hi[k], x);
        }
    RTCBounds *b = args->bounds_o;
    b->lower_x = std::nextafter(float(lo[0]), -INFINITY);
    b->lower_y = std::nextafter(float(lo[1]), -INFINITY);
    b->lower_z = std::nextafter(float(lo[2]), -INFINITY);
    b->upper_x = std::nextafter(float(hi[0]), INFINITY);
    b->upper_y = std::nextafter(float(hi[1]), INFINITY);
    b->upper_z = std::nextafter(float(hi[2]), INFINITY);
}

} // namespace peers
