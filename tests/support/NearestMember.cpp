#include "tests/support/NearestMember.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

namespace moire::test {

namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kInf = std::numeric_limits<double>::infinity();
const double kRoot3 = std::sqrt(3.0);

// wrap(v, w) of the language: v moved by whole multiples of w into [-w/2, w/2).
double wrapHalf(double v, double w) {
    return v - w * std::floor(v / w + 0.5);
}

// theta on the branch (ref - pi, ref + pi].
double thetaNear(double x, double y, double ref) {
    return ref + std::remainder(std::atan2(y, x) - ref, 2.0 * kPi);
}

double unit(double, double) {
    return 1.0;
}

} // namespace

// ---- Table 1, row by row --------------------------------------------------------------

RefFamily refLines(double angle) {
    double c = std::cos(angle), s = std::sin(angle);
    return {"lines", [=](double x, double y, double) { return x * c + y * s; }, unit, {}};
}

RefFamily refCircles() {
    return {"circles", [](double x, double y, double) { return std::hypot(x, y); }, unit, {}, true};
}

RefFamily refSquares() {
    return {"squares",
            [](double x, double y, double) { return std::max(std::fabs(x), std::fabs(y)); },
            unit,
            {},
            true};
}

RefFamily refTriangles() {
    return {
        "triangles",
        [](double x, double y, double) { return std::max(x, kRoot3 / 2 * std::fabs(y) - x / 2); },
        unit,
        {},
        true};
}

RefFamily refHexagons() {
    return {"hexagons",
            [](double x, double y, double) {
                return std::max(std::fabs(x), std::fabs(x) / 2 + kRoot3 / 2 * std::fabs(y));
            },
            unit,
            {},
            true};
}

RefFamily refNgon(int sides) {
    double sector = 2.0 * kPi / sides;
    // The support function needs no branch care: wrap folds theta by the polygon's symmetry.
    return {"ngon",
            [=](double x, double y, double) {
                return std::hypot(x, y) * std::cos(wrapHalf(std::atan2(y, x), sector));
            },
            unit,
            {},
            true};
}

RefFamily refWave(double amplitude, double frequency, double shift) {
    double w = 2.0 * kPi * frequency / 32.0; // omega = 2 pi f / 32
    return {"wave",
            [=](double x, double y, double) { return x - amplitude * std::sin(w * y + shift); },
            [=](double, double y) {
                double c = amplitude * w * std::cos(w * y + shift);
                return std::sqrt(1.0 + c * c);
            },
            {}};
}

RefFamily refParabola(double bend) {
    double a = bend / 100.0;
    return {"parabola",
            [=](double x, double y, double) { return y - a * x * x; },
            [=](double x, double) { return std::sqrt(1.0 + 4.0 * a * a * x * x); },
            {}};
}

RefFamily refHyperbola() {
    return {
        "hyperbola", [](double x, double y, double) { return std::sqrt(std::fabs(x * x - y * y)); },
        [](double x, double y) { return std::hypot(x, y) / std::sqrt(std::fabs(x * x - y * y)); },
        1};
}

RefFamily refSpiral(int arms, double spacing) {
    double b = arms * spacing / (2.0 * kPi); // b = M s / 2 pi
    return {
        "spiral",
        [=](double x, double y, double ref) { return std::hypot(x, y) - b * thetaNear(x, y, ref); },
        [=](double x, double y) { return std::sqrt(1.0 + b * b / (x * x + y * y)); },
        {}};
}

// ---- The layer ------------------------------------------------------------------------

void RefLayer::toLocal(double wx, double wy, double& lx, double& ly) const {
    double dx = wx - originX, dy = wy - originY;
    double c = std::cos(rotation), s = std::sin(rotation);
    lx = c * dx + s * dy;
    ly = -s * dx + c * dy;
}

void RefLayer::toWorld(double lx, double ly, double& wx, double& wy) const {
    double c = std::cos(rotation), s = std::sin(rotation);
    wx = originX + c * lx - s * ly;
    wy = originY + s * lx + c * ly;
}

double RefLayer::index(double wx, double wy) const {
    double lx, ly;
    toLocal(wx, wy, lx, ly);
    return (family.phi(lx, ly, 0.0) - phase) / spacing;
}

std::string layerSource(const std::string& family, const std::string& args, const RefLayer& layer) {
    auto num = [](double v) {
        char buf[40];
        std::snprintf(buf, sizeof buf, "%.15g", v); // 30 degrees, not 29.999999999999996
        return std::string(buf);
    };
    return "layer { family = " + family + "; spacing = " + num(layer.spacing) +
           "; phase = " + num(layer.phase) + "; origin = (" + num(layer.originX) + ", " +
           num(layer.originY) + "); rotation = " + num(layer.rotation * 180.0 / kPi) + "deg" +
           (args.empty() ? "" : "; " + args) + " }\n";
}

double memberCurvature(const RefLayer& layer, const Nearest& at) {
    const double x = at.lx, y = at.ly, h = 1e-3 * layer.spacing, ref = std::atan2(y, x);
    auto f = [&](double dx, double dy) { return layer.family.phi(x + dx, y + dy, ref); };
    double fx = (f(h, 0) - f(-h, 0)) / (2 * h), fy = (f(0, h) - f(0, -h)) / (2 * h);
    double fxx = (f(h, 0) - 2 * f(0, 0) + f(-h, 0)) / (h * h),
           fyy = (f(0, h) - 2 * f(0, 0) + f(0, -h)) / (h * h);
    double fxy = (f(h, h) - f(h, -h) - f(-h, h) + f(-h, -h)) / (4 * h * h);
    double g = std::hypot(fx, fy);
    return std::fabs(fxx * fy * fy - 2 * fxy * fx * fy + fyy * fx * fx) / (g * g * g);
}

// ---- The search -----------------------------------------------------------------------
//
// Rays leave the point q in every direction; along each, the first place where the index
// (phi - phase) / s passes a whole number n (a member, and one that exists: n >= first) is
// found by marching and then bisection. The nearest member is the shortest such ray. Why
// this finds the true distance d: the ray aimed exactly at the nearest point meets no
// member before it (every earlier point is closer than d), and meets the member there
// head-on, so its first crossing is at exactly d; every other ray's first crossing is a
// point on some member, so no ray reports less than d. The minimum over rays is therefore
// d, and the only error is in approximating the optimal ray, handled in two stages:
//  - a coarse fan of kRays rays only has to land in the right basin of the function
//    t(angle). Its value on that basin's best ray exceeds d by a relative
//    (pi / kRays)^2 (1 + d / rho) / 2 at most (3e-4 (1 + d / rho) for a member of
//    curvature radius rho bulging towards q; less for one that is flat or hollow), and
//    every local minimum of the fan within 50% of the best is refined, so the right basin
//    is never dropped for a rival that is only slightly nearer;
//  - each candidate is refined by golden-section search on the angle (30 steps shrink the
//    bracket from 2 * 2 pi / kRays to 5e-8 rad, and t grows only quadratically off the
//    optimum: an error near d * 1e-15), with crossings located by 40 bisections of a
//    march step (s / 64 / 2^40 < 1e-13 s).
// The search error is thus ~1e-12 of the spacing, six orders below the tightest tolerance
// used (1e-6 s). The march step s / 64 (halved wherever the index changes by more than a
// quarter per step) cannot step over a member crossed head-on; it could step over a member
// that a ray only grazes, which affects rays far from the optimum but not the optimal one.
// A member that is a single point (a concentric family's centre, at level 0) is never
// crossed, only touched, so it is added by hand (RefFamily::pointCentre). The hyperbola's
// asymptote pair (level 0) is only touched too, and rightly never found: it is excluded.

namespace {

constexpr int kRays = 128;

struct Search {
    const RefLayer& layer;
    double qx, qy, ref, radius;

    // The index at (x, y), with theta taken on the branch nearest `branch`.
    double u(double x, double y, double branch) const {
        return (layer.family.phi(x, y, branch) - layer.phase) / layer.spacing;
    }

    // Is a member that exists crossed between index values a and b?
    bool crosses(double a, double b) const {
        double lo = std::min(a, b), hi = std::max(a, b);
        double nLo = std::floor(lo) + 1.0, nHi = std::floor(hi);
        if (layer.family.first) nLo = std::max(nLo, static_cast<double>(*layer.family.first));
        return nLo <= nHi;
    }

    // Distance along direction `angle` to the first member crossed (inf if none within the
    // radius); `bisections` sets how finely the crossing is located.
    double firstCrossing(double angle, int bisections) const {
        double dx = std::cos(angle), dy = std::sin(angle);
        const double h0 = layer.spacing / 64.0, hMin = layer.spacing * 1e-12;
        // theta is followed continuously along the ray (each sample's branch is the one
        // nearest the previous sample's angle), so an angular family's index is continuous
        // along it even where the ray crosses atan2's cut.
        double t0 = 0.0, th0 = ref, u0 = u(qx, qy, th0), h = h0;
        while (t0 < radius) {
            double t1 = std::min(t0 + h, radius);
            double x1 = qx + t1 * dx, y1 = qy + t1 * dy;
            double th1 = thetaNear(x1, y1, th0);
            double u1 = u(x1, y1, th1);
            if (std::fabs(u1 - u0) > 0.25 && h > hMin) { // steep: take a shorter step
                h *= 0.5;
                continue;
            }
            if (crosses(u0, u1)) {
                double a = t0, b = t1;
                for (int i = 0; i < bisections; ++i) {
                    double m = 0.5 * (a + b);
                    if (crosses(u0, u(qx + m * dx, qy + m * dy, th0)))
                        b = m;
                    else
                        a = m;
                }
                return b;
            }
            t0 = t1;
            th0 = th1;
            u0 = u1;
            h = h0;
        }
        return kInf;
    }
};

} // namespace

Nearest nearestMember(const RefLayer& layer, double wx, double wy, double radius) {
    double qx, qy;
    layer.toLocal(wx, wy, qx, qy);
    Search search{layer, qx, qy, std::atan2(qy, qx), radius};

    const double step = 2.0 * kPi / kRays;
    std::vector<double> coarse(kRays);
    for (int k = 0; k < kRays; ++k) coarse[k] = search.firstCrossing(k * step, 12);
    double coarseBest = *std::min_element(coarse.begin(), coarse.end());

    // Candidate basins: local minima of the fan, nearest first, at most eight (a point at
    // the centre of the circles sees every ray as a minimum).
    std::vector<int> candidates;
    for (int k = 0; k < kRays; ++k) {
        double prev = coarse[(k + kRays - 1) % kRays], next = coarse[(k + 1) % kRays];
        if (coarse[k] < kInf && coarse[k] <= prev && coarse[k] <= next &&
            coarse[k] <= 1.5 * coarseBest + 1e-12)
            candidates.push_back(k);
    }
    std::sort(candidates.begin(), candidates.end(),
              [&](int a, int b) { return coarse[a] < coarse[b]; });
    if (candidates.size() > 8) candidates.resize(8);

    double best = kInf, bestAngle = 0.0;
    auto eval = [&](double angle) {
        double t = search.firstCrossing(angle, 40);
        if (t < best) {
            best = t;
            bestAngle = angle;
        }
        return t;
    };
    const double g = (std::sqrt(5.0) - 1.0) / 2.0;
    for (int k : candidates) {
        double a = (k - 1) * step, b = (k + 1) * step;
        double c = b - g * (b - a), d = a + g * (b - a);
        double fc = eval(c), fd = eval(d);
        for (int i = 0; i < 30; ++i) {
            if (fc < fd) {
                b = d, d = c, fd = fc;
                c = b - g * (b - a);
                fc = eval(c);
            } else {
                a = c, c = d, fc = fd;
                d = a + g * (b - a);
                fd = eval(d);
            }
        }
        eval(k * step);
    }
    Nearest out;
    out.found = best < kInf;
    out.distance = best;
    out.lx = qx + best * std::cos(bestAngle);
    out.ly = qy + best * std::sin(bestAngle);
    out.member = std::lround(search.u(out.lx, out.ly, thetaNear(out.lx, out.ly, search.ref)));

    // The centre of a concentric family is a member when its level, 0, is one: 0 = n s + phase.
    const RefFamily& f = layer.family;
    double centre = -layer.phase / layer.spacing;
    if (f.pointCentre && std::fabs(centre - std::round(centre)) < 1e-9 &&
        (!f.first || std::round(centre) >= *f.first)) {
        double r = std::hypot(qx, qy);
        if (!out.found || r < out.distance) {
            out.found = true;
            out.distance = r;
            out.lx = out.ly = 0.0;
            out.member = std::lround(centre);
        }
    }
    return out;
}

} // namespace moire::test
