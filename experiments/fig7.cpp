// Fig. 7 of the spec: two line families at pitches 15 and 5, twisted 2 degrees. The render
// carries a broad (3, -1) fringe; the per-pixel reduction must name it, where a criterion
// capped at |k_i| <= 2 reads the frame as fringe-free.
#include "experiments/Harness.h"

#include <cmath>
#include <cstdio>
#include <numbers>

using namespace moire;
using namespace moire::exp;

int main(int argc, char** argv) {
    const Options opt = parseOptions(argc, argv, "the Fig. 7 case of spec §4.3");
    // The pair is the same at every point (straight families), so --quick changes nothing
    // but is accepted like every experiment's.
    (void)opt;
    const double twist = 2 * std::numbers::pi / 180;
    const G g1 = gradientOf(15, 0), g2 = gradientOf(5, twist);
    const Shipped kernel = stackKernel({g1, g2});
    const Shipped twin = shippedPair(g1, g2);
    const Exhaustive floorScan = exhaustiveMinimum(g1, g2, 2);
    const Exhaustive all = exhaustiveMinimum(g1, g2, 48);
    char buf[96];
    printTitle("fig7: line families at pitches 15 and 5, twisted 2 degrees");
    std::snprintf(buf, sizeof buf, "%s, mu %.4f", characterName(kernel.k1, kernel.k2).c_str(),
                  kernel.mu);
    printRow("winner named by the kernel (IR, interpreter)", "(3, -1)", buf);
    std::snprintf(buf, sizeof buf, "%s, mu %.4f", characterName(twin.k1, twin.k2).c_str(), twin.mu);
    printRow("winner named by the same search in double", "(3, -1)", buf);
    std::snprintf(buf, sizeof buf, "(%d, %d), mu %.4f", all.k1, all.k2, all.mu);
    printRow("exhaustive winner, orders <= 48", "(3, -1)", buf);
    std::snprintf(buf, sizeof buf, "(%d, %d), mu %.4f: %s", floorScan.k1, floorScan.k2,
                  floorScan.mu, floorScan.mu < lower::kFringeMerit ? "fringe" : "no fringe");
    printRow("|k_i| <= 2 scan", "reads blank", buf);
    std::snprintf(buf, sizeof buf, "%.4f", oracleMerit(3, -1, g1, g2) / 3);
    printRow("eta_(3,-1)", "-", buf);
    const bool named = sameCharacter(kernel.k1, kernel.k2, 3, -1) &&
                       sameCharacter(twin.k1, twin.k2, 3, -1) && kernel.mu < lower::kFringeMerit;
    return verdict(named && floorScan.mu >= lower::kFringeMerit,
                   "the kernel should name (3, -1) as a fringe the order-two scan misses");
}
