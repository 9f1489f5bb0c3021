// Shared by the antialiasing tests (antialias_test.cpp,
// antialias_compose_test.cpp): a normal map of a known slope field and its
// moment textures (LEAN A and B, Toksvig) built as the renderer builds them.
#pragma once

#include <cmath>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "render_internal.h"
#include "render_test_util.h"

namespace sg::render::test {

// A float-encoded tangent-space normal map (n as stored) of the slopes
// d = (ax cos(2 pi kx s), ay cos(2 pi ky t)) at the texel centres of an
// n x n grid: n = normalize(-d, 1) (listing 4 read backwards). Over the
// whole map var x = ax^2 / 2, var y = ay^2 / 2, cov xy = 0, mean 0.
inline TextureImage sineSlopeMap(int n, double ax, int kx, double ay, int ky) {
    constexpr double kTwoPi = 6.283185307179586;
    std::vector<glm::vec4> texels(size_t(n) * size_t(n));
    for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
            double dx = ax * std::cos(kTwoPi * kx * (i + 0.5) / n);
            double dy = ay * std::cos(kTwoPi * ky * (j + 0.5) / n);
            glm::dvec3 m = glm::normalize(glm::dvec3(-dx, -dy, 1.0));
            texels[size_t(j) * size_t(n) + size_t(i)] = glm::vec4(glm::vec3(m), 1.0f);
        }
    return makeTexture(n, n, std::move(texels), Wrap::Repeat);
}

struct Moments {
    TextureImage a, b, toksvig;
};

inline Moments momentsOf(const TextureImage& map, NormalEncoding enc = NormalEncoding::Float) {
    return {detail::normalMomentTexture(map, TexMoments::LeanA, enc),
            detail::normalMomentTexture(map, TexMoments::LeanB, enc),
            detail::normalMomentTexture(map, TexMoments::Toksvig, enc)};
}

} // namespace sg::render::test
