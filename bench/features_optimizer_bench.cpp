// features_optimizer_bench: the signature optimisation of the quadratic
// bake (TOG 2008 sec. 4, Eq. 2-3) with its compass search against SQP, the
// method the paper names, on the paper's energy (the thin-plate energy of
// Eq. 3 of the affected segments alone) and the same constraint ("every
// affected texel valid", features/src/bake_quadratic.cpp).
//
// Every invalid texel of the inputs after scan conversion is optimised on
// its own from the same grid (restored in between) by:
//   compass  the bake's search (bake_optimize.cpp), extreme-barrier merit;
//   SQP      sequential quadratic programming in the scaled variables:
//            forward-difference gradients of the energy and of the
//            violation, a damped-BFGS Hessian of the Lagrangian, one
//            linearised inequality (violation + grad . d <= 0), a
//            backtracking line search on the l1 merit f + mu * violation;
//            the compass search's three starts (one run from each, the
//            lowest feasible energy kept) and its budget of 320
//            evaluations, shared by the runs.
// Reported per input: texels repaired (ending valid), and over the texels
// both repair, the energy ratio SQP / compass (median, and how often each
// is lower) and the evaluations used.
//
// Run: build/bin/features_optimizer_bench
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "bake_internal.h"
#include "surfgrad/features/curves.h"

using namespace sg::features;
using namespace sg::features::detail;

namespace {

using Vec = std::vector<double>;

double dotv(const Vec& a, const Vec& b) {
    double s = 0;
    for (size_t k = 0; k < a.size(); ++k) s += a[k] * b[k];
    return s;
}

// SQP from start x in scaled variables z = x / scale, until the budget of
// evaluations; true when it ends feasible.
bool sqpFrom(TexelProblem& p, Vec& x, int budget) {
    const size_t n = p.size();
    auto toX = [&](const Vec& z) {
        Vec r(n);
        for (size_t k = 0; k < n; ++k) r[k] = z[k] * p.scale(k);
        return r;
    };
    Vec z(n);
    for (size_t k = 0; k < n; ++k) z[k] = x[k] / p.scale(k);
    auto evalFC = [&](const Vec& zz, double& f, double& c) {
        Vec xx = toX(zz);
        c = p.violation(xx);
        f = p.energy(xx);
    };
    auto gradients = [&](const Vec& zz, double f, double c, Vec& gf, Vec& gc) {
        const double h = 1e-3; // of the natural step
        gf.assign(n, 0.0);
        gc.assign(n, 0.0);
        for (size_t k = 0; k < n; ++k) {
            Vec y = zz;
            y[k] += h;
            double fk, ck;
            evalFC(y, fk, ck);
            gf[k] = (fk - f) / h;
            gc[k] = (ck - c) / h;
        }
    };
    std::vector<Vec> B(n, Vec(n, 0.0));
    for (size_t k = 0; k < n; ++k) B[k][k] = 1.0;
    auto solveB = [&](const Vec& r) {
        // Gaussian elimination on a copy (n <= 8).
        std::vector<Vec> a = B;
        Vec b = r;
        for (size_t c = 0; c < n; ++c) {
            size_t piv = c;
            for (size_t k = c + 1; k < n; ++k)
                if (std::fabs(a[k][c]) > std::fabs(a[piv][c])) piv = k;
            std::swap(a[c], a[piv]);
            std::swap(b[c], b[piv]);
            if (std::fabs(a[c][c]) < 1e-14) a[c][c] = 1e-14;
            for (size_t k = c + 1; k < n; ++k) {
                double m = a[k][c] / a[c][c];
                for (size_t j = c; j < n; ++j) a[k][j] -= m * a[c][j];
                b[k] -= m * b[c];
            }
        }
        Vec out(n);
        for (size_t c = n; c-- > 0;) {
            double s = b[c];
            for (size_t j = c + 1; j < n; ++j) s -= a[c][j] * out[j];
            out[c] = s / a[c][c];
        }
        return out;
    };
    double f, c;
    evalFC(z, f, c);
    double mu = 10.0;
    Vec gf, gc;
    gradients(z, f, c, gf, gc);
    while (p.evaluations < budget) {
        // QP: min gf.d + d'Bd/2 s.t. c + gc.d <= 0 (one linearised row).
        Vec bf = solveB(gf);
        Vec d(n);
        double lambda = 0.0;
        for (size_t k = 0; k < n; ++k) d[k] = -bf[k];
        if (c + dotv(gc, d) > 0.0) {
            Vec bc = solveB(gc);
            double den = dotv(gc, bc);
            if (den < 1e-14) break; // the linearised constraint cannot be met
            lambda = std::max(0.0, (c - dotv(gc, bf)) / den);
            for (size_t k = 0; k < n; ++k) d[k] = -bf[k] - lambda * bc[k];
        }
        mu = std::max(mu, 2.0 * lambda);
        // Backtracking on the l1 merit.
        const double phi0 = f + mu * c;
        const double slope = dotv(gf, d) - mu * c;
        double alpha = 1.0, fn = f, cn = c;
        Vec zn = z;
        bool moved = false;
        for (int ls = 0; ls < 12 && p.evaluations < budget; ++ls, alpha *= 0.5) {
            for (size_t k = 0; k < n; ++k) zn[k] = z[k] + alpha * d[k];
            evalFC(zn, fn, cn);
            if (fn + mu * cn <= phi0 + 1e-4 * alpha * std::min(slope, 0.0)) {
                moved = true;
                break;
            }
        }
        if (!moved) break;
        Vec gfn, gcn;
        gradients(zn, fn, cn, gfn, gcn);
        // Damped BFGS (Powell) on the Lagrangian's gradient.
        Vec s(n), y(n);
        for (size_t k = 0; k < n; ++k) {
            s[k] = zn[k] - z[k];
            y[k] = (gfn[k] + lambda * gcn[k]) - (gf[k] + lambda * gc[k]);
        }
        Vec bs(n, 0.0);
        for (size_t a = 0; a < n; ++a)
            for (size_t b = 0; b < n; ++b) bs[a] += B[a][b] * s[b];
        double sbs = dotv(s, bs), sy = dotv(s, y);
        if (sbs > 1e-18) {
            double theta = sy >= 0.2 * sbs ? 1.0 : 0.8 * sbs / (sbs - sy);
            Vec r(n);
            for (size_t k = 0; k < n; ++k) r[k] = theta * y[k] + (1 - theta) * bs[k];
            double sr = dotv(s, r);
            for (size_t a = 0; a < n; ++a)
                for (size_t b = 0; b < n; ++b)
                    B[a][b] += -bs[a] * bs[b] / sbs + (sr > 1e-18 ? r[a] * r[b] / sr : 0.0);
        }
        z = zn;
        f = fn;
        c = cn;
        gf = gfn;
        gc = gcn;
        if (std::sqrt(dotv(s, s)) < 1e-5) break;
    }
    x = toX(z);
    return p.violation(x) <= 0.0;
}

// SQP from each of the compass search's starts in turn (sharing the
// budget), keeping the lowest-energy feasible result.
bool sqpSearch(TexelProblem& p, Vec& x, int budget) {
    const auto starts = p.starts();
    bool found = false;
    double bestE = 1e300;
    for (size_t k = 0; k < starts.size() && p.evaluations < budget; ++k) {
        Vec y = starts[k];
        const int share = p.evaluations + (budget - p.evaluations) / int(starts.size() - k);
        if (sqpFrom(p, y, share)) {
            double e = p.energy(y);
            if (e < bestE) {
                bestE = e;
                x = y;
                found = true;
            }
        }
    }
    if (!found) x = starts[0];
    return found;
}

struct Input {
    std::string name;
    CurveNetwork net;
    int size;
    bool fit;
};

CurveNetwork tightArcs() {
    CurveNetwork net;
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    for (int k = 0; k < 40; ++k) {
        glm::dvec2 c(4.0 + 24.0 * u(rng), 4.0 + 24.0 * u(rng));
        double r = 0.3 + 1.2 * u(rng), a0 = 2 * M_PI * u(rng), sweep = 0.6 + 1.8 * u(rng);
        Segment s;
        s.kind = Segment::Kind::Quadratic;
        s.p0 = c + r * glm::dvec2(std::cos(a0), std::sin(a0));
        s.p2 = c + r * glm::dvec2(std::cos(a0 + sweep), std::sin(a0 + sweep));
        s.p1 = c + r / std::cos(sweep / 2) *
                       glm::dvec2(std::cos(a0 + sweep / 2), std::sin(a0 + sweep / 2));
        s.curve = int(net.curves.size());
        net.curves.push_back({});
        net.segments.push_back(s);
    }
    return net;
}

} // namespace

int main() {
    std::vector<Input> inputs;
    const std::string wqy = "/usr/share/fonts/truetype/wqy/wqy-microhei.ttc";
    const std::string data = SURFGRAD_DATA_DIR;
    try {
        for (int size : {64, 128, 256}) {
            inputs.push_back({"WenQuanYi \xe7\xb9\x81", loadFont(wqy, "\xe7\xb9\x81"), size, true});
            inputs.push_back({"WenQuanYi \xe5\xbf\x83", loadFont(wqy, "\xe5\xbf\x83"), size, true});
            inputs.push_back({"DejaVu Sans Rg",
                              loadFont("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf", "Rg"),
                              size, true});
            inputs.push_back(
                {"Inconsolata Q&",
                 loadFont("/usr/share/fonts/truetype/inconsolata/Inconsolata.otf", "Q&"), size,
                 true});
            for (const char* icon : {"flame", "carrot", "paw-print", "chart-spline"})
                inputs.push_back({std::string("lucide ") + icon,
                                  loadSvg(data + "/svg/" + icon + ".svg"), size, true});
        }
    } catch (const std::exception& e) {
        std::printf("(input missing: %s)\n", e.what());
    }
    inputs.push_back({"40 tight arcs (r 0.3-1.5)", tightArcs(), 32, false});

    std::printf("| input | map | invalid texels | repaired: compass | repaired: SQP | both: "
                "energy SQP / compass (median) | SQP lower / compass lower | evaluations "
                "compass / SQP (median) |\n|---|---|---|---|---|---|---|---|\n");
    long totalInvalid = 0, totalCompass = 0, totalSqp = 0, sqpLower = 0, compassLower = 0;
    std::vector<double> allRatios;
    for (Input& in : inputs) {
        BakeOptions o;
        o.size = in.size;
        o.mode = BakeMode::Quadratic;
        o.fit = in.fit;
        if (!in.fit) o.transform = {};
        BakeStats st;
        Grid g = scanGrid(in.net, o, st);
        std::vector<std::pair<int, int>> invalid;
        for (int j = 0; j < g.n; ++j) {
            for (int i = 0; i < g.n; ++i) {
                size_t ti = g.ti(i, j);
                if (!(g.segMask[ti] & g.quadMask[ti])) continue;
                LocalTexel t = decodeTexel(g, i, j);
                if (validateTexel(t, nullptr) > 0.0) invalid.emplace_back(i, j);
            }
        }
        int repC = 0, repS = 0, lowS = 0, lowC = 0;
        std::vector<double> ratios, evC, evS;
        for (auto [i, j] : invalid) {
            TexelProblem pc(g, i, j, TexelProblem::Energy::Paper);
            if (pc.size() == 0) continue;
            Vec xc, xs;
            bool okC = compassSearch(pc, xc);
            double eC = okC ? pc.energy(xc) : 0.0;
            evC.push_back(pc.evaluations);
            pc.write(pc.initial());
            TexelProblem ps(g, i, j, TexelProblem::Energy::Paper);
            bool okS = sqpSearch(ps, xs, 320);
            double eS = okS ? ps.energy(xs) : 0.0;
            evS.push_back(ps.evaluations);
            ps.write(ps.initial());
            repC += okC;
            repS += okS;
            if (okC && okS) {
                ratios.push_back(eS / std::max(eC, 1e-12));
                lowS += eS < eC * (1 - 1e-6);
                lowC += eC < eS * (1 - 1e-6);
            }
        }
        std::sort(ratios.begin(), ratios.end());
        std::sort(evC.begin(), evC.end());
        std::sort(evS.begin(), evS.end());
        auto med = [](const std::vector<double>& v) { return v.empty() ? 0.0 : v[v.size() / 2]; };
        std::printf("| %s | %d^2 | %zu | %d | %d | %.3f | %d / %d | %.0f / %.0f |\n",
                    in.name.c_str(), in.size, invalid.size(), repC, repS, med(ratios), lowS, lowC,
                    med(evC), med(evS));
        totalInvalid += long(invalid.size());
        totalCompass += repC;
        totalSqp += repS;
        sqpLower += lowS;
        compassLower += lowC;
        allRatios.insert(allRatios.end(), ratios.begin(), ratios.end());
    }
    std::sort(allRatios.begin(), allRatios.end());
    std::printf("| all | | %ld | %ld | %ld | %.3f | %ld / %ld | |\n", totalInvalid, totalCompass,
                totalSqp, allRatios.empty() ? 0.0 : allRatios[allRatios.size() / 2], sqpLower,
                compassLower);
    return 0;
}
