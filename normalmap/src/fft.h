// Small discrete Fourier and cosine transforms for the Poisson solve of
// to-height (poisson.cpp): a radix-2 FFT for power-of-two sizes and
// Bluestein's chirp-z algorithm (Bluestein 1970) for every other size, in
// double precision; the orthonormal DCT-II/DCT-III through one complex FFT
// of the same length (Makhoul, "A fast cosine transform in one and multiple
// dimensions", IEEE TASSP 28(1), 1980, section II).
#pragma once

#include <complex>
#include <vector>

namespace sg::normalmap::detail {

using cplx = std::complex<double>;

class Fft {
public:
    explicit Fft(int n);
    int size() const { return n_; }
    // In place, unnormalised: X_k = sum_n x_n exp(-+2 pi i k n / N) (minus
    // for forward). `scratch` is resized as needed (one per thread).
    void transform(cplx* x, bool inverse, std::vector<cplx>& scratch) const;

private:
    void radix2(cplx* x, bool inverse) const;
    int n_ = 0;
    int m_ = 0;                  // power-of-two length the radix-2 kernel runs at
    std::vector<cplx> twiddle_;  // exp(-2 pi i k / m), k < m / 2
    std::vector<int> reversed_;  // bit reversal permutation of m
    std::vector<cplx> chirp_;    // Bluestein: exp(-i pi k^2 / n), k < n
    std::vector<cplx> chirpFft_; // Bluestein: FFT_m of the conjugate chirp, wrapped
};

// Orthonormal DCT-II (X_k = c_k sum_n x_n cos(pi k (n + 1/2) / N), c_0 =
// sqrt(1/N), c_k = sqrt(2/N)) and its inverse (DCT-III), length N, through
// an N-point complex FFT.
class Dct {
public:
    explicit Dct(int n);
    int size() const { return fft_.size(); }
    void forward(const double* x, double* out, std::vector<cplx>& a, std::vector<cplx>& s) const;
    void inverse(const double* coeff, double* out, std::vector<cplx>& a,
                 std::vector<cplx>& s) const;

private:
    Fft fft_;
    std::vector<cplx> shift_; // exp(-i pi k / (2N))
};

} // namespace sg::normalmap::detail
