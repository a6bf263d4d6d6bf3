// A peer's collision query with contact points (peer_contacts.cpp).
#pragma once

#include "common.hpp"

namespace peers {

struct ContactStats {
    size_t contacts = 0;   // contacts reported
    size_t zero_depth = 0; // with penetration depth exactly 0
    size_t at_vertex = 0;  // whose position is a vertex of one of the two triangles
};

struct ContactEngine {
    virtual ~ContactEngine() {}
    virtual void build(const Mesh &a, const Mesh &b, const Frame &f0) = 0;
    virtual void update(const Frame &f) = 0; // not timed
    virtual ContactStats query() = 0;        // timed
};

// FCL 0.7, BVHModel<AABBd>, collide() with enable_contact = true.
ContactEngine *make_fcl_contacts();

} // namespace peers
