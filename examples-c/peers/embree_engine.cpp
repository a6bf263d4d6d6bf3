// Embree 3.13: one scene per mesh with one user geometry (rtcCollide needs user geometry),
// REFIT geometry quality under a LOW-quality scene (the two-level builder, which honours
// REFIT), bounds rounded outward to float, rtcCollide candidates then an exact test (CGAL):
// the sound configuration of ../shared/peers/REPORT.md §4. One thread (threads=1).
#include "embree_geo.hpp"

#include <atomic>
#include <cmath>
#include <mutex>

namespace peers {
namespace {
using Geo = EmbreeGeo;

std::atomic<long long> g_bytes{0};
bool monitor(void*, ssize_t bytes, bool) {
    g_bytes += bytes;
    return true;
}

struct EmbreeEngine : Engine {
    RTCDevice dev = nullptr;
    RTCScene sc[2] = {nullptr, nullptr};
    RTCGeometry geo[2] = {nullptr, nullptr};
    Geo g[2];
    std::mutex mu;
    std::vector<Key> cand;
    long long mem = 0;
    std::string name() const override { return "embree_collide"; }
    ~EmbreeEngine() override {
        for (auto s : sc)
            if (s) rtcReleaseScene(s);
        if (dev) rtcReleaseDevice(dev);
    }
    void build(const Mesh& a, const Mesh& b, const Frame& f) override {
        dev = rtcNewDevice("threads=1");
        rtcSetDeviceMemoryMonitorFunction(dev, monitor, nullptr);
        long long before = g_bytes;
        const Mesh* ms[2] = {&a, &b};
        const std::vector<double>* vs[2] = {&f.ad, &f.bd};
        for (int i = 0; i < 2; i++) {
            g[i].mesh = ms[i];
            g[i].v = vs[i]->data();
            sc[i] = rtcNewScene(dev);
            rtcSetSceneBuildQuality(sc[i], RTC_BUILD_QUALITY_LOW);
            geo[i] = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_USER);
            rtcSetGeometryUserPrimitiveCount(geo[i], unsigned(ms[i]->ntri()));
            rtcSetGeometryUserData(geo[i], &g[i]);
            rtcSetGeometryBoundsFunction(geo[i], embree_bounds, nullptr);
            rtcSetGeometryBuildQuality(geo[i], RTC_BUILD_QUALITY_REFIT);
            rtcCommitGeometry(geo[i]);
            rtcAttachGeometry(sc[i], geo[i]);
            rtcReleaseGeometry(geo[i]);
            rtcCommitScene(sc[i]);
        }
        mem = g_bytes - before;
    }
    // The bounds callback reads the caller's array in place.
    void prepare(const Frame& f) override {
        g[0].v = f.ad.data();
        g[1].v = f.bd.data();
    }
    void update(const Frame&) override {
        for (int i = 0; i < 2; i++) {
            rtcCommitGeometry(geo[i]);
            rtcCommitScene(sc[i]);
        }
    }
    static void collide_cb(void* user, RTCCollision* c, unsigned n) {
        auto* e = static_cast<EmbreeEngine*>(user);
        std::lock_guard<std::mutex> l(e->mu);
        for (unsigned i = 0; i < n; i++) e->cand.push_back(key(c[i].primID0, c[i].primID1));
    }
    void query(std::vector<Key>& out) override {
        cand.clear();
        rtcCollide(sc[0], sc[1], collide_cb, this);
        out.clear();
        const Mesh &a = *g[0].mesh, &b = *g[1].mesh;
        for (Key k : cand)
            if (exact_tri_intersect(g[0].v, &a.tri[3 * key_a(k)], g[1].v, &b.tri[3 * key_b(k)])) out.push_back(k);
    }
    size_t bytes() const override { return size_t(mem > 0 ? mem : 0); }
    std::string memory_note() const override {
        return "bytes Embree's device reported allocating while building both scenes "
               "(rtcSetDeviceMemoryMonitorFunction)";
    }
};
} // namespace

Engine* make_embree() { return new EmbreeEngine(); }

} // namespace peers
