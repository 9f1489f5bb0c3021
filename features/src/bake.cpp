// Feature-map bake: curve network -> configuration, signature, distance and
// gradient maps. Parilov, Zorin, "Real-Time Rendering of Textures with
// Feature Curves" (TOG 2008) section 4, and Parilov, Rosenberg, Zorin
// (TR2005-872) sections 4.1-4.2.
//
//  1. Input validation and the input-to-texel transform.
//  2. Strokes: segments of a curve are chained; curve ends meeting at one
//     point are paired (most opposite directions first), so a stroke runs
//     THROUGH a junction texel instead of ending inside it (a star of eight
//     rays becomes four strokes, as in TOG 2008 Fig. 17).
//  3. Scan conversion (sec. 4): each stroke is cut at the texel grid lines;
//     consecutive texels it visits share an edge where it crosses. A visit
//     entering and leaving a texel through two different edges adds a
//     segment via the transformation table (bake_table.cpp); a visit with
//     one crossing contributes only its edge point (the curve ends on the
//     texel boundary, rule 3). Crossings of one edge merge into their
//     centre of mass (rule 1); tangent angles average as line directions.
//     Points exactly on grid lines follow floor() (symbolically, the
//     curves are shifted by (e^2, e) for an infinitesimal e), so a curve
//     along a texel edge lies in the texels above/right of it and a curve
//     through a texel corner passes through the texel above the corner.
//     Edge points stay 2^-10 texels away from the corners.
//  4. Quadratic mode: invalid signatures are optimised (bake_quadratic.cpp).
//  5. Distance and gradient at every corner within bandTexels of a curve, by
//     local brute force in double (exact point-curve distance) with
//     min-merging over segments (sec. 4, "Rasterization of distance
//     field"); the gradient is the unit vector from the closest point
//     (bake_distance.cpp).
//  6. Constrained Laplacian smoothing of the gradient (sec. 4): each corner
//     moves halfway to the mean of its grid neighbours, excluding those
//     across a texel edge that carries a discontinuity point and those with
//     no curve within the band (no gradient). The distance is never
//     smoothed (bake_distance.cpp).
// bake() below runs these steps in order, one named function each; steps
// 4-6 and the configurations run on several threads (BakeOptions::threads,
// bake_parallel.h), step 3 on the calling thread.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>

#include <time.h>

#include "surfgrad/base/scratch_buffer.h"
#include "bake_internal.h"
#include "surfgrad/base/contract.h"
#include "surfgrad/base/io.h"
#include "surfgrad/base/threads.h"

namespace sg::features {

using namespace detail;

const char* toString(BakeMode m) {
    return m == BakeMode::Linear ? "linear" : "quadratic";
}

namespace {

using Clock = std::chrono::steady_clock;
double wallSince(Clock::time_point t0) {
    return std::chrono::duration<double>(Clock::now() - t0).count();
}
// CPU time of the process (every thread of the bake): phase timings that
// stay meaningful on a shared machine.
double processCpu() {
    timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// CPU and wall-clock time of one phase.
struct PhaseTimer {
    double cpu0 = processCpu();
    Clock::time_point wall0 = Clock::now();
    void stop(double& cpuSeconds, double& wallSeconds) const {
        cpuSeconds = processCpu() - cpu0;
        wallSeconds = wallSince(wall0);
    }
};

constexpr double kJoinTol = 1e-7; // texels: segment ends closer than this are one point
constexpr double kMaxCoord = 1e6; // texels: larger coordinates are absurd input

using OSeg = TexelPiece;

struct Stroke {
    std::vector<OSeg> segs;
    bool closed = false;
};

std::string segName(const CurveNetwork& net, size_t k) {
    std::string s = "segment " + std::to_string(k);
    const auto& seg = net.segments[k];
    if (seg.curve >= 0 && size_t(seg.curve) < net.curves.size() &&
        !net.curves[size_t(seg.curve)].name.empty()) {
        s += " (curve '" + net.curves[size_t(seg.curve)].name + "')";
    }
    return s;
}

// Validates the input and maps it to texel space.
std::vector<OSeg> toTexelSpace(const CurveNetwork& net, const TexelTransform& xf) {
    const std::string file = net.source.empty() ? "(curve network)" : net.source;
    std::vector<OSeg> out;
    out.reserve(net.segments.size());
    for (size_t k = 0; k < net.segments.size(); ++k) {
        const auto& s = net.segments[k];
        for (const auto& p : {s.p0, s.p1, s.p2}) {
            if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
                throw io::InputError(file, segName(net, k), "non-finite coordinate");
            }
        }
        OSeg o;
        o.line = s.kind == Segment::Kind::Line;
        o.q.p0 = xf.apply(s.p0);
        o.q.p2 = xf.apply(s.p2);
        o.q.p1 = o.line ? 0.5 * (o.q.p0 + o.q.p2) : xf.apply(s.p1);
        for (const auto& p : {o.q.p0, o.q.p1, o.q.p2}) {
            if (!(std::fabs(p.x) <= kMaxCoord && std::fabs(p.y) <= kMaxCoord)) {
                throw io::InputError(file, segName(net, k),
                                     "coordinate maps to more than 1e6 texels from the map origin");
            }
        }
        // Coincident control points (TOG 2008 sec. 3: segments are
        // non-degenerate). Compared in input units, relative to the scale.
        double scale = std::max({1e-300, glm::length(s.p0), glm::length(s.p1), glm::length(s.p2)});
        auto same = [&](glm::dvec2 a, glm::dvec2 b) { return glm::length(a - b) <= 1e-12 * scale; };
        // A quadratic whose middle point equals an end is a straight line
        // (handled below); coincident END points leave no chord.
        if (same(s.p0, s.p2)) {
            throw io::InputError(
                file, segName(net, k),
                o.line || same(s.p0, s.p1)
                    ? "coincident control points (zero-length segment)"
                    : "coincident end points (the quadratic folds back on itself)");
        }
        if (glm::length(o.q.p2 - o.q.p0) <= 1e-9) {
            throw io::InputError(file, segName(net, k),
                                 "segment shorter than 1e-9 texels at this map size");
        }
        if (!o.line) {
            dvec2 e = o.q.p2 - o.q.p0, m = o.q.p1 - o.q.p0;
            double ee = glm::dot(e, e);
            if (std::fabs(cross2(e, m)) <= 1e-12 * ee) {
                double along = glm::dot(m, e) / ee;
                if (along < 0.0 || along > 1.0) {
                    throw io::InputError(
                        file, segName(net, k),
                        "quadratic folds back on itself (collinear control points, middle "
                        "point outside the chord)");
                }
                // Collinear and inside the chord: geometrically straight.
                o.line = true;
                o.q.p1 = 0.5 * (o.q.p0 + o.q.p2);
            }
        }
        out.push_back(o);
    }
    return out;
}

TexelTransform fitTransform(const CurveNetwork& net, const BakeOptions& opt) {
    TexelTransform xf;
    if (net.segments.empty()) return xf;
    glm::dvec2 lo, hi;
    net.bounds(lo, hi);
    for (double v : {lo.x, lo.y, hi.x, hi.y}) {
        if (!std::isfinite(v)) {
            throw io::InputError(net.source.empty() ? "(curve network)" : net.source, "",
                                 "non-finite coordinate");
        }
    }
    double avail = double(opt.size) - 2.0 * opt.marginTexels;
    if (!(avail > 0.0)) {
        throw io::InputError("(options)", "margin", "margin leaves no room: 2 * margin >= size");
    }
    glm::dvec2 ext = hi - lo;
    double maxExt = std::max(ext.x, ext.y);
    double s = maxExt > 0.0 ? avail / maxExt : 1.0;
    if (!std::isfinite(s) || s <= 0.0) s = 1.0;
    xf.scale = {s, s};
    glm::dvec2 centre = 0.5 * (lo + hi);
    xf.offset = glm::dvec2(0.5 * opt.size) - s * centre;
    return xf;
}

// Chains of connected segments of one curve, then strokes through
// junctions (step 2).
std::vector<Stroke> buildStrokes(const CurveNetwork& net, const std::vector<OSeg>& segs) {
    struct Chain {
        std::vector<OSeg> segs;
        bool closed = false;
    };
    std::vector<Chain> chains;
    for (size_t k = 0; k < segs.size(); ++k) {
        bool cont = k > 0 && net.segments[k].curve == net.segments[k - 1].curve &&
                    glm::length(segs[k].q.p0 - segs[k - 1].q.p2) <= kJoinTol;
        if (!cont) chains.emplace_back();
        chains.back().segs.push_back(segs[k]);
    }
    for (auto& c : chains) {
        c.closed =
            c.segs.size() >= 2 && glm::length(c.segs.front().q.p0 - c.segs.back().q.p2) <= kJoinTol;
    }
    // Open chain ends: position and the direction the chain leaves it in.
    struct End {
        dvec2 pos, dir;
        int chain, side; // side 0: start, 1: end
        int partner = -1;
    };
    std::vector<End> ends;
    for (size_t c = 0; c < chains.size(); ++c) {
        if (chains[c].closed) continue;
        const Quad& f = chains[c].segs.front().q;
        const Quad& l = chains[c].segs.back().q;
        dvec2 d0 = f.tangent(0.0), d1 = -l.tangent(1.0);
        ends.push_back({f.p0, d0 / std::max(glm::length(d0), 1e-300), int(c), 0});
        ends.push_back({l.p2, d1 / std::max(glm::length(d1), 1e-300), int(c), 1});
    }
    // Group coincident ends (sweep in x), pair the most opposite first.
    std::vector<int> order(ends.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return ends[size_t(a)].pos.x < ends[size_t(b)].pos.x; });
    std::vector<int> group(ends.size(), -1);
    int groups = 0;
    for (size_t a = 0; a < order.size(); ++a) {
        int ea = order[a];
        if (group[size_t(ea)] < 0) group[size_t(ea)] = groups++;
        for (size_t b = a + 1; b < order.size(); ++b) {
            int eb = order[b];
            if (ends[size_t(eb)].pos.x - ends[size_t(ea)].pos.x > kJoinTol) break;
            if (group[size_t(eb)] < 0 &&
                glm::length(ends[size_t(eb)].pos - ends[size_t(ea)].pos) <= kJoinTol) {
                group[size_t(eb)] = group[size_t(ea)];
            }
        }
    }
    std::vector<std::vector<int>> members(static_cast<size_t>(groups));
    for (size_t e = 0; e < ends.size(); ++e) members[size_t(group[e])].push_back(int(e));
    for (auto& m : members) {
        if (m.size() < 2) continue;
        std::vector<std::pair<double, std::pair<int, int>>> cand;
        for (size_t a = 0; a < m.size(); ++a) {
            for (size_t b = a + 1; b < m.size(); ++b) {
                cand.push_back(
                    {glm::dot(ends[size_t(m[a])].dir, ends[size_t(m[b])].dir), {m[a], m[b]}});
            }
        }
        std::stable_sort(cand.begin(), cand.end(),
                         [](const auto& x, const auto& y) { return x.first < y.first; });
        for (const auto& [dotv, pr] : cand) {
            (void)dotv;
            if (ends[size_t(pr.first)].partner < 0 && ends[size_t(pr.second)].partner < 0) {
                ends[size_t(pr.first)].partner = pr.second;
                ends[size_t(pr.second)].partner = pr.first;
            }
        }
    }
    std::vector<int> endOf(chains.size() * 2, -1);
    for (size_t e = 0; e < ends.size(); ++e)
        endOf[size_t(ends[e].chain) * 2 + size_t(ends[e].side)] = int(e);

    std::vector<Stroke> strokes;
    std::vector<bool> used(chains.size(), false);
    auto append = [&](Stroke& st, int c, bool reversed) {
        auto& cs = chains[size_t(c)].segs;
        if (!reversed) {
            st.segs.insert(st.segs.end(), cs.begin(), cs.end());
        } else {
            for (auto it = cs.rbegin(); it != cs.rend(); ++it)
                st.segs.push_back({it->q.reversed(), it->line});
        }
    };
    auto walk = [&](int c, bool reversed) {
        Stroke st;
        int first = c;
        for (;;) {
            used[size_t(c)] = true;
            append(st, c, reversed);
            int farEnd = endOf[size_t(c) * 2 + (reversed ? 0 : 1)];
            int partner = farEnd >= 0 ? ends[size_t(farEnd)].partner : -1;
            if (partner < 0) break;
            int nc = ends[size_t(partner)].chain;
            if (nc == first) {
                st.closed = true;
                break;
            }
            if (used[size_t(nc)]) break;
            c = nc;
            reversed = ends[size_t(partner)].side == 1;
        }
        strokes.push_back(std::move(st));
    };
    for (size_t c = 0; c < chains.size(); ++c) {
        if (chains[c].closed) {
            used[c] = true;
            strokes.push_back({chains[c].segs, true});
        }
    }
    // Strokes from free ends first, then the remaining cycles.
    for (size_t e = 0; e < ends.size(); ++e) {
        if (ends[e].partner >= 0 || used[size_t(ends[e].chain)]) continue;
        walk(ends[e].chain, ends[e].side == 1);
    }
    for (size_t c = 0; c < chains.size(); ++c) {
        if (!used[c]) walk(int(c), false);
    }
    return strokes;
}

// Scan conversion of strokes into edge points and segments (step 3).
class Scanner {
public:
    Scanner(Grid& g, BakeStats& st, bool targets) : g_(g), st_(st), targets_(targets) {}

    void stroke(const Stroke& s) {
        visits_.clear();
        havePrevTan_ = false;
        for (const auto& seg : s.segs) segment(seg);
        if (visits_.empty()) return;
        if (s.closed) {
            const Quad& f = s.segs.front().q;
            const Quad& l = s.segs.back().q;
            Visit first = visits_.front();
            if (visits_.size() > 1 && visits_.back().i == first.i && visits_.back().j == first.j) {
                mergeIntoFirst();
            } else if (!(visits_.back().i == first.i && visits_.back().j == first.j)) {
                dvec2 tan = safeDir(l.tangent(1.0)) + safeDir(f.tangent(0.0));
                move(first.i, first.j, f.p0, tan);
                mergeIntoFirst();
            }
        }
        for (const auto& v : visits_) {
            if (v.in < 0 || v.out < 0 || v.in == v.out) continue;
            if (v.i < 0 || v.j < 0 || v.i >= g_.n || v.j >= g_.n) continue;
            size_t ti = g_.ti(v.i, v.j);
            int pair = pairOf(v.in, v.out);
            uint8_t old = g_.segMask[ti];
            uint8_t nw = transition(old, pair);
            if (!(old & (1u << pair))) {
                st_.segmentsDropped +=
                    std::popcount(unsigned(old)) + 1 - std::popcount(unsigned(nw));
            }
            g_.segMask[ti] = nw;
            if (v.quad && (nw & (1u << pair))) {
                g_.quadMask[ti] |= uint8_t(1u << pair);
                if (targets_ && !v.pts.empty()) {
                    // The visit's input point farthest from its chord.
                    dvec2 ch = v.exit - v.entry;
                    double len = glm::length(ch);
                    dvec2 best = v.pts.front();
                    double bestDev = -1.0;
                    for (const dvec2& p : v.pts) {
                        double dev = len > 0 ? std::fabs(cross2(ch / len, p - v.entry)) : 0.0;
                        if (dev > bestDev) {
                            bestDev = dev;
                            best = p;
                        }
                    }
                    auto& tg = g_.targets[Grid::targetKey(ti, pair)];
                    tg.sum += best - dvec2(v.i, v.j);
                    ++tg.count;
                }
            }
            g_.quadMask[ti] &= nw;
        }
    }

private:
    struct Visit {
        int i, j;
        int in = -1, out = -1;
        bool quad = false;
        dvec2 entry{0.0}, exit{0.0}; // crossing points (texel space)
        std::vector<dvec2> pts;      // input points inside (quadratic mode)
    };

    // Closing a closed stroke: its last visit continues its first.
    void mergeIntoFirst() {
        Visit& f = visits_.front();
        Visit& l = visits_.back();
        f.in = l.in;
        f.entry = l.entry;
        f.quad |= l.quad;
        f.pts.insert(f.pts.end(), l.pts.begin(), l.pts.end());
        visits_.pop_back();
    }

    static dvec2 safeDir(dvec2 v) {
        double l = glm::length(v);
        return l > 0 ? v / l : dvec2(1.0, 0.0);
    }

    void segment(const OSeg& s) {
        const Quad& c = s.q;
        std::vector<double> ts{0.0, 1.0};
        dvec2 lo = glm::min(glm::min(c.p0, c.p1), c.p2), hi = glm::max(glm::max(c.p0, c.p1), c.p2);
        dvec2 a = c.a(), b = c.b();
        for (int axis = 0; axis < 2; ++axis) {
            double from = std::max(std::ceil(lo[axis]), 0.0),
                   to = std::min(std::floor(hi[axis]), double(g_.n));
            for (double line = from; line <= to; line += 1.0) {
                double r[2];
                int n = s.line ? 0 : quadRoots(a[axis], b[axis], c.p0[axis] - line, r);
                if (s.line) {
                    double den = c.p2[axis] - c.p0[axis];
                    if (den != 0.0) {
                        r[0] = (line - c.p0[axis]) / den;
                        n = 1;
                    }
                }
                for (int k = 0; k < n; ++k) {
                    if (r[k] > 0.0 && r[k] < 1.0) ts.push_back(r[k]);
                }
            }
        }
        std::sort(ts.begin(), ts.end());
        for (size_t k = 0; k + 1 < ts.size(); ++k) {
            double t0 = ts[k], t1 = ts[k + 1];
            if (t1 - t0 <= 1e-12) continue;
            dvec2 mid = c.at(0.5 * (t0 + t1));
            // Texels off the map collapse into one ring around it (index -1
            // or n), so a curve that leaves and re-enters still steps
            // between neighbours and its border crossings are recorded.
            int i = int(std::clamp(std::floor(mid.x), -1.0, double(g_.n)));
            int j = int(std::clamp(std::floor(mid.y), -1.0, double(g_.n)));
            dvec2 start = c.at(t0);
            dvec2 tan = safeDir(c.tangent(t0));
            if (!visits_.empty() && havePrevTan_) tan = safeDir(tan + prevTan_);
            piece(i, j, start, tan, !s.line);
            if (targets_ && !s.line) {
                if (t0 == 0.0) visits_.back().pts.push_back(start); // a joint inside the texel
                visits_.back().pts.push_back(mid);
                visits_.back().pts.push_back(c.at(0.25 * t0 + 0.75 * t1));
                visits_.back().pts.push_back(c.at(0.75 * t0 + 0.25 * t1));
            }
            prevTan_ = safeDir(c.tangent(t1));
            havePrevTan_ = true;
        }
    }

    void piece(int i, int j, dvec2 start, dvec2 tan, bool quad) {
        if (visits_.empty()) {
            visits_.push_back({i, j});
            visits_.back().quad = quad;
            return;
        }
        if (visits_.back().i != i || visits_.back().j != j) move(i, j, start, tan);
        visits_.back().quad |= quad;
    }

    // From the current texel to (i, j) through the point x: one step per
    // shared edge; a diagonal move (through a corner) goes through the upper
    // of the two side texels (vertical steps first when moving up).
    void move(int i, int j, dvec2 x, dvec2 tan) {
        int ci = visits_.back().i, cj = visits_.back().j;
        int guard = 0;
        while ((ci != i || cj != j) && guard++ < 8) {
            int ni = ci, nj = cj;
            bool stepY = cj != j && (j > cj || ci == i);
            if (stepY)
                nj += j > cj ? 1 : -1;
            else
                ni += i > ci ? 1 : -1;
            step(ci, cj, ni, nj, x, tan);
            ci = ni;
            cj = nj;
        }
        if (ci != i || cj != j) {
            // Far jump (a crossing lost to rounding): restart the visit there.
            visits_.push_back({i, j});
        }
    }

    void step(int ci, int cj, int ni, int nj, dvec2 x, dvec2 tan) {
        int outEdge, inEdge;
        bool horizontal; // the shared edge is horizontal
        int ei, ej;      // corner the shared edge starts at
        if (ni == ci + 1) {
            outEdge = 1;
            inEdge = 3;
            horizontal = false;
            ei = ni;
            ej = cj;
        } else if (ni == ci - 1) {
            outEdge = 3;
            inEdge = 1;
            horizontal = false;
            ei = ci;
            ej = cj;
        } else if (nj == cj + 1) {
            outEdge = 2;
            inEdge = 0;
            horizontal = true;
            ei = ci;
            ej = nj;
        } else {
            outEdge = 0;
            inEdge = 2;
            horizontal = true;
            ei = ci;
            ej = cj;
        }
        double pos = horizontal ? x.x - ei : x.y - ej;
        bool exists = horizontal ? (ei >= 0 && ei < g_.n && ej >= 0 && ej <= g_.n)
                                 : (ei >= 0 && ei <= g_.n && ej >= 0 && ej < g_.n);
        if (exists) {
            EdgeAcc& acc = horizontal ? g_.hAcc[g_.ci(ei, ej)] : g_.vAcc[g_.ci(ei, ej)];
            if (acc.count > 0) ++st_.edgePointsMerged;
            // Doubled-angle vector of the unit tangent (cos 2a, sin 2a).
            dvec2 u = safeDir(tan);
            acc.sumPos += std::clamp(pos, 0.0, 1.0);
            acc.sumCos += u.x * u.x - u.y * u.y;
            acc.sumSin += 2.0 * u.x * u.y;
            ++acc.count;
        }
        visits_.back().out = outEdge;
        visits_.back().exit = x;
        visits_.push_back({ni, nj});
        visits_.back().in = inEdge;
        visits_.back().entry = x;
    }

    Grid& g_;
    BakeStats& st_;
    bool targets_;
    std::vector<Visit> visits_;
    dvec2 prevTan_{1.0, 0.0};
    bool havePrevTan_ = false;
};

// Step 1: the options a caller may get wrong.
void checkOptions(const BakeOptions& opt) {
    if (opt.size < 1 || opt.size > kMaxFeatureMapSize) {
        throw io::InputError("(options)", "size",
                             "must be 1.." + std::to_string(kMaxFeatureMapSize) + ", got " +
                                 std::to_string(opt.size));
    }
    if (!(opt.bandTexels >= 1.0 && opt.bandTexels <= 1024.0)) {
        throw io::InputError("(options)", "band", "must be 1..1024 texels");
    }
    if (opt.smoothIterations < 0 || opt.smoothIterations > 1000) {
        throw io::InputError("(options)", "smooth", "iterations must be 0..1000");
    }
    if (!std::isfinite(opt.marginTexels) || opt.marginTexels < 0.0) {
        throw io::InputError("(options)", "margin", "must be a finite number >= 0");
    }
}

// Step 1: the input-to-texel transform (fitted or given).
TexelTransform inputToTexel(const CurveNetwork& net, const BakeOptions& opt) {
    TexelTransform xf = opt.fit ? fitTransform(net, opt) : opt.transform;
    if (!std::isfinite(xf.scale.x) || !std::isfinite(xf.scale.y) || !std::isfinite(xf.offset.x) ||
        !std::isfinite(xf.offset.y) || xf.scale.x == 0.0 || xf.scale.y == 0.0) {
        throw io::InputError("(options)", "transform",
                             "scale must be finite and non-zero, offset finite");
    }
    return xf;
}

// Steps 2-3: strokes, scan conversion, and the edge points of rule 1 (the
// centre of mass of each edge's crossings and the mean of their tangent
// angles), quantized to the 16-bit grids.
void scanConvert(const CurveNetwork& net, const std::vector<OSeg>& segs, const BakeOptions& opt,
                 Grid& g, BakeStats& st) {
    const int n = g.n;
    const size_t nc = size_t(n + 1) * size_t(n + 1);
    g.hAcc.clear();
    g.vAcc.clear();
    g.segMask.assign(size_t(n) * size_t(n), 0);
    g.quadMask.assign(size_t(n) * size_t(n), 0);
    g.straightMask.assign(size_t(n) * size_t(n), 0);
    {
        Scanner scanner(g, st, opt.mode == BakeMode::Quadratic);
        std::vector<Stroke> strokes = buildStrokes(net, segs);
        auto last = Clock::now();
        for (size_t k = 0; k < strokes.size(); ++k) {
            scanner.stroke(strokes[k]);
            if (opt.progress && Clock::now() - last > std::chrono::milliseconds(200)) {
                opt.progress("scan", double(k + 1) / double(strokes.size()));
                last = Clock::now();
            }
        }
    }
    // Every phase reports its end (its intermediate reports are throttled).
    if (opt.progress) opt.progress("scan", 1.0);
    sg::detail::assignWithHugePages(g.hPos, nc, -1.0);
    sg::detail::assignWithHugePages(g.vPos, nc, -1.0);
    sg::detail::assignWithHugePages(g.hAng, nc, 0.0);
    sg::detail::assignWithHugePages(g.vAng, nc, 0.0);
    for (int dir = 0; dir < 2; ++dir) {
        for (const auto& [k, acc] : dir == 0 ? g.hAcc : g.vAcc) {
            if (acc.count == 0) continue;
            double theta = 0.0;
            if (std::hypot(acc.sumCos, acc.sumSin) > 1e-9 * acc.count)
                theta = 0.5 * std::atan2(acc.sumSin, acc.sumCos);
            (dir == 0 ? g.hPos : g.vPos)[k] = quantizePos(acc.sumPos / acc.count);
            (dir == 0 ? g.hAng : g.vAng)[k] = quantizeAngle(theta);
        }
    }
    g.hAcc = {};
    g.vAcc = {};
}

// Rows of texels per block of the per-texel passes.
constexpr size_t kRowsPerBlock = 8;

// The configuration word bits 0-11 of every texel (after the straightening
// rules of the quadratic mode) and the edge points, into the maps. Blocks
// of rows in parallel (ex); their counters are summed in block order.
void storeConfigurations(const Grid& g, BakeMode mode, FeatureMaps& maps, BakeStats& st,
                         const Exec& ex) {
    const int n = g.n;
    const size_t nc = size_t(n + 1) * size_t(n + 1);
    sg::detail::assignWithHugePages(maps.seg, nc, uint16_t(0));
    struct Counts {
        int withFeatures = 0, withSegments = 0, curved = 0, kept = 0;
        ValidationCounters validation;
    };
    std::vector<Counts> counts(blockCount(size_t(n), kRowsPerBlock));
    forBlocks(ex, size_t(n), kRowsPerBlock, [&](size_t b, size_t j0, size_t j1) {
        Counts& c = counts[b];
        for (int j = int(j0); j < int(j1); ++j) {
            for (int i = 0; i < n; ++i) {
                size_t ti = g.ti(i, j);
                bool anyPoint = false;
                for (int e = 0; e < 4; ++e) anyPoint |= const_cast<Grid&>(g).pos(i, j, e) >= 0.0;
                if (anyPoint || g.segMask[ti]) ++c.withFeatures;
                if (!g.segMask[ti]) continue;
                ++c.withSegments;
                LocalTexel t = decodeTexel(g, i, j);
                if (mode == BakeMode::Quadratic) validateTexel(t, &c.validation);
                uint32_t word = uint32_t(t.nseg);
                for (int s = 0; s < t.nseg; ++s) {
                    word |= uint32_t(t.a[s]) << (2 + 5 * s);
                    word |= uint32_t(t.b[s]) << (4 + 5 * s);
                    if (t.curved[s]) {
                        word |= 1u << (6 + 5 * s);
                        ++c.curved;
                    }
                    ++c.kept;
                }
                maps.seg[maps.index(i, j)] = uint16_t(word);
            }
        }
    });
    for (const Counts& c : counts) {
        st.texelsWithFeatures += c.withFeatures;
        st.texelsWithSegments += c.withSegments;
        st.curvedSegments += c.curved;
        st.segmentsKept += c.kept;
        st.straightenedThetaMin += c.validation.thetaMin;
        st.straightenedFlat += c.validation.flat;
        st.straightenedCrossing += c.validation.cross;
    }
    sg::detail::assignWithHugePages(maps.hPos, nc, -1.0f);
    sg::detail::assignWithHugePages(maps.vPos, nc, -1.0f);
    sg::detail::assignWithHugePages(maps.hAngle, nc, 0.0f);
    sg::detail::assignWithHugePages(maps.vAngle, nc, 0.0f);
    forBlocks(ex, nc, kRowsPerBlock * size_t(n + 1), [&](size_t, size_t k0, size_t k1) {
        for (size_t k = k0; k < k1; ++k) {
            maps.hPos[k] = float(g.hPos[k]);
            maps.vPos[k] = float(g.vPos[k]);
            // Angles in both modes: linear maps use them for the gradient on
            // the curve (the curve's normal), quadratic maps also for the
            // shape.
            maps.hAngle[k] = g.hPos[k] >= 0.0 ? float(g.hAng[k]) : 0.0f;
            maps.vAngle[k] = g.vPos[k] >= 0.0 ? float(g.vAng[k]) : 0.0f;
        }
    });
}

} // namespace

FeatureMaps detail::bakeSteps(const CurveNetwork& net, const BakeOptions& opt, const Exec& ex,
                              BakeStats& st) {
    checkOptions(opt); // step 1
    st.size = opt.size;
    const TexelTransform xf = inputToTexel(net, opt);
    st.inputToTexel = xf;
    const std::vector<OSeg> segs = toTexelSpace(net, xf);

    Grid g;
    g.n = opt.size;
    PhaseTimer phase;
    scanConvert(net, segs, opt, g, st); // steps 2-3
    phase.stop(st.secondsScan, st.wallSecondsScan);

    phase = {};
    if (opt.mode == BakeMode::Quadratic) optimizeSignatures(g, st, opt.progress, ex); // step 4
    phase.stop(st.secondsOptimize, st.wallSecondsOptimize);

    FeatureMaps maps;
    maps.size = opt.size;
    maps.mode = opt.mode;
    maps.inputToTexel = xf;
    maps.bandTexels = opt.bandTexels;
    maps.smoothIterations = opt.smoothIterations;
    maps.source = net.source;
    storeConfigurations(g, opt.mode, maps, st, ex);
    g = {}; // the grid's memory back before the distance pass allocates

    phase = {};
    computeDistances(segs, opt.bandTexels, maps, opt.progress, ex); // step 5
    phase.stop(st.secondsDistance, st.wallSecondsDistance);

    phase = {};
    smoothGradients(opt.bandTexels, opt.smoothIterations, maps, ex); // step 6
    phase.stop(st.secondsSmooth, st.wallSecondsSmooth);
    if (opt.nearField) keepNearPieces(net, segs, opt, xf, maps, st); // exact near field
    return maps;
}

Grid detail::scanGrid(const CurveNetwork& net, const BakeOptions& opt, BakeStats& st) {
    checkOptions(opt);
    st.size = opt.size;
    st.inputToTexel = inputToTexel(net, opt);
    Grid g;
    g.n = opt.size;
    scanConvert(net, toTexelSpace(net, st.inputToTexel), opt, g, st);
    return g;
}

FeatureMaps bake(const CurveNetwork& net, const BakeOptions& opt, BakeStats* statsOut) {
    SG_EXPECTS(opt.threads >= 0 && opt.threads <= kMaxThreads,
               "BakeOptions::threads is 0 (all cores) .. kMaxThreads");
    const auto t0 = Clock::now();
    const double cpu0 = processCpu();
    BakeStats st;
    FeatureMaps maps;
    if (opt.threads == 1 || opt.size < kBakeSerialBelowSize) {
        maps = bakeSteps(net, opt, Exec{false}, st);
    } else {
        maps = runWithThreads(opt.threads, [&] {
            st.threads = tbb::this_task_arena::max_concurrency();
            return bakeSteps(net, opt, Exec{true}, st);
        });
    }
    st.seconds = wallSince(t0);
    st.cpuSeconds = processCpu() - cpu0;
    if (statsOut) *statsOut = st;
    return maps;
}

} // namespace sg::features
