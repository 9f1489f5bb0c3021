// The texel transformation table and the signature quantization of the
// feature-map bake. Parilov, Zorin (TOG 2008) section 4 ("a table of texel
// transformations ... maps a valid texel configuration to another valid
// texel configuration"), Fig. 5-6.
#include <array>
#include <bit>
#include <cmath>

#include "bake_internal.h"

namespace sg::features::detail {

int pairOf(int edgeA, int edgeB) {
    for (int p = 0; p < kPairCount; ++p) {
        if ((kPairEdges[p][0] == edgeA && kPairEdges[p][1] == edgeB) ||
            (kPairEdges[p][0] == edgeB && kPairEdges[p][1] == edgeA)) {
            return p;
        }
    }
    return -1;
}

namespace {

int edgesCovered(unsigned mask) {
    unsigned edges = 0;
    for (int p = 0; p < kPairCount; ++p) {
        if (mask & (1u << p)) edges |= (1u << kPairEdges[p][0]) | (1u << kPairEdges[p][1]);
    }
    return std::popcount(edges);
}

// table[mask][pair] for the 22 valid masks (at most two bits of six).
std::array<std::array<uint8_t, kPairCount>, 64> buildTable() {
    std::array<std::array<uint8_t, kPairCount>, 64> t{};
    for (unsigned mask = 0; mask < 64; ++mask) {
        for (int p = 0; p < kPairCount; ++p) {
            unsigned bit = 1u << p;
            if (std::popcount(mask) > 2) {
                t[mask][p] = uint8_t(mask); // not a valid configuration; never used
            } else if (mask & bit) {
                t[mask][p] = uint8_t(mask); // same segment type: its points merge
            } else if (std::popcount(mask) < 2) {
                t[mask][p] = uint8_t(mask | bit);
            } else {
                unsigned best = mask;
                int bestCover = edgesCovered(mask);
                for (int q = 0; q < kPairCount; ++q) {
                    if (!(mask & (1u << q))) continue;
                    unsigned cand = (mask & ~(1u << q)) | bit;
                    int cover = edgesCovered(cand);
                    if (cover > bestCover) {
                        best = cand;
                        bestCover = cover;
                    }
                }
                t[mask][p] = uint8_t(best);
            }
        }
    }
    return t;
}

} // namespace

uint8_t transition(uint8_t mask, int pair) {
    static const auto table = buildTable();
    return table[mask & 63u][size_t(pair)];
}

double quantizePos(double t) {
    double k = std::round(t * 65535.0);
    // The margin in grid steps: 2^-10 * 65535 = 63.99.. -> 64 steps.
    k = std::clamp(k, 64.0, 65535.0 - 64.0);
    return k / 65535.0;
}

// Angle code a in 1..65535 of u = tan(theta / 2) = (a - 32768) / 32767
// (layout.glsl): 0 and +-pi/2 are exact.
double quantizeAngle(double theta) {
    double a = std::round(std::tan(0.5 * wrapAngle(theta)) * 32767.0);
    a = std::clamp(a, -32767.0, 32767.0);
    return 2.0 * std::atan(a / 32767.0);
}

uint32_t packEdgeWord(double posQ, double angleQ) {
    auto p = uint32_t(std::clamp(std::lround(posQ * 65535.0), 0L, 65535L));
    double u = std::tan(0.5 * std::clamp(angleQ, -0.5 * M_PI, 0.5 * M_PI));
    auto a = uint32_t(std::clamp(std::lround(u * 32767.0), -32767L, 32767L) + 32768L);
    return p | (a << 16);
}

double& Grid::pos(int i, int j, int e) {
    switch (e) {
    case 0:
        return hPos[ci(i, j)];
    case 1:
        return vPos[ci(i + 1, j)];
    case 2:
        return hPos[ci(i, j + 1)];
    default:
        return vPos[ci(i, j)];
    }
}

double& Grid::ang(int i, int j, int e) {
    switch (e) {
    case 0:
        return hAng[ci(i, j)];
    case 1:
        return vAng[ci(i + 1, j)];
    case 2:
        return hAng[ci(i, j + 1)];
    default:
        return vAng[ci(i, j)];
    }
}

} // namespace sg::features::detail
