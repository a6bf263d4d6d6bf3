// Bullet 3.24 (double): btGImpactMeshShape over the caller's double array, refit with
// postUpdate() + updateBound(), box pairs from btGImpactQuantizedBvh::find_collision, then
// an exact test (CGAL): the sound configuration of peers/REPORT.md §3.
#include <btBulletCollisionCommon.h>
#include <BulletCollision/Gimpact/btGImpactQuantizedBvh.h>
#include <BulletCollision/Gimpact/btGImpactShape.h>

#include <memory>

#include "common.h"

namespace {
struct Side {
  std::unique_ptr<btTriangleIndexVertexArray> arr;
  std::unique_ptr<btGImpactMeshShape> shape;
  const Mesh* mesh = nullptr;
  const double* verts = nullptr;
};

struct BulletEngine : Engine {
  double margin[2];
  Side s[2];
  BulletEngine(double ma, double mb) : margin{ma, mb} {}
  std::string name() const override { return "bullet_gimpact"; }
  void point(Side& x, const std::vector<double>& v) {
    x.verts = v.data();
    x.arr->getIndexedMeshArray()[0].m_vertexBase = reinterpret_cast<const unsigned char*>(v.data());
  }
  void make(Side& x, const Mesh& m, const std::vector<double>& v, double mg) {
    x.mesh = &m;
    btIndexedMesh im;
    im.m_numTriangles = int(m.nt());
    im.m_triangleIndexBase = reinterpret_cast<const unsigned char*>(m.t.data());
    im.m_triangleIndexStride = 3 * sizeof(uint32_t);
    im.m_numVertices = int(m.nv());
    im.m_vertexBase = reinterpret_cast<const unsigned char*>(v.data());
    im.m_vertexStride = 3 * sizeof(double);
    im.m_indexType = PHY_INTEGER;
    im.m_vertexType = PHY_DOUBLE;
    x.arr.reset(new btTriangleIndexVertexArray());
    x.arr->addIndexedMesh(im, PHY_INTEGER);
    x.shape.reset(new btGImpactMeshShape(x.arr.get()));
    x.shape->setMargin(mg);
    x.shape->updateBound();
    x.verts = v.data();
  }
  void build(const Mesh& a, const Mesh& b, const Frame& f) override {
    make(s[0], a, f.ad, margin[0]);
    make(s[1], b, f.bd, margin[1]);
  }
  // Bullet reads the caller's array in place: the frame's array becomes the mesh's array.
  void prepare(const Frame& f) override {
    point(s[0], f.ad);
    point(s[1], f.bd);
  }
  void update(const Frame&) override {
    for (auto& x : s) {
      x.shape->postUpdate();
      x.shape->updateBound();
    }
  }
  void query(std::vector<Pair>& out) override {
    btPairSet pairs;
    btTransform I = btTransform::getIdentity();
    btGImpactQuantizedBvh::find_collision(s[0].shape->getMeshPart(0)->getBoxSet(), I,
                                          s[1].shape->getMeshPart(0)->getBoxSet(), I, pairs);
    out.clear();
    const Mesh &a = *s[0].mesh, &b = *s[1].mesh;
    const double *av = s[0].verts, *bv = s[1].verts;
    for (int k = 0; k < pairs.size(); k++) {
      uint32_t i = uint32_t(pairs[k].m_index1), j = uint32_t(pairs[k].m_index2);
      const uint32_t* ta = &a.t[3 * i];
      const uint32_t* tb = &b.t[3 * j];
      if (tri_exact(av + 3 * ta[0], av + 3 * ta[1], av + 3 * ta[2], bv + 3 * tb[0], bv + 3 * tb[1],
                    bv + 3 * tb[2]))
        out.push_back({i, j});
    }
  }
  size_t bytes() const override {
    size_t n = 0;
    for (auto& x : s)
      n += size_t(x.shape->getMeshPart(0)->getBoxSet()->getNodeCount()) * sizeof(BT_QUANTIZED_BVH_NODE);
    return n;
  }
  std::string memory_note() const override {
    return "BT_QUANTIZED_BVH_NODE " + std::to_string(sizeof(BT_QUANTIZED_BVH_NODE)) +
           " B x getNodeCount() (2n-1); vertices stay in the caller's array (not counted)";
  }
};
}  // namespace

Engine* make_bullet(double ma, double mb) { return new BulletEngine(ma, mb); }
