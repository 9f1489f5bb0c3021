// MIP chains for normal-map antialiasing (Loviscach 2008, "Care:
// Antialiasing (1)-(2)"): LEAN moments (Olano and Baker 2010) and Toksvig's
// averaged normals (Toksvig 2005) filtered level by level; the per-texel
// math is shaders/sg/lean.glsl. The file layout is documented in
// surfgrad/normalmap/operations.h ("MIP chains for antialiasing").
#include <algorithm>
#include <cmath>

#include "normalmap_internal.h"

namespace sg::normalmap {

namespace g = sg::glsl;
using detail::forRows;

std::vector<std::pair<int, int>> mipSizes(int width, int height) {
    std::vector<std::pair<int, int>> s;
    int w = width, h = height;
    s.emplace_back(w, h);
    while (w > 1 || h > 1) {
        w = std::max(1, w / 2);
        h = std::max(1, h / 2);
        s.emplace_back(w, h);
    }
    return s;
}

namespace {

// Source texels (index, weight) each output texel of one axis averages: the
// overlap of [i n / m, (i + 1) n / m) with each source texel, divided by the
// footprint's length n / m (weights sum to 1).
std::vector<std::vector<std::pair<int, double>>> boxWeights(int n, int m) {
    std::vector<std::vector<std::pair<int, double>>> w(static_cast<size_t>(m));
    const double ratio = double(n) / double(m);
    for (int i = 0; i < m; ++i) {
        const double a = i * ratio, b = (i + 1) * ratio;
        for (int k = int(std::floor(a)); k < n && double(k) < b; ++k) {
            const double overlap = std::min(b, double(k + 1)) - std::max(a, double(k));
            if (overlap > 1e-12) w[size_t(i)].emplace_back(k, overlap / ratio);
        }
    }
    return w;
}

} // namespace

Image boxReduce(const Image& src, int width, int height) {
    const int nc = src.channels;
    const auto wx = boxWeights(src.width, width), wy = boxWeights(src.height, height);
    // Along x into (width x src.height), then along y.
    std::vector<double> tmp(size_t(width) * size_t(src.height) * size_t(nc), 0.0);
    forRows(src.height, [&](int j) {
        for (int i = 0; i < width; ++i) {
            double* o = &tmp[(size_t(j) * size_t(width) + size_t(i)) * size_t(nc)];
            for (const auto& [k, wt] : wx[size_t(i)])
                for (int c = 0; c < nc; ++c) o[c] += wt * src.at(k, j, c);
        }
    });
    Image dst(width, height, nc);
    dst.isFloat = true;
    forRows(height, [&](int j) {
        std::vector<double> acc(static_cast<size_t>(nc));
        for (int i = 0; i < width; ++i) {
            std::fill(acc.begin(), acc.end(), 0.0);
            for (const auto& [k, wt] : wy[size_t(j)]) {
                const double* s = &tmp[(size_t(k) * size_t(width) + size_t(i)) * size_t(nc)];
                for (int c = 0; c < nc; ++c) acc[size_t(c)] += wt * s[c];
            }
            for (int c = 0; c < nc; ++c) dst.at(i, j, c) = float(acc[size_t(c)]);
        }
    });
    return dst;
}

Image leanLevel0(const DerivField& d) {
    Image img(d.width, d.height, 5);
    img.isFloat = true;
    forRows(d.height, [&](int j) {
        for (int i = 0; i < d.width; ++i) {
            const glm::vec2 s = d.at(i, j);
            const glm::vec3 m = g::sgLeanSecondMoments(s);
            const float v[5] = {s.x, s.y, m.x, m.y, m.z};
            for (int c = 0; c < 5; ++c) img.at(i, j, c) = v[c];
        }
    });
    return img;
}

Image toksvigLevel0(const NormalField& n) {
    Image img(n.width, n.height, 4);
    img.isFloat = true;
    forRows(n.height, [&](int j) {
        for (int i = 0; i < n.width; ++i) {
            const glm::vec3 v = n.at(i, j);
            img.at(i, j, 0) = v.x;
            img.at(i, j, 1) = v.y;
            img.at(i, j, 2) = v.z;
            img.at(i, j, 3) = g::sgToksvigVariance(v);
        }
    });
    return img;
}

Image naiveMipLevel0(const NormalField& n) {
    Image img(n.width, n.height, 3);
    img.isFloat = true;
    for (size_t k = 0; k < n.size(); ++k)
        for (int c = 0; c < 3; ++c) img.samples[k * 3 + size_t(c)] = n.v[k][c];
    return img;
}

std::vector<Image> mipChain(Image level0, const Progress& progress) {
    const auto sizes = mipSizes(level0.width, level0.height);
    std::vector<Image> levels;
    levels.reserve(sizes.size());
    levels.push_back(std::move(level0));
    for (size_t k = 1; k < sizes.size(); ++k) {
        levels.push_back(boxReduce(levels.back(), sizes[k].first, sizes[k].second));
        if (progress) progress(double(k) / double(sizes.size() - 1));
    }
    return levels;
}

void finishToksvig(std::vector<Image>& levels) {
    for (Image& L : levels) {
        forRows(L.height, [&](int j) {
            for (int i = 0; i < L.width; ++i) {
                const glm::vec3 avg(L.at(i, j, 0), L.at(i, j, 1), L.at(i, j, 2));
                L.at(i, j, 3) = g::sgToksvigVariance(avg);
            }
        });
    }
}

void finishNaiveMips(std::vector<Image>& levels) {
    for (Image& L : levels) {
        forRows(L.height, [&](int j) {
            for (int i = 0; i < L.width; ++i) {
                const glm::vec3 v = g::sgSafeNormalize(
                    glm::vec3(L.at(i, j, 0), L.at(i, j, 1), L.at(i, j, 2)), detail::kFlat);
                for (int c = 0; c < 3; ++c) L.at(i, j, c) = v[c];
            }
        });
    }
}

} // namespace sg::normalmap
