// The peer harness: what common.hpp declares that is not an engine or the judge.
#include "common.hpp"

#include <algorithm>
#include <cmath>

namespace peers {

void Mesh::split_polygons() {
    tri.clear();
    tri_poly.clear();
    for (size_t p = 0; p < npoly(); p++) {
        const uint32_t *q = &poly[p * vpp];
        if (vpp == 3) {
            tri.insert(tri.end(), {q[0], q[1], q[2]});
            tri_poly.push_back(uint32_t(p));
        } else { // quad (v0,v1,v2,v3) -> (v0,v1,v2), (v0,v2,v3)
            tri.insert(tri.end(), {q[0], q[1], q[2], q[0], q[2], q[3]});
            tri_poly.push_back(uint32_t(p));
            tri_poly.push_back(uint32_t(p));
        }
    }
}

void sort_unique(std::vector<Key> &v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

double median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    size_t n = v.size();
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

} // namespace peers
