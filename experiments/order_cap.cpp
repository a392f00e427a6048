// The order cap (spec §4.3): over random carrier pairs, how many visible fringes (min mu_k <
// 1/4 over every character of order <= 48, found exhaustively) the |k_i| <= 2 scan declares
// absent, and how many the shipped reduction misses; how often the shipped search names the
// exhaustive winner.
//
// The pairs: pitches s1 log-uniform in [4, 40] and s2 = s1 4^u, u uniform in [-1, 1] (within a
// factor four); the first gradient in a uniform random direction, the second turned from it
// by a twist uniform in [-kTwistDeg, kTwistDeg] and, for half the pairs, reversed (an index
// counted the other way: the sum characters). Seeded, so every run prints the same table.
#include "experiments/Harness.h"

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace moire;
using namespace moire::exp;

namespace {

constexpr int kMaxOrder = 48;
constexpr double kTwistDeg = 10.0;

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseOptions(argc, argv, "the order cap table of spec §4.3");
    const int trials = opt.quick ? 400 : 4000;
    std::mt19937_64 rng(20240415);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    int visible = 0, floorMisses = 0, shippedMisses = 0, agree = 0, agreeVisible = 0,
        slowerBeyond = 0;
    int nearThree = 0, irAgrees = 0;
    for (int t = 0; t < trials; ++t) {
        const double s1 = 4.0 * std::pow(10.0, unit(rng));
        const double s2 = s1 * std::pow(4.0, 2.0 * unit(rng) - 1.0);
        const double a1 = 2 * std::numbers::pi * unit(rng);
        const double twist = (2.0 * unit(rng) - 1.0) * kTwistDeg * std::numbers::pi / 180.0;
        const double flip = unit(rng) < 0.5 ? std::numbers::pi : 0.0;
        const G g1 = gradientOf(s1, a1), g2 = gradientOf(s2, a1 + twist + flip);
        const Exhaustive all = exhaustiveMinimum(g1, g2, kMaxOrder);
        const Exhaustive low = exhaustiveMinimum(g1, g2, 2);
        const Shipped got = shippedPair(g1, g2);
        const Shipped kernel = stackKernel({g1, g2}); // the same search as IR, interpreted
        irAgrees += sameCharacter(kernel.k1, kernel.k2, got.k1, got.k2) &&
                    std::abs(kernel.mu - got.mu) <= 1e-12 * std::max(1.0, got.mu);
        const bool same = sameCharacter(got.k1, got.k2, all.k1, all.k2);
        agree += same;
        if (!same && got.mu < all.mu) ++slowerBeyond; // a slower beat past order 48
        if (all.mu < lower::kFringeMerit) {
            ++visible;
            agreeVisible += same;
            if (low.mu >= lower::kFringeMerit) {
                ++floorMisses;
                const double r = std::max(s1, s2) / std::min(s1, s2);
                if (std::abs(r - 3.0) < 0.25) ++nearThree;
            }
            if (got.mu >= lower::kFringeMerit) ++shippedMisses;
        }
    }
    char buf[64];
    auto num = [&](double v) {
        std::snprintf(buf, sizeof buf, "%g", v);
        return std::string(buf);
    };
    printTitle("order cap: " + num(trials) + " random pairs within a factor 4 in pitch, twist +-" +
               num(kTwistDeg) + " deg");
    printRow("pairs with a visible fringe (min mu < 1/4, order <= 48)", "-",
             num(visible) + " (" + percent(double(visible) / trials) + ")");
    printRow("visible fringes the |k_i| <= 2 scan misses", "858 (21%)",
             num(floorMisses) + " (" + percent(double(floorMisses) / visible) + ")");
    printRow("  of them at a pitch ratio within 0.25 of 3", "clustered near 3", num(nearThree));
    printRow("visible fringes the shipped reduction misses", "1", num(shippedMisses));
    printRow("kernel IR (interpreter) = the search in double", "-",
             num(irAgrees) + " of " + num(trials));
    printRow("shipped winner = exhaustive winner, all pairs", "99.8%",
             percent(double(agree) / trials));
    printRow("shipped winner = exhaustive winner, visible pairs", "-",
             percent(double(agreeVisible) / visible));
    printRow("  of the disagreements, a slower beat found past order 48", "-", num(slowerBeyond));
    // The quick variant's claim: the reduction catches what the order-two floor misses.
    const bool ok =
        floorMisses > 0 && shippedMisses * 20 <= floorMisses && double(agree) / trials >= 0.98;
    return verdict(ok, "the shipped search should miss under a twentieth of the floor's misses "
                       "and agree with the exhaustive winner on 98% of pairs");
}
