// crosscheck: FCL 0.7 (libfcl-dev) in the configuration ../shared/peers/REPORT.md found sound:
// BVHModel<AABB> (not OBBRSS: its merge-based refit drops a corner and misses real pairs),
// refit each frame with beginUpdateModel / updateSubModel / endUpdateModel(refit, bottom-up)
// followed by CollisionObject::computeAABB() (without it the object's world box is stale),
// and one collide() with num_max_contacts = SIZE_MAX and enable_contact = false, which
// yields one Contact per intersecting triangle pair with b1/b2 = the triangle indices.
// FCL's narrow phase (Intersect::intersect_Triangle, a 17-axis SAT in double) is its own.
// Placement and deformation are already in the vertices, so both transforms are identity
// (a non-identity transform would only make FCL transform every vertex again).
#include "common.hpp"

#include <fcl/narrowphase/collision.h>
#include <fcl/narrowphase/collision_object.h>
#include <fcl/geometry/bvh/BVH_model.h>

#include <limits>
#include <memory>
#include <stdexcept>

namespace xc {

using Model = fcl::BVHModel<fcl::AABBd>;

struct FclPeer {
    std::shared_ptr<Model> m[2];
    std::unique_ptr<fcl::CollisionObjectd> o[2];
    size_t nv[2];
};

static std::vector<fcl::Vector3d> points(const double *p, size_t nv) {
    std::vector<fcl::Vector3d> v(nv);
    for (size_t i = 0; i < nv; i++) v[i] = fcl::Vector3d(p[3 * i], p[3 * i + 1], p[3 * i + 2]);
    return v;
}

FclPeer *fcl_create(const Mesh &A, const double *pa, const Mesh &B, const double *pb) {
    auto *p = new FclPeer;
    const Mesh *ms[2] = {&A, &B};
    const double *ps[2] = {pa, pb};
    for (int k = 0; k < 2; k++) {
        const Mesh &M = *ms[k];
        std::vector<fcl::Triangle> ts(M.ntri());
        for (size_t t = 0; t < M.ntri(); t++)
            ts[t] = fcl::Triangle(M.tri[3 * t], M.tri[3 * t + 1], M.tri[3 * t + 2]);
        p->m[k] = std::make_shared<Model>();
        p->nv[k] = M.nv();
        if (p->m[k]->beginModel(int(M.ntri()), int(M.nv())) != fcl::BVH_OK ||
            p->m[k]->addSubModel(points(ps[k], M.nv()), ts) != fcl::BVH_OK ||
            p->m[k]->endModel() != fcl::BVH_OK)
            throw std::runtime_error("FCL: building the BVHModel failed");
        p->o[k].reset(new fcl::CollisionObjectd(p->m[k], fcl::Transform3d::Identity()));
        p->o[k]->computeAABB();
    }
    return p;
}

void fcl_update(FclPeer *p, const double *pa, const double *pb) {
    const double *ps[2] = {pa, pb};
    for (int k = 0; k < 2; k++) {
        if (p->m[k]->beginUpdateModel() != fcl::BVH_OK ||
            p->m[k]->updateSubModel(points(ps[k], p->nv[k])) != fcl::BVH_OK ||
            p->m[k]->endUpdateModel(true, true) != fcl::BVH_OK)
            throw std::runtime_error("FCL: refitting the BVHModel failed");
        p->o[k]->computeAABB();
    }
}

void fcl_query(FclPeer *p, std::vector<Key> &out) {
    fcl::CollisionRequestd req(std::numeric_limits<size_t>::max(), false);
    fcl::CollisionResultd res;
    fcl::collide(p->o[0].get(), p->o[1].get(), req, res);
    std::vector<fcl::Contactd> cs;
    res.getContacts(cs);
    out.clear();
    out.reserve(cs.size());
    for (const auto &c : cs) out.push_back(key(uint32_t(c.b1), uint32_t(c.b2)));
    sort_unique(out);
}

void fcl_destroy(FclPeer *p) { delete p; }

} // namespace xc
