// CurveNetwork helpers (see surfgrad/features/curves.h).
#include "surfgrad/features/curves.h"

#include <glm/common.hpp>

namespace sg::features {

void CurveNetwork::bounds(glm::dvec2& lo, glm::dvec2& hi) const {
    if (segments.empty()) {
        lo = hi = glm::dvec2(0.0);
        return;
    }
    lo = hi = segments.front().p0;
    for (const auto& s : segments) {
        for (const auto& p : {s.p0, s.p1, s.p2}) {
            lo = glm::min(lo, p);
            hi = glm::max(hi, p);
        }
    }
}

} // namespace sg::features
