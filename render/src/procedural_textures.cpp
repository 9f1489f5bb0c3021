// Built-in procedural bump textures, so scenes (and the default scene) work
// without image files. Each pattern is a height field h(s, t) in [0, 1],
// tileable over [0,1]^2, sampled at texel centres and turned into:
//   "normal"     - tangent-space normal map, rgb = 0.5 n + 0.5 with
//                  n = normalize(-dH/ds, -dH/dt, 1) and H = bumpHeight * h
//                  (heights per unit of st, OpenGL green-up convention), and
//                  the height H in alpha (the height channel derivative-space
//                  modifiers read, with height scale 1);
//   "derivative" - rg = (dH/ds, dH/dt) signed, b = H (float texels);
//   "height"     - rgb = h.
// Slopes come from central differences on the texel grid (wrapping), so the
// stored normals are exactly the derivative of the stored heights.
#include <algorithm>
#include <cmath>

#include "render_internal.h"

namespace sg::render::detail {

namespace {

float fract(float x) {
    return x - std::floor(x);
}
float smooth(float e0, float e1, float x) {
    float t = std::clamp((x - e0) / (e1 - e0), 0.0f, 1.0f);
    return t * t * (3.0f - 2.0f * t);
}
uint32_t hash(uint32_t x) {
    x ^= x >> 16;
    x *= 0x7feb352du;
    x ^= x >> 15;
    x *= 0x846ca68bu;
    x ^= x >> 16;
    return x;
}
float rand01(uint32_t x) {
    return float(hash(x) & 0xffffffu) / float(0x1000000);
}

// Bricks: 8 rows of 4, alternate rows shifted by half a brick; bevelled
// edges, slight per-brick tilt.
float bricks(float s, float t) {
    const float rows = 8.0f, cols = 4.0f;
    float y = t * rows;
    float row = std::floor(y);
    float x = s * cols + (int(row) % 2 ? 0.5f : 0.0f);
    float col = std::floor(x);
    float fx = fract(x), fy = fract(y);
    // Distance to the brick border in units of the row height.
    float dx = std::min(fx, 1.0f - fx) * rows / cols, dy = std::min(fy, 1.0f - fy);
    float d = std::min(dx, dy);
    float mortar = 0.06f, bevel = 0.12f;
    float h = smooth(mortar, mortar + bevel, d);
    uint32_t id = uint32_t(int(row) * 31 + (int(col) % int(cols) + int(cols)) % int(cols));
    float tilt = (rand01(id) - 0.5f) * 0.15f * (fx - 0.5f) + 0.9f + 0.1f * rand01(id + 7u);
    return h * tilt;
}

// Square tiles, 6 x 6, rounded bevel.
float tiles(float s, float t) {
    const float n = 6.0f;
    float fx = fract(s * n), fy = fract(t * n);
    float d = std::min(std::min(fx, 1.0f - fx), std::min(fy, 1.0f - fy));
    return smooth(0.03f, 0.15f, d);
}

// Hemispherical bumps on a staggered lattice (8 rows of 8).
float bumps(float s, float t) {
    const float n = 8.0f, r = 0.42f;
    float best = 0.0f;
    float y = t * n;
    for (int dr = -1; dr <= 1; ++dr) {
        float row = std::floor(y) + float(dr);
        float shift = (int(std::floor(row)) % 2 + 2) % 2 ? 0.5f : 0.0f;
        float x = s * n - shift;
        for (int dc = -1; dc <= 1; ++dc) {
            float cx = std::floor(x) + float(dc) + 0.5f, cy = row + 0.5f;
            float ddx = x - cx, ddy = y - cy;
            float q = 1.0f - (ddx * ddx + ddy * ddy) / (r * r);
            if (q > 0.0f) best = std::max(best, std::sqrt(q));
        }
    }
    return best;
}

// Plain weave: 8 threads each way passing over and under.
float weave(float s, float t) {
    const float n = 8.0f;
    auto thread = [&](float across, float along, float parity) {
        float c = 2.0f * fract(across * n) - 1.0f;
        float profile = std::sqrt(std::max(0.0f, 1.0f - c * c));
        float lift = 0.5f + 0.5f * std::cos(3.14159265f * (along * n + parity));
        return profile * (0.35f + 0.65f * lift);
    };
    float warp = thread(s, t, std::floor(s * n));
    float weft = thread(t, s, std::floor(t * n) + 1.0f);
    return std::max(warp, weft);
}

// Scratches: 40 random grooves (wrapped so the pattern tiles); h = 1 is
// the undamaged surface.
float scratches(float s, float t) {
    float h = 1.0f;
    for (uint32_t i = 0; i < 40u; ++i) {
        float ax = rand01(i * 4u), ay = rand01(i * 4u + 1u);
        float ang = rand01(i * 4u + 2u) * 6.2831853f, len = 0.1f + 0.3f * rand01(i * 4u + 3u);
        float dx = std::cos(ang), dy = std::sin(ang);
        for (int ox = -1; ox <= 1; ++ox)
            for (int oy = -1; oy <= 1; ++oy) {
                float px = s + float(ox) - ax, py = t + float(oy) - ay;
                float along = std::clamp(px * dx + py * dy, 0.0f, len);
                float ex = px - along * dx, ey = py - along * dy;
                float d = std::sqrt(ex * ex + ey * ey);
                h = std::min(h, 1.0f - 0.6f * (1.0f - smooth(0.0f, 0.006f, d)));
            }
    }
    return h;
}

} // namespace

TextureImage makeProceduralTexture(const TextureSource& src) {
    const int n = src.size;
    float (*fn)(float, float) = bricks;
    if (src.procedural == "tiles") fn = tiles;
    if (src.procedural == "bumps") fn = bumps;
    if (src.procedural == "weave") fn = weave;
    if (src.procedural == "scratches") fn = scratches;
    std::vector<float> h(size_t(n) * size_t(n));
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x)
            h[size_t(y) * size_t(n) + size_t(x)] =
                fn((float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n));
    auto at = [&](int x, int y) {
        return h[size_t((y + n) % n) * size_t(n) + size_t((x + n) % n)];
    };
    std::vector<glm::vec4> texels(h.size());
    const float H = src.bumpHeight;
    for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
            // Central differences: one texel is 1/n in st.
            float dHds = H * (at(x + 1, y) - at(x - 1, y)) * 0.5f * float(n);
            float dHdt = H * (at(x, y + 1) - at(x, y - 1)) * 0.5f * float(n);
            float hv = at(x, y);
            glm::vec4 out;
            if (src.output == "height") {
                out = glm::vec4(hv, hv, hv, 1.0f);
            } else if (src.output == "derivative") {
                out = glm::vec4(dHds, dHdt, H * hv, 1.0f);
            } else {
                glm::vec3 nrm = glm::normalize(glm::vec3(-dHds, -dHdt, 1.0f));
                out = glm::vec4(0.5f * nrm + 0.5f, H * hv);
            }
            texels[size_t(y) * size_t(n) + size_t(x)] = out;
        }
    return makeTexture(n, n, std::move(texels), src.wrap);
}

} // namespace sg::render::detail
