// The ternary beat of spec §4.4: three ring families whose pitches keep 2 / s3 = 1 / s1 +
// 1 / s2 (s3 the harmonic mean) make the zero-sum character (1, 1, -2) slow wherever the
// three gradients point alike, a fringe that belongs to no pair. Over a grid of points, the
// shipped search over the stack must name (1, 1, -2) where an independent prediction does:
// the ternary merit restated here, below the exhaustive minimum (orders <= 48) of every pair.
// The same rings with s3 moved off the harmonic mean are the control.
#include "experiments/Harness.h"

#include <cmath>
#include <cstdio>

using namespace moire;
using namespace moire::exp;

namespace {

// Rings of pitch s about c: the index |p - c| / s, its gradient the unit radial over s.
G ringGradient(double px, double py, double cx, double cy, double s) {
    const double r = std::max(std::hypot(px - cx, py - cy), 1e-9);
    return {(px - cx) / (r * s), (py - cy) / (r * s)};
}

// (1, 1, -2)'s merit, written out again: |g1 + g2 - 2 g3| over half |g1 + g2 + 2 g3|, times 2.
double oracleTernary(G g1, G g2, G g3) {
    const double bx = g1.x + g2.x - 2 * g3.x, by = g1.y + g2.y - 2 * g3.y;
    const double cx = g1.x + g2.x + 2 * g3.x, cy = g1.y + g2.y + 2 * g3.y;
    return 2 * std::max(std::hypot(bx, by) / (0.5 * std::hypot(cx, cy)), 1e-3);
}

struct Tally {
    int points = 0, predicted = 0, named = 0, agree = 0;
    double namedMu = 0.0; // summed over the points where (1, 1, -2) is named
};

Tally survey(double s1, double s2, double s3, int grid) {
    // Centres 160 units apart on a line, the third family's midway; a 480-unit frame. (The
    // share of the frame the ternary holds depends on the spacing, which the spec leaves
    // open: 98% at 40 apart, 60% at 160, 50% at 180.)
    const double c1x = -80, c2x = 80, c3x = 0, cy = 0, half = 240;
    Tally t;
    for (int iy = 0; iy < grid; ++iy)
        for (int ix = 0; ix < grid; ++ix) {
            const double px = -half + (ix + 0.5) * 2 * half / grid;
            const double py = -half + (iy + 0.5) * 2 * half / grid;
            const G g1 = ringGradient(px, py, c1x, cy, s1);
            const G g2 = ringGradient(px, py, c2x, cy, s2);
            const G g3 = ringGradient(px, py, c3x, cy, s3);
            const double pairs =
                std::min({exhaustiveMinimum(g1, g2, 48).mu, exhaustiveMinimum(g1, g3, 48).mu,
                          exhaustiveMinimum(g2, g3, 48).mu});
            const double ternary = oracleTernary(g1, g2, g3);
            const bool predicted = ternary < pairs && ternary < lower::kFringeMerit;
            const lower::Grad<double> g[3] = {g1, g2, g3};
            const lower::StackCharacterT<double> got = lower::bestStackCharacter<double>(g);
            const int sign = got.k[0] < 0 ? -1 : 1;
            const bool named = sign * got.k[0] == 1 && sign * got.k[1] == 1 &&
                               sign * got.k[2] == -2 && got.mu < lower::kFringeMerit;
            ++t.points;
            t.predicted += predicted;
            t.named += named;
            if (named) t.namedMu += got.mu;
            t.agree += predicted == named;
        }
    return t;
}

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseOptions(argc, argv, "the ternary beat of spec §4.4");
    const int grid = opt.quick ? 24 : 96;
    const double s1 = 7, s2 = 11, harmonic = 2 / (1 / s1 + 1 / s2); // 9.6
    const Tally on = survey(s1, s2, harmonic, grid);
    const Tally off = survey(s1, s2, harmonic * 1.1, grid);
    // The kernel itself (IR on the interpreter) at one point of the predicted region.
    const G p1 = ringGradient(230, 30, -80, 0, s1), p2 = ringGradient(230, 30, 80, 0, s2),
            p3 = ringGradient(230, 30, 0, 0, harmonic);
    const Shipped kernel = stackKernel({p1, p2, p3});
    char buf[96];
    printTitle("ternary: rings of pitches 7 and 11 and their harmonic mean 8.56 between them, "
               "outer centres 160 apart");
    std::snprintf(buf, sizeof buf, "%s of %d points", percent(double(on.named) / on.points).c_str(),
                  on.points);
    printRow("frame where the shipped search names (1, 1, -2)", "over half the frame", buf);
    std::snprintf(buf, sizeof buf, "%s", percent(double(on.predicted) / on.points).c_str());
    printRow("frame where the prediction puts it", "-", buf);
    std::snprintf(buf, sizeof buf, "%s", percent(double(on.agree) / on.points).c_str());
    printRow("points where search and prediction agree", "-", buf);
    std::snprintf(buf, sizeof buf, "%.4f", on.named ? on.namedMu / on.named : 0.0);
    printRow("mean min mu where it is named", "-", buf);
    std::snprintf(buf, sizeof buf, "%s named, %s predicted, mean mu %.4f",
                  percent(double(off.named) / off.points).c_str(),
                  percent(double(off.predicted) / off.points).c_str(),
                  off.named ? off.namedMu / off.named : 0.0);
    printRow("control: third pitch 1.1 x the harmonic mean", "-", buf);
    printRow("kernel (IR, interpreter) at (230, 30)", "(1, 1, -2)",
             characterName(kernel.k1, kernel.k2, kernel.k3, true));
    const bool ok = on.agree >= on.points * 99 / 100 && on.named * 5 > on.points &&
                    on.namedMu * off.named < off.namedMu * on.named &&
                    characterName(kernel.k1, kernel.k2, kernel.k3, true) == "(1, 1, -2)";
    return verdict(ok, "(1, 1, -2) should win where predicted (99% of points) over a fifth of "
                       "the frame, broader there than off the harmonic mean");
}
