// The band question asked of a peer: the distance of two triangles, by FCL's own triangle
// distance (the PQP algorithm FCL's distance queries use), in double.
#include "engines.hpp"

#include <fcl/narrowphase/detail/primitive_shape_algorithm/triangle_distance.h>

namespace scene_peers {

double tri_distance(const double *pa, const uint32_t *ta, const double *pb, const uint32_t *tb) {
    fcl::Vector3d s[3], t[3], p, q;
    for (int k = 0; k < 3; k++) {
        s[k] = fcl::Vector3d(pa[3 * ta[k]], pa[3 * ta[k] + 1], pa[3 * ta[k] + 2]);
        t[k] = fcl::Vector3d(pb[3 * tb[k]], pb[3 * tb[k] + 1], pb[3 * tb[k] + 2]);
    }
    return fcl::detail::TriangleDistance<double>::triDistance(s, t, p, q);
}

} // namespace scene_peers
