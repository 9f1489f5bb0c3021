// The FFT (radix 2 and Bluestein) and the orthonormal DCT-II/III of the
// Poisson solve against their defining sums, evaluated directly in double.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "fft.h"

namespace {

using sg::normalmap::detail::cplx;
constexpr double kPi = 3.14159265358979323846;

// Sizes: tiny, powers of two, primes (Bluestein), composites.
const int kSizes[] = {1, 2, 3, 4, 5, 7, 8, 12, 16, 17, 31, 64, 97, 100, 128, 255};

TEST(Transforms, FftMatchesTheDftSum) {
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int n : kSizes) {
        std::vector<cplx> x(static_cast<size_t>(n)), scratch;
        for (auto& v : x) v = cplx(U(rng), U(rng));
        for (bool inverse : {false, true}) {
            std::vector<cplx> y = x;
            sg::normalmap::detail::Fft(n).transform(y.data(), inverse, scratch);
            double err = 0;
            for (int k = 0; k < n; ++k) {
                cplx s(0);
                for (int m = 0; m < n; ++m)
                    s += x[size_t(m)] * std::polar(1.0, (inverse ? 2 : -2) * kPi * k * m / n);
                err = std::max(err, std::abs(s - y[size_t(k)]));
            }
            // O(1) inputs, sums of n terms: the direct sum's own rounding is
            // ~n 1e-16 (2.5e-14 at n = 255); Bluestein's three FFTs of
            // length 2n-4n and the chirp products add tens of times that
            // (measured 2.3e-12). 1e-11 is far below any indexing or sign
            // error (O(1)).
            EXPECT_LT(err, 1e-11) << "n = " << n << (inverse ? " inverse" : "");
        }
    }
}

TEST(Transforms, DctIsOrthonormalDct2AndInverts) {
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> U(-1, 1);
    for (int n : kSizes) {
        const size_t sz = static_cast<size_t>(n);
        std::vector<double> x(sz), X(sz), back(sz);
        for (auto& v : x) v = U(rng);
        std::vector<cplx> a, s;
        const sg::normalmap::detail::Dct dct(n);
        dct.forward(x.data(), X.data(), a, s);
        double err = 0, errBack = 0;
        for (int k = 0; k < n; ++k) {
            double sum = 0;
            for (int m = 0; m < n; ++m) sum += x[size_t(m)] * std::cos(kPi * k * (m + 0.5) / n);
            sum *= std::sqrt((k == 0 ? 1.0 : 2.0) / n);
            err = std::max(err, std::abs(sum - X[size_t(k)]));
        }
        dct.inverse(X.data(), back.data(), a, s);
        for (int m = 0; m < n; ++m)
            errBack = std::max(errBack, std::abs(back[size_t(m)] - x[size_t(m)]));
        // Same budget as the FFT test.
        EXPECT_LT(err, 1e-11) << "n = " << n;
        EXPECT_LT(errBack, 1e-11) << "n = " << n;
    }
}

} // namespace
