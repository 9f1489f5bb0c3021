// FFT (radix 2 and Bluestein) and the orthonormal DCT-II/III; see fft.h.
#include "fft.h"

#include <cmath>

namespace sg::normalmap::detail {

namespace {

constexpr double kPi = 3.14159265358979323846;

int nextPow2(int n) {
    int m = 1;
    while (m < n) m *= 2;
    return m;
}

} // namespace

Fft::Fft(int n) : n_(n) {
    const bool pow2 = n > 0 && (n & (n - 1)) == 0;
    m_ = pow2 ? n : nextPow2(2 * n - 1);
    twiddle_.resize(size_t(m_ / 2));
    for (int k = 0; k < m_ / 2; ++k) {
        twiddle_[size_t(k)] = std::polar(1.0, -2.0 * kPi * k / m_);
    }
    reversed_.resize(size_t(m_));
    int bits = 0;
    while ((1 << bits) < m_) ++bits;
    for (int i = 0; i < m_; ++i) {
        int r = 0;
        for (int b = 0; b < bits; ++b) r |= ((i >> b) & 1) << (bits - 1 - b);
        reversed_[size_t(i)] = r;
    }
    if (pow2) return;
    // Bluestein: x_k w_k convolved with conj(w) (indices -n+1 .. n-1), w_k =
    // exp(-i pi k^2 / n); k^2 is reduced mod 2n so the phase stays exact for
    // large k.
    chirp_.resize(size_t(n));
    for (int k = 0; k < n; ++k) {
        const long long k2 = (static_cast<long long>(k) * k) % (2LL * n);
        chirp_[size_t(k)] = std::polar(1.0, -kPi * double(k2) / n);
    }
    chirpFft_.assign(size_t(m_), cplx(0.0));
    chirpFft_[0] = std::conj(chirp_[0]);
    for (int k = 1; k < n; ++k) {
        chirpFft_[size_t(k)] = chirpFft_[size_t(m_ - k)] = std::conj(chirp_[size_t(k)]);
    }
    radix2(chirpFft_.data(), false);
}

void Fft::radix2(cplx* x, bool inverse) const {
    for (int i = 0; i < m_; ++i) {
        const int r = reversed_[size_t(i)];
        if (i < r) std::swap(x[i], x[r]);
    }
    for (int len = 2; len <= m_; len *= 2) {
        const int half = len / 2, step = m_ / len;
        for (int start = 0; start < m_; start += len) {
            for (int k = 0; k < half; ++k) {
                cplx w = twiddle_[size_t(k * step)];
                if (inverse) w = std::conj(w);
                const cplx a = x[start + k], b = w * x[start + k + half];
                x[start + k] = a + b;
                x[start + k + half] = a - b;
            }
        }
    }
}

void Fft::transform(cplx* x, bool inverse, std::vector<cplx>& scratch) const {
    if (n_ <= 1) return;
    if (m_ == n_) {
        radix2(x, inverse);
        return;
    }
    // Inverse through the forward transform of the conjugate.
    if (inverse) {
        for (int k = 0; k < n_; ++k) x[k] = std::conj(x[k]);
    }
    scratch.assign(size_t(m_), cplx(0.0));
    for (int k = 0; k < n_; ++k) scratch[size_t(k)] = x[k] * chirp_[size_t(k)];
    radix2(scratch.data(), false);
    for (int k = 0; k < m_; ++k) scratch[size_t(k)] *= chirpFft_[size_t(k)];
    radix2(scratch.data(), true);
    const double invM = 1.0 / m_;
    for (int k = 0; k < n_; ++k) x[k] = scratch[size_t(k)] * invM * chirp_[size_t(k)];
    if (inverse) {
        for (int k = 0; k < n_; ++k) x[k] = std::conj(x[k]);
    }
}

Dct::Dct(int n) : fft_(n) {
    shift_.resize(size_t(n));
    for (int k = 0; k < n; ++k) shift_[size_t(k)] = std::polar(1.0, -kPi * k / (2.0 * n));
}

void Dct::forward(const double* x, double* out, std::vector<cplx>& a, std::vector<cplx>& s) const {
    const int n = size();
    a.resize(size_t(n));
    // Even samples in order, odd samples reversed (Makhoul's reordering).
    for (int i = 0; 2 * i < n; ++i) a[size_t(i)] = x[2 * i];
    for (int i = 0; 2 * i + 1 < n; ++i) a[size_t(n - 1 - i)] = x[2 * i + 1];
    fft_.transform(a.data(), false, s);
    const double c0 = std::sqrt(1.0 / n), ck = std::sqrt(2.0 / n);
    for (int k = 0; k < n; ++k) {
        out[k] = (k == 0 ? c0 : ck) * (shift_[size_t(k)] * a[size_t(k)]).real();
    }
}

void Dct::inverse(const double* coeff, double* out, std::vector<cplx>& a,
                  std::vector<cplx>& s) const {
    const int n = size();
    a.resize(size_t(n));
    const double c0 = std::sqrt(1.0 / n), ck = std::sqrt(2.0 / n);
    // Unnormalised DCT-II coefficients X_k back to the FFT of the reordered
    // samples: V_k = exp(i pi k / 2N) (X_k - i X_{N-k}), X_N = 0.
    auto X = [&](int k) { return k == 0 ? coeff[0] / c0 : (k == n ? 0.0 : coeff[k] / ck); };
    for (int k = 0; k < n; ++k) {
        a[size_t(k)] = std::conj(shift_[size_t(k)]) * cplx(X(k), -X(n - k));
    }
    fft_.transform(a.data(), true, s);
    const double invN = 1.0 / n;
    for (int i = 0; 2 * i < n; ++i) out[2 * i] = a[size_t(i)].real() * invN;
    for (int i = 0; 2 * i + 1 < n; ++i) out[2 * i + 1] = a[size_t(n - 1 - i)].real() * invN;
}

} // namespace sg::normalmap::detail
