// Bullet 3.24 (libbullet-dev, double build `bullet-float64`) through GImpact.
//
// Route, and why (see ../shared/peers/REPORT.md §3):
// * Bullet has no query that returns every intersecting triangle pair of two meshes. A
//   collision world reports contact *manifolds* of at most 4 points per object pair, so it
//   would drop pairs; btBvhTriangleMeshShape can refit but has no tree-vs-tree query.
// * GImpact has both: btGImpactMeshShape over a btTriangleIndexVertexArray that points at
//   the caller's double vertices in place (PHY_DOUBLE), refit per frame with postUpdate() +
//   updateBound() (btGImpactQuantizedBvh::refit: leaf boxes from the triangles, parents
//   merged bottom-up), and the public static btGImpactQuantizedBvh::find_collision(), which
//   returns every pair of triangles whose boxes overlap.
// * The triangle test after it: GImpact's own one (collide_sat_triangles: clip each triangle
//   by the other's edge planes, accept points below the other's plane within the margin) is
//   a *penetration* test, not an intersection test; it accepts triangles facing each other
//   behind the surface (bullet3#4318). So query() is find_collision + the exact CGAL test
//   (it checks that Bullet's broad phase is conservative), and GImpact's native test,
//   reproduced with the public calls getPrimitiveTriangle / buildTriPlane /
//   overlap_test_conservative / find_triangle_collision_clip_method with margin 0, is
//   native(), which the cross-check reports as a finding only.
// * Quantization: the 16-bit frame (m_global_bound) is fixed at buildSet(), padded by 1.0,
//   and a refit *clamps* boxes into it, which can lose pairs once a mesh leaves it; it also
//   rounds to nearest. So the margin is at least one quantum (>= half a quantum) and, with
//   the rebuild guard, when a mesh's box leaves the frame it was built in, the set is rebuilt
//   (buildSet) instead of refit; rebuilds() counts them. Without the guard (refit only, as
//   REPORT.md measured it, and as the benchmark times it) rebuilds() counts the times a mesh
//   was out of its frame, which shows what the clamping does.
#include "common.hpp"

#include <btBulletCollisionCommon.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>
#include <BulletCollision/Gimpact/btGImpactQuantizedBvh.h>
#include <BulletCollision/Gimpact/btTriangleShapeEx.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>

namespace peers {
namespace {

struct Side {
    const Mesh *mesh = nullptr;
    const double *v = nullptr; // the caller's array; Bullet reads it in place
    std::unique_ptr<btTriangleIndexVertexArray> arr;
    std::unique_ptr<btGImpactMeshShape> shape;
    double margin = 0;
    double frame_lo[3], frame_hi[3]; // the quantization frame of the last buildSet
    bool out = false;                // prepare: the mesh has left that frame

    btGImpactMeshShapePart *part() const { return shape->getMeshPart(0); }
    void point(const std::vector<double> &x) {
        v = x.data();
        arr->getIndexedMeshArray()[0].m_vertexBase = reinterpret_cast<const unsigned char *>(v);
    }
    void bounds(double lo[3], double hi[3]) const {
        for (int k = 0; k < 3; k++) lo[k] = HUGE_VAL, hi[k] = -HUGE_VAL;
        for (size_t i = 0; i < 3 * mesh->nv(); i++) {
            int k = int(i % 3);
            lo[k] = std::min(lo[k], v[i]);
            hi[k] = std::max(hi[k], v[i]);
        }
    }
    // What calc_quantization does: primitive boxes (with margin) padded by 1.0.
    void remember_frame() {
        bounds(frame_lo, frame_hi);
        for (int k = 0; k < 3; k++) frame_lo[k] -= margin + 1.0, frame_hi[k] += margin + 1.0;
    }
    bool outside_frame() const {
        double lo[3], hi[3];
        bounds(lo, hi);
        for (int k = 0; k < 3; k++)
            if (lo[k] - margin < frame_lo[k] || hi[k] + margin > frame_hi[k]) return true;
        return false;
    }
    void make(const Mesh &m, const std::vector<double> &x, double mg) {
        mesh = &m;
        v = x.data();
        btIndexedMesh im;
        im.m_numTriangles = int(m.ntri());
        im.m_triangleIndexBase = reinterpret_cast<const unsigned char *>(m.tri.data());
        im.m_triangleIndexStride = 3 * sizeof(uint32_t);
        im.m_numVertices = int(m.nv());
        im.m_vertexBase = reinterpret_cast<const unsigned char *>(v);
        im.m_vertexStride = 3 * sizeof(double);
        im.m_indexType = PHY_INTEGER;
        im.m_vertexType = PHY_DOUBLE;
        arr.reset(new btTriangleIndexVertexArray());
        arr->addIndexedMesh(im, PHY_INTEGER);
        shape.reset(new btGImpactMeshShape(arr.get()));
        if (mg <= 0) { // one quantum of the frame buildSet will choose
            double lo[3], hi[3], size = 0;
            bounds(lo, hi);
            for (int k = 0; k < 3; k++) size = std::max(size, hi[k] - lo[k] + 2.0);
            mg = size / 65535.0;
        }
        margin = mg;
        shape->setMargin(btScalar(margin));
        shape->updateBound(); // buildSet on the first call
        remember_frame();
        if (shape->getMeshPartCount() != 1) throw std::runtime_error("Bullet: expected 1 part");
    }
};

struct BulletImpl : BulletEngine {
    double margin[2];
    bool guard;
    Side s[2];
    btPairSet pairs; // the last query's candidates
    int count = 0;

    BulletImpl(double ma, double mb, bool g) : margin{ma, mb}, guard(g) {}
    std::string name() const override { return "bullet_gimpact"; }
    void build(const Mesh &a, const Mesh &b, const Frame &f) override {
        s[0].make(a, f.ad, margin[0]);
        s[1].make(b, f.bd, margin[1]);
    }
    // The frame's arrays become the meshes' arrays.
    void prepare(const Frame &f) override {
        s[0].point(f.ad);
        s[1].point(f.bd);
        if (!guard)
            for (auto &x : s) count += x.outside_frame(); // counted only: refit clamps into the stale frame
    }
    void update(const Frame &) override {
        for (auto &x : s) {
            if (guard && x.outside_frame()) {
                btGImpactMeshShapePart *part = x.part();
                part->lockChildShapes();
                const_cast<btGImpactQuantizedBvh *>(part->getBoxSet())->buildSet();
                part->unlockChildShapes();
                x.remember_frame();
                count++;
            }
            x.shape->postUpdate();
            x.shape->updateBound(); // refit
        }
    }
    void query(std::vector<Key> &out) override {
        pairs.clear();
        btTransform I = btTransform::getIdentity();
        btGImpactQuantizedBvh::find_collision(s[0].part()->getBoxSet(), I, s[1].part()->getBoxSet(), I, pairs);
        out.clear();
        const Mesh &a = *s[0].mesh, &b = *s[1].mesh;
        for (int k = 0; k < pairs.size(); k++) {
            uint32_t i = uint32_t(pairs[k].m_index1), j = uint32_t(pairs[k].m_index2);
            if (exact_tri_intersect(s[0].v, &a.tri[3 * i], s[1].v, &b.tri[3 * j])) out.push_back(key(i, j));
        }
    }
    void native(std::vector<Key> &out) override {
        out.clear();
        btGImpactMeshShapePart *pa = s[0].part(), *pb = s[1].part();
        pa->lockChildShapes();
        pb->lockChildShapes();
        btPrimitiveTriangle t0, t1;
        GIM_TRIANGLE_CONTACT contact;
        for (int k = 0; k < pairs.size(); k++) {
            pa->getPrimitiveTriangle(pairs[k].m_index1, t0);
            pb->getPrimitiveTriangle(pairs[k].m_index2, t1);
            t0.m_margin = 0;
            t1.m_margin = 0;
            t0.buildTriPlane();
            t1.buildTriPlane();
            if (t0.overlap_test_conservative(t1) && t0.find_triangle_collision_clip_method(t1, contact))
                out.push_back(key(uint32_t(pairs[k].m_index1), uint32_t(pairs[k].m_index2)));
        }
        pa->unlockChildShapes();
        pb->unlockChildShapes();
    }
    int rebuilds() const override { return count; }
    size_t bytes() const override {
        size_t n = 0;
        for (auto &x : s) n += size_t(x.part()->getBoxSet()->getNodeCount()) * sizeof(BT_QUANTIZED_BVH_NODE);
        return n;
    }
    std::string memory_note() const override {
        return "BT_QUANTIZED_BVH_NODE " + std::to_string(sizeof(BT_QUANTIZED_BVH_NODE)) +
               " B x getNodeCount() (2n-1); vertices stay in the caller's array (not counted)";
    }
};

} // namespace

BulletEngine *make_bullet(double ma, double mb, bool rebuild_guard) { return new BulletImpl(ma, mb, rebuild_guard); }

} // namespace peers
