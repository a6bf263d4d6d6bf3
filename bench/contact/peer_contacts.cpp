// FCL 0.7 with enable_contact = true: the same model and refit as ../../examples-c/peers/
// fcl_engine.cpp (FclPair of fcl_model.hpp: BVHModel<AABBd>, refit bottom-up), and one collide() with
// num_max_contacts = SIZE_MAX and enable_contact = true, which fills Contact::pos, normal and
// penetration_depth for every intersecting triangle pair.
#include "common.hpp"

#include <fcl/fcl.h>

#include <limits>
#include <memory>
#include <stdexcept>

#include "fcl_model.hpp"
#include "peer_contacts.hpp"

namespace peers {
namespace {

using namespace fcl;

struct FclContacts : ContactEngine {
    FclPair fcl;
    const Mesh *mesh[2] = {nullptr, nullptr};

    void build(const Mesh &a, const Mesh &b, const Frame &f) override {
        fcl.set(f);
        mesh[0] = &a;
        mesh[1] = &b;
        fcl.build(a, b);
    }
    void update(const Frame &f) override {
        fcl.set(f);
        fcl.refit();
    }
    ContactStats query() override {
        CollisionRequestd req(std::numeric_limits<size_t>::max(), true);
        CollisionResultd res;
        collide(fcl.o[0].get(), fcl.o[1].get(), req, res);
        ContactStats s;
        s.contacts = res.numContacts();
        for (size_t i = 0; i < res.numContacts(); i++) {
            const auto &c = res.getContact(i);
            if (c.penetration_depth == 0) s.zero_depth++;
            // Is the position one of the two triangles' vertices (fcl#106)?
            bool at_vertex = false;
            const std::vector<Vector3d> *pv[2] = {&fcl.p[0], &fcl.p[1]};
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
