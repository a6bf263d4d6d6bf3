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
#include "fcl_model.hpp"

#include <fcl/fcl.h>

#include <limits>
#include <memory>
#include <stdexcept>

namespace peers {
namespace {

using namespace fcl;
using Model = FclPair::Model;

struct FclEngine : Engine {
    FclPair fcl;

    std::string name() const override { return "fcl_aabb"; }
    void build(const Mesh &a, const Mesh &b, const Frame &f) override {
        fcl.set(f);
        fcl.build(a, b);
    }
    void prepare(const Frame &f) override { fcl.set(f); }
    void update(const Frame &) override { fcl.refit(); }
    void query(std::vector<Key> &out) override {
        CollisionRequestd req(std::numeric_limits<size_t>::max(), false);
        CollisionResultd res;
        collide(fcl.o[0].get(), fcl.o[1].get(), req, res);
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
    size_t bytes() const override { return model_bytes(*fcl.m[0]) + model_bytes(*fcl.m[1]); }
    std::string memory_note() const override {
        return "BVNode<AABBd> " + std::to_string(sizeof(BVNode<AABBd>)) +
               " B x (2n-1) + vertices and prev_vertices (2x24 B/vertex) + triangles (12 B) + primitive_indices (4 B); "
               "the per-query deep copy of both models is not counted";
    }
};

} // namespace

Engine *make_fcl() { return new FclEngine(); }

} // namespace peers
