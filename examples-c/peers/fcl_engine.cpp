// FCL 0.7 (libfcl-dev) in the configuration ../shared/peers/REPORT.md §2 found sound:
// BVHModel<AABB> (not OBBRSS: its merge-based refit drops a corner and misses real pairs),
// refit each frame with beginUpdateModel / updateSubModel / endUpdateModel(refit, bottom-up),
// computeLocalAABB and CollisionObject::computeAABB() (without them the object's world box
// is stale), and one collide() with num_max_contacts = SIZE_MAX and enable_contact = false,
// which yields one Contact per intersecting triangle pair with b1/b2 = the triangle indices.
// FCL's narrow phase (Intersect::intersect_Triangle, a 17-axis SAT in double) is its own.
// Placement and deformation are already in the vertices, so both transforms are identity
// (a non-identity transform would only make FCL transform every vertex again).
#include "common.hpp"

#include <fcl/fcl.h>

#include <limits>
#include <memory>
#include <stdexcept>

namespace peers {
namespace {

using namespace fcl;
using Model = BVHModel<AABBd>;

struct FclEngine : Engine {
    std::shared_ptr<Model> m[2];
    std::unique_ptr<CollisionObjectd> o[2];
    std::vector<Vector3d> p[2]; // the caller's arrays in FCL's type (prepare)

    std::string name() const override { return "fcl_aabb"; }
    static void fill(std::vector<Vector3d> &dst, const std::vector<double> &v) {
        dst.resize(v.size() / 3);
        for (size_t i = 0; i < dst.size(); i++) dst[i] = Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
    void build(const Mesh &a, const Mesh &b, const Frame &f) override {
        prepare(f);
        const Mesh *ms[2] = {&a, &b};
        for (int k = 0; k < 2; k++) {
            const Mesh &M = *ms[k];
            std::vector<Triangle> ts(M.ntri());
            for (size_t t = 0; t < M.ntri(); t++) ts[t] = Triangle(M.tri[3 * t], M.tri[3 * t + 1], M.tri[3 * t + 2]);
            m[k] = std::make_shared<Model>();
            if (m[k]->beginModel(int(M.ntri()), int(M.nv())) != BVH_OK || m[k]->addSubModel(p[k], ts) != BVH_OK ||
                m[k]->endModel() != BVH_OK)
                throw std::runtime_error("FCL: building the BVHModel failed");
            m[k]->computeLocalAABB();
            o[k].reset(new CollisionObjectd(m[k], Transform3d::Identity()));
            o[k]->computeAABB();
        }
    }
    void prepare(const Frame &f) override {
        fill(p[0], f.ad);
        fill(p[1], f.bd);
    }
    void update(const Frame &) override {
        for (int k = 0; k < 2; k++) {
            if (m[k]->beginUpdateModel() != BVH_OK || m[k]->updateSubModel(p[k]) != BVH_OK ||
                m[k]->endUpdateModel(true, true) != BVH_OK)
                throw std::runtime_error("FCL: refitting the BVHModel failed");
            m[k]->computeLocalAABB();
        }
        for (auto &x : o) x->computeAABB();
    }
    void query(std::vector<Key> &out) override {
        CollisionRequestd req(std::numeric_limits<size_t>::max(), false);
        CollisionResultd res;
        collide(o[0].get(), o[1].get(), req, res);
        out.clear();
        out.reserve(res.numContacts());
        for (size_t i = 0; i < res.numContacts(); i++) {
            const auto &c = res.getContact(i);
            out.push_back(key(uint32_t(c.b1), uint32_t(c.b2)));
        }
    }
    static size_t model_bytes(const Model &x) {
        return size_t(x.getNumBVs()) * sizeof(BVNode<AABBd>) + size_t(x.num_vertices) * 2 * sizeof(Vector3d) +
               size_t(x.num_tris) * (sizeof(Triangle) + sizeof(unsigned int));
    }
    size_t bytes() const override { return model_bytes(*m[0]) + model_bytes(*m[1]); }
    std::string memory_note() const override {
        return "BVNode<AABBd> " + std::to_string(sizeof(BVNode<AABBd>)) +
               " B x (2n-1) + vertices and prev_vertices (2x24 B/vertex) + triangles (12 B) + primitive_indices (4 B); "
               "the per-query deep copy of both models is not counted";
    }
};

} // namespace

Engine *make_fcl() { return new FclEngine(); }

} // namespace peers
