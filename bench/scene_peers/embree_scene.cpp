// Embree's whole-scene way (engines.hpp): the scene collided with itself.
#include "engines.hpp"

#include "embree_geo.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace scene_peers {
namespace {

using peers::EmbreeGeo;

struct EmbreeScene : SceneEngine {
    RTCDevice dev = nullptr;
    RTCScene scene = nullptr;
    std::vector<RTCGeometry> geos;
    std::vector<EmbreeGeo> g;
    std::vector<Pair> cand;
    std::string name() const override { return "Embree rtcCollide (one scene)"; }
    ~EmbreeScene() override {
        if (scene) rtcReleaseScene(scene);
        if (dev) rtcReleaseDevice(dev);
    }
    static void collide_cb(void *user, RTCCollision *c, unsigned n) {
        auto *self = static_cast<EmbreeScene *>(user);
        for (unsigned k = 0; k < n; k++) {
            uint32_t ga = c[k].geomID0, ta = c[k].primID0, gb = c[k].geomID1, tb = c[k].primID1;
            if (ga == gb) continue; // inter-body only
            if (ga > gb) std::swap(ga, gb), std::swap(ta, tb);
            self->cand.push_back({ga, ta, gb, tb});
        }
    }
    void build(const std::vector<peers::Mesh> &ms, const Frame &f0) override {
        dev = rtcNewDevice("threads=1");
        if (!dev) throw std::runtime_error("Embree: no device");
        scene = rtcNewScene(dev);
        rtcSetSceneBuildQuality(scene, RTC_BUILD_QUALITY_LOW);
        g.resize(ms.size());
        for (size_t i = 0; i < ms.size(); i++) {
            g[i] = {&ms[i], f0.d[i].data()};
            RTCGeometry geo = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(geo, unsigned(ms[i].ntri()));
            rtcSetGeometryUserData(geo, &g[i]);
            rtcSetGeometryBoundsFunction(geo, peers::embree_bounds, nullptr);
            rtcSetGeometryBuildQuality(geo, RTC_BUILD_QUALITY_REFIT);
            rtcCommitGeometry(geo);
            rtcAttachGeometryByID(scene, geo, unsigned(i));
            geos.push_back(geo);
            rtcReleaseGeometry(geo);
        }
        rtcCommitScene(scene);
    }
    void update(const Frame &f) override {
        for (size_t i = 0; i < geos.size(); i++) {
            g[i].v = f.d[i].data();
            rtcCommitGeometry(geos[i]);
        }
        rtcCommitScene(scene);
    }
    void query(std::vector<Pair> &out) override {
        cand.clear();
        rtcCollide(scene, scene, collide_cb, this);
        std::sort(cand.begin(), cand.end());
        cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
        out.clear();
        for (const Pair &p : cand) {
            const EmbreeGeo &a = g[p.body_a], &b = g[p.body_b];
            if (peers::exact_tri_intersect(a.v, &a.mesh->tri[3 * p.tri_a], b.v, &b.mesh->tri[3 * p.tri_b]))
                out.push_back(p);
        }
    }
};
} // namespace

SceneEngine *make_embree_scene() { return new EmbreeScene(); }

} // namespace scene_peers
