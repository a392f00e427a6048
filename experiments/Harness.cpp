#include "experiments/Harness.h"

#include "compiler/backend/interp/Interpreter.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <numeric>

namespace moire::exp {

Options parseOptions(int argc, char** argv, const char* what) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        if (std::strcmp(argv[i], "--quick") == 0) {
            o.quick = true;
        } else {
            std::fprintf(stderr, "usage: %s [--quick]\n  %s\n", argv[0], what);
            std::exit(2);
        }
    }
    return o;
}

double oracleMerit(int k1, int k2, G g1, G g2) {
    // Eq. 11 and 12, written out again (the oracle shares no code with the shipped search).
    const double bx = k1 * g1.x + k2 * g2.x, by = k1 * g1.y + k2 * g2.y;
    const double cx = k1 * g1.x - k2 * g2.x, cy = k1 * g1.y - k2 * g2.y;
    const double eta = std::sqrt(bx * bx + by * by) / (0.5 * std::sqrt(cx * cx + cy * cy));
    return std::abs(double(k1) * double(k2)) * std::max(eta, 1e-3); // the floor of kEtaFloor
}

Exhaustive exhaustiveMinimum(G g1, G g2, int maxOrder) {
    Exhaustive best{INFINITY, 0, 0};
    for (int k1 = 1; k1 <= maxOrder; ++k1)
        for (int k2 = -maxOrder; k2 <= maxOrder; ++k2) {
            if (k2 == 0) continue;
            const double mu = oracleMerit(k1, k2, g1, g2);
            // Ties go to the lower order (then to the order scanned first).
            const int order = std::max(k1, std::abs(k2));
            const int bestOrder = std::max(best.k1, std::abs(best.k2));
            if (mu < best.mu || (mu == best.mu && order < bestOrder)) best = {mu, k1, k2};
        }
    return best;
}

std::vector<Exhaustive> exhaustiveLadder(G g1, G g2, int maxOrder) {
    // Each budget adds the ring of characters whose larger coefficient is exactly n.
    std::vector<Exhaustive> ladder;
    Exhaustive best{INFINITY, 0, 0};
    for (int n = 1; n <= maxOrder; ++n) {
        for (int k1 = 1; k1 <= n; ++k1)
            for (int k2 = -n; k2 <= n; ++k2) {
                if (k2 == 0 || std::max(k1, std::abs(k2)) != n) continue;
                const double mu = oracleMerit(k1, k2, g1, g2);
                if (mu < best.mu) best = {mu, k1, k2};
            }
        ladder.push_back(best);
    }
    return ladder;
}

std::vector<Fraction> convergents(double x, int64_t maxQ) {
    std::vector<Fraction> out;
    int64_t p0 = 1, q0 = 0, p1 = 0, q1 = 1; // p_{-1}/q_{-1} = 1/0, p_{-2}/q_{-2} = 0/1
    double r = x;
    for (int n = 0; n < 64; ++n) {
        const double a = std::floor(r);
        if (a > 1e12) break;
        const auto ai = static_cast<int64_t>(a);
        const int64_t p = ai * p0 + p1, q = ai * q0 + q1;
        if (q > maxQ) break;
        out.push_back({p, q});
        p1 = p0;
        q1 = q0;
        p0 = p;
        q0 = q;
        const double frac = r - a;
        // The expansion ends where the remainder is lost in double rounding.
        if (frac < 1e-9 * std::max(1.0, r)) break;
        r = 1.0 / frac;
    }
    return out;
}

Shipped stackKernel(const std::vector<G>& g) {
    // The kernel: the layers' gradients are uniforms; the stack's character is built by
    // stackCharacter, exactly as a view builds it, and run on the reference interpreter.
    ir::Function f;
    f.name = "characters";
    f.numOutputs = 4;
    ir::Builder b(f);
    std::vector<lower::LayerFields> layers;
    for (size_t i = 0; i < g.size(); ++i) {
        lower::LayerFields l;
        l.index = l.distance = b.constF(0.0);
        l.gradX = b.uniform(static_cast<int>(2 * i));
        l.gradY = b.uniform(static_cast<int>(2 * i + 1));
        layers.push_back(l);
    }
    lower::Character c = lower::stackCharacter(b, layers);
    b.output(0, c.mu);
    for (int i = 0; i < 3; ++i)
        b.output(1 + i, i < c.count ? c.k[static_cast<size_t>(i)] : b.constF(0.0));
    ir::verify(f);
    std::vector<double> u;
    for (const G& v : g) {
        u.push_back(v.x);
        u.push_back(v.y);
    }
    const std::vector<double> out = Interpreter(f).atPixel(u, 0.5, 0.5, 1, 1);
    return {out[0], static_cast<int>(std::lround(out[1])), static_cast<int>(std::lround(out[2])),
            static_cast<int>(std::lround(out[3]))};
}

Shipped shippedPair(G g1, G g2) {
    const lower::PairCharacterT<double> c = lower::bestPairCharacter<double>(g1, g2);
    return {c.mu, static_cast<int>(std::lround(c.k1)), static_cast<int>(std::lround(c.k2)), 0};
}

std::string characterName(int k1, int k2, int k3, bool three) {
    const int sign = (k1 != 0 ? k1 : (k2 != 0 ? k2 : k3)) < 0 ? -1 : 1;
    char buf[64];
    if (three)
        std::snprintf(buf, sizeof buf, "(%d, %d, %d)", sign * k1, sign * k2, sign * k3);
    else
        std::snprintf(buf, sizeof buf, "(%d, %d)", sign * k1, sign * k2);
    return buf;
}

bool sameCharacter(int a1, int a2, int b1, int b2) {
    return (a1 == b1 && a2 == b2) || (a1 == -b1 && a2 == -b2);
}

G gradientOf(double pitch, double angle) {
    return {std::cos(angle) / pitch, std::sin(angle) / pitch};
}

void printTitle(const std::string& title) {
    std::printf("%s\n%-58s %-22s %s\n", title.c_str(), "", "paper", "ours");
}

void printRow(const std::string& what, const std::string& paper, const std::string& ours) {
    std::printf("  %-56s %-22s %s\n", what.c_str(), paper.c_str(), ours.c_str());
}

std::string percent(double fraction) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.1f%%", 100.0 * fraction);
    return buf;
}

int verdict(bool ok, const std::string& why) {
    if (ok) {
        std::printf("PASS\n");
        return 0;
    }
    std::printf("FAIL: %s\n", why.c_str());
    return 1;
}

} // namespace moire::exp
