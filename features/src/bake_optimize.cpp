// Quadratic mode of the feature-map bake, step 4: the local constrained
// optimisation of invalid signatures. Parilov, Zorin, "Real-Time Rendering
// of Textures with Feature Curves" (TOG 2008) section 4, Eq. 2 and the
// thin-plate energy of Eq. 3.
//
// The paper minimises the thin-plate energy of the affected segments (this
// texel's and the connected ones in its four edge neighbours) over their
// control points, with linear inequalities (control points inside their
// texels), nonlinear equalities (G1 continuity, points on edges) and SQP. We
// optimise over the signatures, (t, theta) of this texel's edge points: the
// equalities hold by construction (a shared angle IS G1 continuity; t IS a
// point on the edge), and what remains ("every affected texel valid",
// bake_quadratic.cpp) is not smooth (it counts roots and checks
// star-shapedness), so instead of SQP a compass search with an
// extreme-barrier merit (Audet and Dennis 2006): infeasible trial points
// rank by their violation and never beat a feasible one; on the smooth part
// it converges to a stationary point like SQP (Lewis and Torczon 1999).
// bench/features_optimizer_bench.cpp measures both on the paper's energy.
// The energy adds a fidelity term (bake_quadratic.cpp, kFidelityWeight)
// and a weak anchor 0.25 (t - t0)^2 keeping points near the centre of mass
// of the input crossings. A texel the search cannot make valid has its
// segments straightened, which is always valid (the linear partition of
// TR2005).
//
// Threads: optimising texel T reads the edge points of T and of its four
// neighbours (their validity, energy and the Catmull-Rom start) and writes
// T's edge points and its straightening bit, so two texels more than
// kOptimizeReach apart in x or y never see each other's work. Each invalid
// texel gets a wave number one above the largest of the earlier (row-major)
// invalid texels within that reach; a wave's texels run in parallel and the
// waves in order. Every texel then sees exactly the state the serial loop
// gives it: the same result for every thread count.
#include <algorithm>
#include <chrono>
#include <cmath>

#include "bake_internal.h"
#include "shared_double.h"

namespace sg::features::detail {

namespace {

// Neighbour of texel (i, j) across edge e and the edge's index there.
void across(int i, int j, int e, int& ni, int& nj, int& ne) {
    static const int di[4] = {0, 1, 0, -1}, dj[4] = {-1, 0, 1, 0};
    ni = i + di[e];
    nj = j + dj[e];
    ne = (e + 2) % 4;
}

bool touchesCandidate(const Grid& g, int i, int j, int e) {
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return false;
    size_t ti = g.ti(i, j);
    unsigned m = g.segMask[ti] & g.quadMask[ti] & ~unsigned(g.straightMask[ti]);
    for (int p = 0; p < kPairCount; ++p) {
        if ((m & (1u << p)) && (kPairEdges[p][0] == e || kPairEdges[p][1] == e)) return true;
    }
    return false;
}

double texelViolation(const Grid& g, int i, int j) {
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return 0.0;
    LocalTexel t = decodeTexel(g, i, j);
    return validateTexel(t, nullptr);
}

double texelEnergy(const Grid& g, int i, int j, bool fidelity) {
    if (i < 0 || j < 0 || i >= g.n || j >= g.n) return 0.0;
    LocalTexel t = decodeTexel(g, i, j);
    double e = 0.0;
    for (int s = 0; s < t.nseg; ++s) e += segmentEnergy(t, s, fidelity);
    return e;
}

double angleOf(dvec2 d) {
    return wrapAngle(std::atan2(d.y, d.x));
}

} // namespace

TexelProblem::TexelProblem(Grid& g, int i, int j, Energy energy)
    : g_(g), i_(i), j_(j), kind_(energy) {
    for (int e = 0; e < 4; ++e) {
        if (g.pos(i, j, e) < 0.0) continue;
        int ni, nj, ne;
        across(i, j, e, ni, nj, ne);
        if (touchesCandidate(g, i, j, e) || touchesCandidate(g, ni, nj, ne))
            vars_.push_back({e, ni, nj, g.pos(i, j, e)});
    }
    saved_.resize(size());
    for (size_t k = 0; k < vars_.size(); ++k) {
        saved_[2 * k] = g.pos(i, j, vars_[k].e);
        saved_[2 * k + 1] = g.ang(i, j, vars_[k].e);
    }
    for (const auto& v : vars_) neighbours0_ += texelViolation(g, v.ni, v.nj);
}

void TexelProblem::write(const std::vector<double>& x) {
    for (size_t k = 0; k < vars_.size(); ++k) {
        g_.pos(i_, j_, vars_[k].e) = quantizePos(x[2 * k]);
        g_.ang(i_, j_, vars_[k].e) = quantizeAngle(x[2 * k + 1]);
    }
}

double TexelProblem::violation(const std::vector<double>& x) {
    write(x);
    ++evaluations;
    double nb = 0.0;
    for (const auto& w : vars_) nb += texelViolation(g_, w.ni, w.nj);
    return texelViolation(g_, i_, j_) + std::max(0.0, nb - neighbours0_ - 1e-12);
}

double TexelProblem::energy(const std::vector<double>& x) {
    write(x);
    const bool ours = kind_ == Energy::Ours;
    double energy = texelEnergy(g_, i_, j_, ours);
    for (size_t k = 0; k < vars_.size(); ++k) {
        energy += texelEnergy(g_, vars_[k].ni, vars_[k].nj, ours);
        double dt = g_.pos(i_, j_, vars_[k].e) - vars_[k].t0;
        if (ours) energy += 0.25 * dt * dt;
    }
    return energy;
}

double TexelProblem::merit(const std::vector<double>& x) {
    write(x);
    ++evaluations;
    double vt = texelViolation(g_, i_, j_);
    double nb = 0.0;
    for (const auto& w : vars_) nb += texelViolation(g_, w.ni, w.nj);
    if (vt > 0.0 || nb > neighbours0_ + 1e-12) return 1e9 + vt + std::max(0.0, nb - neighbours0_);
    return energy(x);
}

std::vector<std::vector<double>> TexelProblem::starts() const {
    std::vector<std::vector<double>> out{saved_};
    const size_t nv = vars_.size();
    const LocalTexel t = decodeTexel(g_, i_, j_);
    {
        // Eq. 7 remedy: b1 onto the chord's perpendicular bisector (x0 = 0).
        std::vector<double> s = saved_;
        for (int sg = 0; sg < t.nseg; ++sg) {
            if (!t.candidate[sg]) continue;
            int a = t.a[sg], b = t.b[sg];
            dvec2 qa = t.q[a], qb = t.q[b], b1;
            if (!sharedTangentIntersection(qa, t.tang[a], qb, t.tang[b], b1)) continue;
            dvec2 m = 0.5 * (qa + qb), ch = glm::normalize(qb - qa), nrm{-ch.y, ch.x};
            double h = std::clamp(glm::dot(b1 - m, nrm), -0.45, 0.45);
            dvec2 sym = m + h * nrm;
            for (size_t k = 0; k < nv; ++k) {
                if (vars_[k].e == a) s[2 * k + 1] = angleOf(sym - qa);
                if (vars_[k].e == b) s[2 * k + 1] = angleOf(sym - qb);
            }
        }
        out.push_back(s);
    }
    {
        // Catmull-Rom: tangent at an edge point along the line through the
        // other ends of the segments on its two sides.
        std::vector<double> s = saved_;
        for (size_t k = 0; k < nv; ++k) {
            int e = vars_[k].e, ni, nj, ne;
            across(i_, j_, e, ni, nj, ne);
            dvec2 here{0.0}, there{0.0};
            bool hasHere = false, hasThere = false;
            for (int sg = 0; sg < t.nseg && !hasHere; ++sg) {
                if (t.a[sg] == e || t.b[sg] == e) {
                    here = t.q[t.a[sg] == e ? t.b[sg] : t.a[sg]];
                    hasHere = true;
                }
            }
            if (ni >= 0 && nj >= 0 && ni < g_.n && nj < g_.n) {
                LocalTexel u = decodeTexel(g_, ni, nj);
                for (int sg = 0; sg < u.nseg && !hasThere; ++sg) {
                    int o = u.a[sg] == ne ? u.b[sg] : (u.b[sg] == ne ? u.a[sg] : -1);
                    if (o >= 0) {
                        there = u.q[o] + dvec2(ni - i_, nj - j_);
                        hasThere = true;
                    }
                }
            }
            if (hasHere && hasThere && glm::length(there - here) > 1e-6)
                s[2 * k + 1] = angleOf(there - here);
        }
        out.push_back(s);
    }
    return out;
}

bool compassSearch(TexelProblem& p, std::vector<double>& x) {
    double best = 1e300;
    for (const auto& s : p.starts()) {
        double m = p.merit(s);
        if (m < best) {
            best = m;
            x = s;
        }
    }
    // Poll +-step along every coordinate, move to the best improving point
    // and double the steps, else halve them. Small first steps: most invalid
    // signatures need only a nudge.
    double stepT = 1.0 / 128.0, stepA = 1.0 / 32.0;
    int evals = 0;
    while (stepT >= 1.0 / 8192.0 && evals < 320) {
        std::vector<double> bestY;
        double bestM = best;
        for (size_t k = 0; k < p.size(); ++k) {
            for (double sgn : {1.0, -1.0}) {
                std::vector<double> y = x;
                y[k] += sgn * ((k % 2 == 0) ? stepT : stepA);
                double m = p.merit(y);
                ++evals;
                if (m < bestM - 1e-12) {
                    bestM = m;
                    bestY = y;
                }
            }
        }
        if (!bestY.empty()) {
            best = bestM;
            x = bestY;
            stepT = std::min(stepT * 2.0, 1.0 / 8.0);
            stepA = std::min(stepA * 2.0, 0.5);
        } else {
            stepT *= 0.5;
            stepA *= 0.5;
        }
    }
    return best < 1e9;
}

namespace {

// Optimises the signature of texel (i, j); true when it ends valid (else
// the signature is restored).
bool optimizeTexel(Grid& g, int i, int j) {
    TexelProblem p(g, i, j);
    if (p.size() == 0) return false;
    std::vector<double> x;
    if (!compassSearch(p, x)) {
        p.write(p.initial());
        return false;
    }
    p.write(x);
    return true;
}

} // namespace

namespace {

constexpr size_t kRowsPerBlock = 8; // rows of texels per block of the validation passes

// The invalid texels (row-major) with the validation counters of every
// candidate texel, blocks of rows in parallel.
std::vector<std::pair<int, int>> invalidTexels(const Grid& g, ValidationCounters& counters,
                                               const Exec& ex) {
    const int n = g.n;
    struct Block {
        std::vector<std::pair<int, int>> work;
        ValidationCounters counters;
    };
    std::vector<Block> blocks(blockCount(size_t(n), kRowsPerBlock));
    forBlocks(ex, size_t(n), kRowsPerBlock, [&](size_t b, size_t j0, size_t j1) {
        for (int j = int(j0); j < int(j1); ++j) {
            for (int i = 0; i < n; ++i) {
                size_t ti = g.ti(i, j);
                if (!(g.segMask[ti] & g.quadMask[ti])) continue;
                LocalTexel t = decodeTexel(g, i, j);
                if (validateTexel(t, &blocks[b].counters) > 0.0) blocks[b].work.emplace_back(i, j);
            }
        }
    });
    std::vector<std::pair<int, int>> work;
    for (const Block& b : blocks) {
        work.insert(work.end(), b.work.begin(), b.work.end());
        counters.thetaMin += b.counters.thetaMin;
        counters.flat += b.counters.flat;
        counters.eq7 += b.counters.eq7;
        counters.cross += b.counters.cross;
    }
    return work;
}

// Wave of each work item: 1 + the largest wave of the earlier items within
// kOptimizeReach (each texel is in the list at most once); the items of
// each wave in list order.
std::vector<std::vector<size_t>> optimizationWaves(const Grid& g,
                                                   const std::vector<std::pair<int, int>>& work) {
    std::vector<int> waveAt(size_t(g.n) * size_t(g.n), -1);
    std::vector<std::vector<size_t>> waves;
    for (size_t w = 0; w < work.size(); ++w) {
        auto [i, j] = work[w];
        int wave = 0;
        for (int dj = -kOptimizeReach; dj <= kOptimizeReach; ++dj) {
            for (int di = -kOptimizeReach; di <= kOptimizeReach; ++di) {
                int ni = i + di, nj = j + dj;
                if (ni < 0 || nj < 0 || ni >= g.n || nj >= g.n) continue;
                wave = std::max(wave, waveAt[g.ti(ni, nj)] + 1);
            }
        }
        waveAt[g.ti(i, j)] = wave;
        if (size_t(wave) >= waves.size()) waves.resize(size_t(wave) + 1);
        waves[size_t(wave)].push_back(w);
    }
    return waves;
}

} // namespace

void optimizeSignatures(Grid& g, BakeStats& stats,
                        const std::function<void(const char*, double)>& progress, const Exec& ex) {
    const int n = g.n;
    ValidationCounters counters;
    const std::vector<std::pair<int, int>> work = invalidTexels(g, counters, ex);
    stats.eq7Failures = counters.eq7;
    stats.invalidTexels = int(work.size());
    // 1: repaired (valid or optimised), 0: straightened.
    std::vector<uint8_t> repaired(work.size(), 0);
    PhaseProgress report(progress, "optimize", work.size());
    for (const std::vector<size_t>& wave : optimizationWaves(g, work)) {
        forBlocks(ex, wave.size(), 1, [&](size_t, size_t w0, size_t w1) {
            for (size_t k = w0; k < w1; ++k) {
                const size_t w = wave[k];
                auto [i, j] = work[w];
                size_t ti = g.ti(i, j);
                if (texelViolation(g, i, j) <= 0.0 || optimizeTexel(g, i, j))
                    repaired[w] = 1;
                else
                    g.straightMask[ti] |= g.segMask[ti];
            }
            report.add(w1 - w0);
        });
    }
    for (uint8_t r : repaired) ++(r ? stats.optimizedTexels : stats.fallbackTexels);
    // Safety net: anything still invalid becomes straight (always valid).
    // Each texel's test reads only its own state.
    std::vector<int> fallbacks(blockCount(size_t(n), kRowsPerBlock), 0);
    forBlocks(ex, size_t(n), kRowsPerBlock, [&](size_t b, size_t j0, size_t j1) {
        for (int j = int(j0); j < int(j1); ++j) {
            for (int i = 0; i < n; ++i) {
                size_t ti = g.ti(i, j);
                if (!(g.segMask[ti] & g.quadMask[ti] & ~g.straightMask[ti])) continue;
                if (texelViolation(g, i, j) > 0.0) {
                    g.straightMask[ti] |= g.segMask[ti];
                    ++fallbacks[b];
                }
            }
        }
    });
    for (int f : fallbacks) stats.fallbackTexels += f;
    report.finish();
}

} // namespace sg::features::detail
