// FCL 0.7 with enable_contact = true: the same model and refit as ../../examples-c/peers/
// fcl_engine.cpp (BVHModel<AABBd>, refit bottom-up), and one collide() with
// num_max_contacts = SIZE_MAX and enable_contact = true, which fills Contact::pos, normal and
// penetration_depth for every intersecting triangle pair.
#include "common.hpp"

#include <fcl/fcl.h>

#include <limits>
#include <memory>
#include <stdexcept>

#include "peer_contacts.hpp"

namespace peers {
namespace {

using namespace fcl;
using Model = BVHModel<AABBd>;

struct FclContacts : ContactEngine {
    std::shared_ptr<Model> m[2];
    std::unique_ptr<CollisionObjectd> o[2];
    std::vector<Vector3d> p[2];
    const Mesh *mesh[2] = {nullptr, nullptr};

    static void fill(std::vector<Vector3d> &dst, const std::vector<double> &v) {
        dst.resize(v.size() / 3);
        for (size_t i = 0; i < dst.size(); i++) dst[i] = Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
    void build(const Mesh &a, const Mesh &b, const Frame &f) override {
        fill(p[0], f.ad);
        fill(p[1], f.bd);
        mesh[0] = &a;
        mesh[1] = &b;
        for (int k = 0; k < 2; k++) {
            const Mesh &M = *mesh[k];
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
    void update(const Frame &f) override {
        fill(p[0], f.ad);
        fill(p[1], f.bd);
        for (int k = 0; k < 2; k++) {
            if (m[k]->beginUpdateModel() != BVH_OK || m[k]->updateSubModel(p[k]) != BVH_OK ||
                m[k]->endUpdateModel(true, true) != BVH_OK)
                throw std::runtime_error("FCL: refitting the BVHModel failed");
            m[k]->computeLocalAABB();
        }
        for (auto &x : o) x->computeAABB();
    }
    ContactStats query() override {
        CollisionRequestd req(std::numeric_limits<size_t>::max(), true);
        CollisionResultd res;
        collide(o[0].get(), o[1].get(), req, res);
        ContactStats s;
        s.contacts = res.numContacts();
        for (size_t i = 0; i < res.numContacts(); i++) {
            const auto &c = res.getContact(i);
            if (c.penetration_depth == 0) s.zero_depth++;
            // Is the position one of the two triangles' vertices (fcl#106)?
            bool at_vertex = false;
            const std::vector<Vector3d> *pv[2] = {&p[0], &p[1]};
            size_t ids[2] = {size_t(c.b1), size_t(c.b2)};
            for (int k = 0; k < 2 && !at_vertex; k++)
                for (int j = 0; j < 3; j++)
                    at_vertex = at_vertex || (*pv[k])[mesh[k]->tri[3 * ids[k] + j]] == c.pos;
            s.at_vertex += at_vertex;
        }
        return s;
    }
};

} // namespace

ContactEngine *make_fcl_contacts() { return new FclContacts(); }

} // namespace peers
