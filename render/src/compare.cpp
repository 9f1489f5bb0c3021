// Comparison of vector-valued images (see compareVectorImages in
// surfgrad/render.h): angle statistics over pixels whose primitive matches.
#include <algorithm>
#include <cmath>

#include "surfgrad/render.h"

namespace sg::render {

VectorImageDiff compareVectorImages(const Image& a, const Image& b, const Image& primA,
                                    const Image& primB) {
    VectorImageDiff d;
    if (a.width != b.width || a.height != b.height || primA.width != a.width ||
        primB.width != a.width || primA.height != a.height || primB.height != a.height) {
        d.coverageMismatch = size_t(-1);
        return d;
    }
    std::vector<double> angles;
    angles.reserve(a.texelCount());
    for (int y = 0; y < a.height; ++y)
        for (int x = 0; x < a.width; ++x) {
            float pa = primA.rgba(x, y).x, pb = primB.rgba(x, y).x;
            if (pa != pb) {
                ++d.coverageMismatch;
                continue;
            }
            if (pa <= 0.0f) continue; // background in both
            glm::dvec3 va(a.rgba(x, y)), vb(b.rgba(x, y));
            bool finite = true;
            for (int c = 0; c < 3; ++c)
                finite = finite && std::isfinite(va[c]) && std::isfinite(vb[c]);
            ++d.compared;
            if (!finite) {
                ++d.nonFinite;
                continue;
            }
            double la = glm::length(va), lb = glm::length(vb);
            double ang = 0.0;
            if (la > 0 && lb > 0) {
                // atan2 of |cross| and dot: accurate for tiny angles too.
                ang = std::atan2(glm::length(glm::cross(va, vb)), glm::dot(va, vb)) * 180.0 /
                      3.14159265358979;
            } else if (la != lb) {
                ang = 180.0; // one vector vanished
            }
            if (ang > d.maxDeg) {
                d.maxDeg = ang;
                d.maxX = x;
                d.maxY = y;
            }
            angles.push_back(ang);
        }
    if (angles.empty()) return d;
    double sum = 0;
    for (double x : angles) sum += x;
    d.meanDeg = sum / double(angles.size());
    std::sort(angles.begin(), angles.end());
    auto pct = [&](double p) {
        return angles[std::min(angles.size() - 1, size_t(p * double(angles.size())))];
    };
    d.p50Deg = pct(0.5);
    d.p90Deg = pct(0.9);
    d.p99Deg = pct(0.99);
    d.p999Deg = pct(0.999);
    return d;
}

} // namespace sg::render
