// FCL's multi-body way (engines.hpp).
#include "engines.hpp"

#include <fcl/fcl.h>

#include <limits>
#include <memory>
#include <stdexcept>

namespace scene_peers {
namespace {
using Model = fcl::BVHModel<fcl::AABBd>;

struct Body {
    std::shared_ptr<Model> model;
    std::unique_ptr<fcl::CollisionObjectd> obj;
    std::vector<fcl::Vector3d> p;
    void fill(const std::vector<double> &v) {
        p.resize(v.size() / 3);
        for (size_t i = 0; i < p.size(); i++) p[i] = fcl::Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
    }
};

struct Collect {
    std::vector<Pair> *out;
};

bool pair_cb(fcl::CollisionObjectd *o1, fcl::CollisionObjectd *o2, void *data) {
    auto *c = static_cast<Collect *>(data);
    fcl::CollisionRequestd req(std::numeric_limits<size_t>::max(), false);
    fcl::CollisionResultd res;
    fcl::collide(o1, o2, req, res);
    uint32_t i1 = uint32_t(reinterpret_cast<uintptr_t>(o1->getUserData()));
    uint32_t i2 = uint32_t(reinterpret_cast<uintptr_t>(o2->getUserData()));
    for (size_t k = 0; k < res.numContacts(); k++) {
        const fcl::Contactd &ct = res.getContact(k);
        uint32_t t1 = uint32_t(ct.b1), t2 = uint32_t(ct.b2);
        // b1 is a primitive of o1, b2 of o2 (collide(o1, o2) keeps the order).
        if (i1 < i2)
            c->out->push_back({i1, t1, i2, t2});
        else
            c->out->push_back({i2, t2, i1, t1});
    }
    return false; // go on
}

struct FclScene : SceneEngine {
    std::vector<Body> bodies;
    fcl::DynamicAABBTreeCollisionManagerd manager;
    std::string name() const override { return "FCL DynamicAABBTree + BVHModel<AABB>"; }
    void build(const std::vector<peers::Mesh> &ms, const Frame &f0) override {
        bodies.resize(ms.size());
        std::vector<fcl::CollisionObjectd *> objs;
        for (size_t i = 0; i < ms.size(); i++) {
            Body &b = bodies[i];
            b.fill(f0.d[i]);
            std::vector<fcl::Triangle> ts(ms[i].ntri());
            for (size_t t = 0; t < ts.size(); t++)
                ts[t] = fcl::Triangle(ms[i].tri[3 * t], ms[i].tri[3 * t + 1], ms[i].tri[3 * t + 2]);
            b.model = std::make_shared<Model>();
            if (b.model->beginModel(int(ts.size()), int(b.p.size())) != fcl::BVH_OK ||
                b.model->addSubModel(b.p, ts) != fcl::BVH_OK || b.model->endModel() != fcl::BVH_OK)
                throw std::runtime_error("FCL: building a BVHModel failed");
            b.model->computeLocalAABB();
            b.obj.reset(new fcl::CollisionObjectd(b.model, fcl::Transform3d::Identity()));
            b.obj->setUserData(reinterpret_cast<void *>(uintptr_t(i)));
            b.obj->computeAABB();
            objs.push_back(b.obj.get());
        }
        manager.registerObjects(objs);
        manager.setup();
    }
    void update(const Frame &f) override {
        for (size_t i = 0; i < bodies.size(); i++) {
            Body &b = bodies[i];
            b.fill(f.d[i]);
            if (b.model->beginUpdateModel() != fcl::BVH_OK || b.model->updateSubModel(b.p) != fcl::BVH_OK ||
                b.model->endUpdateModel(true, true) != fcl::BVH_OK)
                throw std::runtime_error("FCL: refitting a BVHModel failed");
            b.model->computeLocalAABB();
            b.obj->computeAABB();
        }
        manager.update();
    }
    void query(std::vector<Pair> &out) override {
        out.clear();
        Collect c{&out};
        manager.collide(&c, pair_cb);
    }
};
} // namespace

SceneEngine *make_fcl_scene() { return new FclScene(); }

} // namespace scene_peers
