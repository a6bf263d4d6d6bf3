// Bullet's multi-body way (engines.hpp).
#include "engines.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/Gimpact/btGImpactQuantizedBvh.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>

#include <memory>
#include <stdexcept>

namespace scene_peers {
namespace {

struct Body {
    const peers::Mesh *mesh = nullptr;
    const double *v = nullptr; // the frame's array, read in place
    std::unique_ptr<btTriangleIndexVertexArray> arr;
    std::unique_ptr<btGImpactMeshShape> shape;
    btBroadphaseProxy *proxy = nullptr;
    btGImpactMeshShapePart *part() const { return shape->getMeshPart(0); }
    void point(const std::vector<double> &x) {
        v = x.data();
        arr->getIndexedMeshArray()[0].m_vertexBase = reinterpret_cast<const unsigned char *>(v);
    }
    void aabb(btVector3 &lo, btVector3 &hi) const { shape->getAabb(btTransform::getIdentity(), lo, hi); }
};

struct BulletScene : SceneEngine {
    std::vector<Body> bodies;
    btDefaultCollisionConfiguration config;
    btCollisionDispatcher dispatcher{&config};
    btDbvtBroadphase broadphase;
    btPairSet pairs;
    std::string name() const override {
        return h > 0 ? "Bullet GImpact (boxes + h/2), FCL triangle distance <= h" : "Bullet btDbvtBroadphase + GImpact";
    }
    ~BulletScene() override {
        for (auto &b : bodies)
            if (b.proxy) broadphase.destroyProxy(b.proxy, &dispatcher);
    }
    void build(const std::vector<peers::Mesh> &ms, const Frame &f0) override {
        bodies.resize(ms.size());
        for (size_t i = 0; i < ms.size(); i++) {
            Body &b = bodies[i];
            const peers::Mesh &m = ms[i];
            b.mesh = &m;
            b.v = f0.d[i].data();
            btIndexedMesh im;
            im.m_numTriangles = int(m.ntri());
            im.m_triangleIndexBase = reinterpret_cast<const unsigned char *>(m.tri.data());
            im.m_triangleIndexStride = 3 * sizeof(uint32_t);
            im.m_numVertices = int(m.nv());
            im.m_vertexBase = reinterpret_cast<const unsigned char *>(b.v);
            im.m_vertexStride = 3 * sizeof(double);
            im.m_indexType = PHY_INTEGER;
            im.m_vertexType = PHY_DOUBLE;
            b.arr.reset(new btTriangleIndexVertexArray());
            b.arr->addIndexedMesh(im, PHY_INTEGER);
            b.shape.reset(new btGImpactMeshShape(b.arr.get()));
            // Margin: one quantum of the 16-bit frame (the harness's sound setting), plus h / 2
            // within a band (two boxes then meet when their primitives are within h).
            double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}, size = 0;
            for (size_t k = 0; k < 3 * m.nv(); k++) lo[k % 3] = std::min(lo[k % 3], b.v[k]), hi[k % 3] = std::max(hi[k % 3], b.v[k]);
            for (int k = 0; k < 3; k++) size = std::max(size, hi[k] - lo[k] + 2.0);
            b.shape->setMargin(btScalar(size / 65535.0 + h / 2));
            b.shape->updateBound();
            btVector3 a0, a1;
            b.aabb(a0, a1);
            b.proxy = broadphase.createProxy(a0, a1, GIMPACT_SHAPE_PROXYTYPE, reinterpret_cast<void *>(uintptr_t(i)),
                                             1, -1, &dispatcher);
        }
    }
    void update(const Frame &f) override {
        for (size_t i = 0; i < bodies.size(); i++) {
            Body &b = bodies[i];
            b.point(f.d[i]);
            b.shape->postUpdate();
            b.shape->updateBound(); // refit
            btVector3 a0, a1;
            b.aabb(a0, a1);
            broadphase.setAabb(b.proxy, a0, a1, &dispatcher);
        }
        broadphase.calculateOverlappingPairs(&dispatcher);
    }
    void query(std::vector<Pair> &out) override {
        out.clear();
        btBroadphasePairArray &arr = broadphase.getOverlappingPairCache()->getOverlappingPairArray();
        btTransform I = btTransform::getIdentity();
        for (int k = 0; k < arr.size(); k++) {
            uint32_t i = uint32_t(reinterpret_cast<uintptr_t>(arr[k].m_pProxy0->m_clientObject));
            uint32_t j = uint32_t(reinterpret_cast<uintptr_t>(arr[k].m_pProxy1->m_clientObject));
            if (i > j) std::swap(i, j);
            const Body &a = bodies[i], &b = bodies[j];
            pairs.clear();
            btGImpactQuantizedBvh::find_collision(a.part()->getBoxSet(), I, b.part()->getBoxSet(), I, pairs);
            for (int q = 0; q < pairs.size(); q++) {
                uint32_t ta = uint32_t(pairs[q].m_index1), tb = uint32_t(pairs[q].m_index2);
                const uint32_t *x = &a.mesh->tri[3 * ta], *y = &b.mesh->tri[3 * tb];
                if (h > 0 ? tri_distance(a.v, x, b.v, y) <= h : peers::exact_tri_intersect(a.v, x, b.v, y))
                    out.push_back({i, ta, j, tb});
            }
        }
    }
};
} // namespace

SceneEngine *make_bullet_scene() { return new BulletScene(); }

} // namespace scene_peers
