// The FCL models of a mesh pair, as both FCL engines use them (fcl_engine.cpp for the pairs,
// bench/contact/peer_contacts.cpp with enable_contact): BVHModel<AABBd> built once, refit
// bottom-up each frame, then computeLocalAABB and CollisionObject::computeAABB (without them
// the object's world box is stale); both transforms identity (placement is in the vertices).
#pragma once

#include "common.hpp"

#include <fcl/fcl.h>

#include <memory>
#include <stdexcept>
#include <vector>

namespace peers {

struct FclPair {
    using Model = fcl::BVHModel<fcl::AABBd>;
    std::shared_ptr<Model> m[2];
    std::unique_ptr<fcl::CollisionObjectd> o[2];
    std::vector<fcl::Vector3d> p[2]; // the frame's positions in FCL's type (set)

    // This frame's positions, converted.
    void set(const Frame &f) {
        fill(p[0], f.ad);
        fill(p[1], f.bd);
    }
    // The models of a and b at the positions last set.
    void build(const Mesh &a, const Mesh &b) {
        const Mesh *ms[2] = {&a, &b};
        for (int k = 0; k < 2; k++) {
            const Mesh &M = *ms[k];
            std::vector<fcl::Triangle> ts(M.ntri());
            for (size_t t = 0; t < M.ntri(); t++)
                ts[t] = fcl::Triangle(M.tri[3 * t], M.tri[3 * t + 1], M.tri[3 * t + 2]);
            m[k] = std::make_shared<Model>();
            if (m[k]->beginModel(int(M.ntri()), int(M.nv())) != fcl::BVH_OK ||
                m[k]->addSubModel(p[k], ts) != fcl::BVH_OK || m[k]->endModel() != fcl::BVH_OK)
                throw std::runtime_error("FCL: building the BVHModel failed");
            m[k]->computeLocalAABB();
            o[k].reset(new fcl::CollisionObjectd(m[k], fcl::Transform3d::Identity()));
            o[k]->computeAABB();
        }
    }
    // Both models refit to the positions last set.
    void refit() {
        for (int k = 0; k < 2; k++) {
            if (m[k]->beginUpdateModel() != fcl::BVH_OK || m[k]->updateSubModel(p[k]) != fcl::BVH_OK ||
                m[k]->endUpdateModel(true, true) != fcl::BVH_OK)
                throw std::runtime_error("FCL: refitting the BVHModel failed");
            m[k]->computeLocalAABB();
        }
        for (auto &x : o) x->computeAABB();
    }

  private:
    static void fill(std::vector<fcl::Vector3d> &dst, const std::vector<double> &v) {
        dst.resize(v.size() / 3);
        for (size_t i = 0; i < dst.size(); i++) dst[i] = fcl::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
};

} // namespace peers
