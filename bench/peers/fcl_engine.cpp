// FCL 0.7: BVHModel<AABBd>, refit bottom-up (the sound configuration, peers/REPORT.md §2).
#include <fcl/fcl.h>

#include <limits>
#include <memory>

#include "common.h"

namespace {
using namespace fcl;
struct FclEngine : Engine {
  std::shared_ptr<BVHModel<AABBd>> ma, mb;
  std::unique_ptr<CollisionObjectd> oa, ob;
  std::vector<Vector3d> pa, pb;  // the caller's arrays in FCL's type (filled untimed)
  size_t na = 0, nb = 0;
  std::string name() const override { return "fcl_aabb"; }
  static void fill(std::vector<Vector3d>& dst, const std::vector<double>& v) {
    dst.resize(v.size() / 3);
    for (size_t i = 0; i < dst.size(); i++) dst[i] = Vector3d(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
  }
  static std::shared_ptr<BVHModel<AABBd>> model(const Mesh& m, const std::vector<Vector3d>& ps) {
    auto bm = std::make_shared<BVHModel<AABBd>>();
    std::vector<Triangle> ts(m.nt());
    for (size_t i = 0; i < m.nt(); i++) ts[i] = Triangle(m.t[3 * i], m.t[3 * i + 1], m.t[3 * i + 2]);
    bm->beginModel(int(m.nt()), int(m.nv()));
    bm->addSubModel(ps, ts);
    bm->endModel();
    bm->computeLocalAABB();
    return bm;
  }
  void build(const Mesh& a, const Mesh& b, const Frame& f) override {
    fill(pa, f.ad);
    fill(pb, f.bd);
    ma = model(a, pa);
    mb = model(b, pb);
    oa.reset(new CollisionObjectd(ma));
    ob.reset(new CollisionObjectd(mb));
    na = a.nt();
    nb = b.nt();
  }
  void prepare(const Frame& f) override {
    fill(pa, f.ad);
    fill(pb, f.bd);
  }
  void update(const Frame& f) override {
    // the caller's arrays in Vector3d are made outside the timed region (prepare_frame)
    for (auto* x : {&ma, &mb}) {
      auto& m = *x;
      m->beginUpdateModel();
      m->updateSubModel(x == &ma ? pa : pb);
      m->endUpdateModel(true, true);
      m->computeLocalAABB();
    }
    oa->computeAABB();
    ob->computeAABB();
  }
  void query(std::vector<Pair>& out) override {
    CollisionRequestd req(std::numeric_limits<int>::max(), false);
    CollisionResultd res;
    collide(oa.get(), ob.get(), req, res);
    out.clear();
    for (size_t i = 0; i < res.numContacts(); i++) {
      const auto& c = res.getContact(i);
      out.push_back({uint32_t(c.b1), uint32_t(c.b2)});
    }
  }
  size_t model_bytes(const BVHModel<AABBd>& m) const {
    return size_t(m.getNumBVs()) * sizeof(BVNode<AABBd>) + size_t(m.num_vertices) * 2 * sizeof(Vector3d) +
           size_t(m.num_tris) * (sizeof(Triangle) + sizeof(unsigned int));
  }
  size_t bytes() const override { return model_bytes(*ma) + model_bytes(*mb); }
  std::string memory_note() const override {
    return "BVNode<AABBd> " + std::to_string(sizeof(BVNode<AABBd>)) + " B x (2n-1) + vertices and prev_vertices (2x24 B/vertex) + triangles (12 B) + primitive_indices (4 B); the per-query deep copy of both models is not counted";
  }
};
}  // namespace

Engine* make_fcl() { return new FclEngine(); }
