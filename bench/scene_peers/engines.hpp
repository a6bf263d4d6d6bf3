// Whole-scene peers (bench/scene_peers): every pair of triangles of different bodies that
// intersect, each library's multi-body way. Inter-body only: FCL and Bullet have no mesh
// self-collision (self-collision is timed against CGAL and Embree by examples-c/selfcheck).
#pragma once

#include "common.hpp"

#include <cstdint>
#include <string>
#include <tuple>
#include <vector>

namespace scene_peers {

// A triangle pair of two bodies, body_a < body_b.
struct Pair {
    uint32_t body_a, tri_a, body_b, tri_b;
    bool operator<(const Pair &o) const {
        return std::tie(body_a, tri_a, body_b, tri_b) < std::tie(o.body_a, o.tri_a, o.body_b, o.tri_b);
    }
    bool operator==(const Pair &o) const {
        return std::tie(body_a, tri_a, body_b, tri_b) == std::tie(o.body_a, o.tri_a, o.body_b, o.tri_b);
    }
};

// One frame of every body: positions as float (glcollide's input) and the same values
// widened to double (the peers' input).
struct Frame {
    std::vector<std::vector<float>> f;
    std::vector<std::vector<double>> d;
};

struct SceneEngine {
    // Half the band (epsilon / 2): 0 asks for the intersecting pairs; h > 0 for the pairs
    // within h of each other (the peers: by distance; glcollide: its viewing volumes, a
    // subset of those, docs/API.md). Set before build.
    double h = 0;
    virtual ~SceneEngine() {}
    virtual std::string name() const = 0;
    // The library's structures for the bodies at frame `f0` (not timed).
    virtual void build(const std::vector<peers::Mesh> &bodies, const Frame &f0) = 0;
    // The library's update of every body after its vertices moved to `f` (timed).
    virtual void update(const Frame &f) = 0;
    // Broad phase over the bodies, then each body pair's triangle pairs, exact (timed).
    virtual void query(std::vector<Pair> &out) = 0;
};

// The distance of triangle ta of positions pa and triangle tb of pb (FCL's triangle
// distance, double): the peers' narrow test within a band.
double tri_distance(const double *pa, const uint32_t *ta, const double *pb, const uint32_t *tb);

// FCL 0.7: DynamicAABBTreeCollisionManager over one CollisionObject per body, each a
// BVHModel<AABBd> refit bottom-up; collide() per overlapping body pair, all contacts.
SceneEngine *make_fcl_scene();
// Bullet 3.24 (double): btDbvtBroadphase over one proxy per body, each a btGImpactMeshShape
// (refit); per overlapping body pair GImpact's find_collision, then the exact test. Within a
// band (h > 0): every primitive box grown by h / 2 (the shape's margin), then
// tri_distance <= h.
SceneEngine *make_bullet_scene();
// Embree 3: one scene of user geometries (one per body, REFIT, bounds rounded outward to
// float), rtcCollide of the scene with itself, pairs of different bodies, the exact test.
SceneEngine *make_embree_scene();

} // namespace scene_peers
