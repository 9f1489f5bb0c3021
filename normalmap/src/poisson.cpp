// Height <-> slopes ("Birth of Normal Vectors", Loviscach 2008: the map
// stores normalize(-dh/du, -dh/dv, 1) from central differences) and back:
// the least-squares height of a slope field (Poisson integration), exact
// on the range of the central-difference operator.
//
// The normal equations of min_h |Dx h - gx|^2 + |Dy h - gy|^2, with Dx, Dy
// the central differences of fromHeight, are diagonal in a Fourier basis:
//  - Repeat (periodic grid): Dx multiplies frequency k by i sin(2 pi k / W),
//    so H = -i (sx Gx + sy Gy) / (sx^2 + sy^2);
//  - Clamp (border texel repeated = mirrored extension, Neumann): Dx maps
//    the cosine basis cos(pi k (u + 1/2) / W) (DCT-II) to -sin(pi k / W)
//    times the sine basis sin(pi k (u + 1/2) / W) (DST-II), so with
//    orthonormal transforms A = -(sx Gx + sy Gy) / (sx^2 + sy^2). The
//    central difference of the mirrored grid is half the one-sided
//    difference at the border; fromHeight stores the one-sided one (the
//    better slope estimate there) and the solve halves it back.
// Frequencies with sx = sy = 0 are not seen by the differences: set to 0.
#include <algorithm>
#include <cmath>
#include <limits>

#include "fft.h"
#include "normalmap_internal.h"

namespace sg::normalmap {

namespace g = sg::glsl;
using detail::cplx;
using detail::forRows;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Below this the sum of squared sines is a frequency the central difference
// does not see (exactly 0 in exact arithmetic; sin(pi) rounds to 1e-16).
constexpr double kNullSymbol = 1e-20;

// 1D transform `f(line, a, s)` applied to every row, then to every column,
// of a W x H array of T (columns gathered into contiguous lines).
template <class T, class F>
void alongRows(std::vector<T>& data, int w, int h, F&& f) {
    forRows(h, [&](int j) {
        thread_local std::vector<cplx> a, s;
        f(&data[size_t(j) * size_t(w)], a, s);
    });
}
template <class T, class F>
void alongColumns(std::vector<T>& data, int w, int h, F&& f) {
    forRows(w, [&](int i) {
        thread_local std::vector<T> line;
        thread_local std::vector<cplx> a, s;
        line.resize(size_t(h));
        for (int j = 0; j < h; ++j) line[size_t(j)] = data[size_t(j) * size_t(w) + size_t(i)];
        f(line.data(), a, s);
        for (int j = 0; j < h; ++j) data[size_t(j) * size_t(w) + size_t(i)] = line[size_t(j)];
    });
}

void report(const Progress& p, double f) {
    if (p) p(f);
}

// Measures a height from its lowest texel.
ScalarField finish(const std::vector<double>& h, int w, int hgt) {
    ScalarField out(w, hgt);
    double lo = std::numeric_limits<double>::infinity();
    for (double x : h) lo = std::min(lo, x);
    for (size_t k = 0; k < h.size(); ++k) out.v[k] = float(h[k] - lo);
    return out;
}

ScalarField solvePeriodic(const DerivField& d, const Progress& progress) {
    const int w = d.width, h = d.height;
    std::vector<cplx> z(d.size());
    for (size_t k = 0; k < z.size(); ++k) z[k] = cplx(d.v[k].x, d.v[k].y);
    const detail::Fft fw(w), fh(h);
    auto fftRows = [&](bool inv) {
        alongRows(z, w, h, [&](cplx* line, auto&, auto& s) { fw.transform(line, inv, s); });
    };
    auto fftCols = [&](bool inv) {
        alongColumns(z, w, h, [&](cplx* line, auto&, auto& s) { fh.transform(line, inv, s); });
    };
    fftRows(false);
    report(progress, 0.25);
    fftCols(false);
    report(progress, 0.5);
    // Z = FFT(gx + i gy): Gx = (Z_k + conj Z_-k) / 2, Gy = (Z_k - conj Z_-k) / 2i.
    // Each pair (k, -k) is solved together and written in place.
    forRows(h, [&](int l) {
        const int lm = (h - l) % h;
        const double sy = std::sin(2.0 * kPi * l / h);
        for (int k = 0; k < w; ++k) {
            const int km = (w - k) % w;
            const size_t a = size_t(l) * size_t(w) + size_t(k),
                         b = size_t(lm) * size_t(w) + size_t(km);
            if (b < a) continue; // handled with its mirror
            const double sx = std::sin(2.0 * kPi * k / w);
            const double den = sx * sx + sy * sy;
            const cplx za = z[a], zb = z[b];
            auto solve = [&](cplx zk, cplx zmk, double ssx, double ssy) {
                if (den < kNullSymbol) return cplx(0.0);
                const cplx gx = 0.5 * (zk + std::conj(zmk));
                const cplx gy = cplx(0.0, -0.5) * (zk - std::conj(zmk));
                return cplx(0.0, -1.0) * (ssx * gx + ssy * gy) / den;
            };
            // The mirror frequency has the negated sines.
            z[a] = solve(za, zb, sx, sy);
            if (b != a) z[b] = solve(zb, za, -sx, -sy);
        }
    });
    fftCols(true);
    report(progress, 0.75);
    fftRows(true);
    std::vector<double> hv(z.size());
    const double norm = 1.0 / (double(w) * double(h));
    for (size_t k = 0; k < z.size(); ++k) hv[k] = z[k].real() * norm;
    report(progress, 1.0);
    return finish(hv, w, h);
}

ScalarField solveNeumann(const DerivField& d, const Progress& progress) {
    const int w = d.width, h = d.height;
    // The DST-II of x equals the DCT-II, at index N - k, of x with every
    // other sample negated (sin(pi k (n + 1/2) / N) = (-1)^n cos(pi (N - k)
    // (n + 1/2) / N)), with the same orthonormal factor.
    std::vector<double> ax(d.size()), ay(d.size());
    forRows(h, [&](int j) {
        for (int i = 0; i < w; ++i) {
            const size_t k = size_t(j) * size_t(w) + size_t(i);
            // fromHeight's one-sided border slopes are twice the central
            // difference of the mirrored grid the DCT models: halved here.
            const double bx = (i == 0 || i == w - 1) ? 0.5 : 1.0;
            const double by = (j == 0 || j == h - 1) ? 0.5 : 1.0;
            ax[k] = (i % 2 ? -bx : bx) * d.v[k].x;
            ay[k] = (j % 2 ? -by : by) * d.v[k].y;
        }
    });
    const detail::Dct cw(w), ch(h);
    auto dct2 = [&](std::vector<double>& x, bool inv) {
        if (!inv) {
            alongRows(x, w, h, [&](double* line, auto& a, auto& s) {
                thread_local std::vector<double> tmp;
                tmp.assign(line, line + w);
                cw.forward(tmp.data(), line, a, s);
            });
        }
        alongColumns(x, w, h, [&](double* line, auto& a, auto& s) {
            thread_local std::vector<double> tmp;
            tmp.assign(line, line + h);
            if (inv)
                ch.inverse(tmp.data(), line, a, s);
            else
                ch.forward(tmp.data(), line, a, s);
        });
        if (inv) {
            alongRows(x, w, h, [&](double* line, auto& a, auto& s) {
                thread_local std::vector<double> tmp;
                tmp.assign(line, line + w);
                cw.inverse(tmp.data(), line, a, s);
            });
        }
    };
    dct2(ax, false);
    report(progress, 0.3);
    dct2(ay, false);
    report(progress, 0.6);
    // A(k, l) from Gx(k, l) = ax(W - k, l) and Gy(k, l) = ay(k, H - l); k and
    // W - k of a row are solved together so A overwrites ax in place.
    forRows(h, [&](int l) {
        const double sy = std::sin(kPi * l / h);
        double* row = &ax[size_t(l) * size_t(w)];
        auto gyAt = [&](int k) { return l == 0 ? 0.0 : ay[size_t(h - l) * size_t(w) + size_t(k)]; };
        auto solve = [&](int k, double gx) {
            const double sx = std::sin(kPi * k / w);
            const double den = sx * sx + sy * sy;
            return den < kNullSymbol ? 0.0 : -(sx * gx + sy * gyAt(k)) / den;
        };
        // k = 0 has no sine partner (sx = 0): Gx is not needed.
        const double a0 = solve(0, 0.0);
        for (int k = 1; 2 * k <= w; ++k) {
            const int km = w - k;
            const double gxk = row[km], gxkm = row[k];
            const double ak = solve(k, gxk), akm = solve(km, gxkm);
            row[k] = ak;
            row[km] = akm;
        }
        row[0] = a0;
    });
    report(progress, 0.8);
    dct2(ax, true);
    report(progress, 1.0);
    return finish(ax, w, h);
}

} // namespace

DerivField fromHeight(const ScalarField& h, float scale, Wrap wrap) {
    DerivField d(h.width, h.height);
    forRows(h.height, [&](int j) {
        for (int i = 0; i < h.width; ++i) d.at(i, j) = scale * detail::centralSlope(h, i, j, wrap);
    });
    return d;
}

ScalarField toHeight(const DerivField& d, Wrap wrap, const Progress& progress) {
    if (d.size() == 0) return ScalarField();
    return wrap == Wrap::Repeat ? solvePeriodic(d, progress) : solveNeumann(d, progress);
}

namespace naive {

DerivField fromHeight(const ScalarField& h, float scale, Wrap wrap) {
    DerivField d(h.width, h.height);
    forRows(h.height, [&](int j) {
        for (int i = 0; i < h.width; ++i) {
            const int r = i + 1 < h.width ? i + 1 : detail::wrapIndex(i + 1, h.width, wrap);
            const int u = j + 1 < h.height ? j + 1 : detail::wrapIndex(j + 1, h.height, wrap);
            d.at(i, j) = scale * g::sgHeightDeriv3Tap(h.at(i, j), h.at(r, j), h.at(i, u));
        }
    });
    return d;
}

ScalarField toHeight(const DerivField& d) {
    const int w = d.width, h = d.height;
    std::vector<double> hv(d.size());
    double col = 0.0;
    for (int j = 0; j < h; ++j) {
        if (j > 0) col += 0.5 * (double(d.at(0, j - 1).y) + d.at(0, j).y);
        double x = col;
        hv[size_t(j) * size_t(w)] = x;
        for (int i = 1; i < w; ++i) {
            x += 0.5 * (double(d.at(i - 1, j).x) + d.at(i, j).x);
            hv[size_t(j) * size_t(w) + size_t(i)] = x;
        }
    }
    return finish(hv, w, h);
}

} // namespace naive

} // namespace sg::normalmap
