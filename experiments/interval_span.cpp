// Fig. 16 and §9.6 of the spec: where Theorem 4's interval is wider than the budget, and
// what the strided scan loses there.
//
//   build/bin/experiments/interval_span [--quick]
//
// 1. A broad sweep of settings (five shapes x spacings x offsets and their directions x
//    turns x zooms), each sampled at quasi-random points of a 1200 x 800 frame by the shipped
//    kernel (interpreter), which also outputs the interval it computed (n_lo, n_hi). Per
//    setting: the 90th-percentile span n_hi - n_lo + 1 (capped at 2^16 like the scan), and
//    the ink of the solved field, a lower bound on the exact field's (a partial scan can only
//    miss members). Binned by span, with the share within the budget B = 1024.
// 2. The strided band: settings past the budget whose solver actually scans (a turn, or a
//    polygon faster than its spacing; the closed forms of §7.5 do not stride). A stratified
//    sample (the legible ones, under 50% ink, and a slice of the saturated ones) is solved
//    again with the budget raised to 131072, which walks the whole capped span at stride 1,
//    and the ink lost by the shipped budget is measured against that.
#include "compiler/lower/WalkingFamily.h"
#include "experiments/Harness.h"
#include "experiments/WalkingSettings.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fmt/format.h>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;
namespace ref = moire::reference;

namespace {

constexpr double kSpanCap = 65536; // lower::kWalkSpanCap
constexpr double kLegible = 0.5;   // §9.6's stricter cut: the strided band is darker

struct Measured {
    double span90 = 0, ink = 0;
    bool strided = false;
};

double median(std::vector<double> v) {
    if (v.empty()) return NAN;
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseOptions(argc, argv, "Fig. 16 and §9.6 of the spec");
    const int stride = opt.quick ? 53 : 1;
    const int points = opt.quick ? 32 : 64;
    const std::vector<std::array<double, 2>> pixels = haltonPixels(points, kFrameW, kFrameH);
    const std::vector<WalkSetting> all = intervalGrid();

    std::vector<std::unique_ptr<WalkingKernel>> shipped, raised;
    lower::WalkingVariant wide;
    wide.budget = 131072;
    for (int shape = 0; shape < 5; ++shape) {
        shipped.push_back(std::make_unique<WalkingKernel>(shape, lower::WalkingVariant{}));
        raised.push_back(std::make_unique<WalkingKernel>(shape, wide));
    }

    // Part 1: span and ink per setting.
    std::vector<WalkSetting> settings;
    std::vector<Measured> got;
    long disagreements = 0, compared = 0;
    std::vector<double> spans(points);
    for (size_t k = 0; k < all.size(); k += stride) {
        const WalkSetting& s = all[k];
        WalkingKernel& kernel = *shipped[s.shape];
        kernel.set(s);
        const ref::Walking w = walkingOf(s);
        Measured m;
        for (int i = 0; i < points; ++i) {
            const Solved v = kernel.at(pixels[i][0], pixels[i][1]);
            spans[i] = std::min(kSpanCap, std::max(0.0, v.nHi - v.nLo) + 1);
            m.ink += coverageOf(v.distance, kernel.band());
            // The kernel's interval against Theorem 4 written out independently.
            const auto [wx, wy] = kernel.world(pixels[i][0], pixels[i][1]);
            const double mine = std::min(kSpanCap, intervalSpan(w, wx, wy, kernel.guard()));
            ++compared;
            disagreements += std::fabs(mine - spans[i]) > 1 + 1e-9 * mine;
        }
        m.ink /= points;
        std::sort(spans.begin(), spans.end());
        m.span90 = spans[static_cast<size_t>(std::ceil(0.9 * points)) - 1];
        const double drift = ref::drift(w);
        const bool closedForm =
            s.turnDeg == 0 && (w.facets == 0 || drift <= s.spacing + lower::kWalkMarginal);
        m.strided = m.span90 > lower::kWalkBudget && !closedForm;
        settings.push_back(s);
        got.push_back(m);
    }

    // Fig. 16's bins: powers of two of the 90th-percentile span, the cap its own bin.
    printTitle(fmt::format("interval_span: Fig. 16, {} settings at {} points each{}",
                           settings.size(), points, opt.quick ? " (quick: every 53rd)" : ""));
    std::printf("  %-22s %9s %11s %9s\n", "90th-pct span", "settings", "median ink", "least");
    std::vector<double> within, past;
    int cap = 0, capMarginal = 0, legiblePast = 0;
    double worstRatio = 1;
    int farFromMarginal = 0;   // past the budget with m not within 4.2x of s
    double densestSpacing = 0; // the widest spacing among those, in pixels
    std::vector<double> capInk;
    for (int b = 0; b <= 17; ++b) {
        std::vector<double> inks;
        for (size_t i = 0; i < got.size(); ++i) {
            const double sp = got[i].span90;
            const int bin = sp >= kSpanCap ? 17 : static_cast<int>(std::floor(std::log2(sp)));
            if (bin == b) inks.push_back(got[i].ink);
        }
        if (inks.empty()) continue;
        const std::string label = b == 17 ? std::string("at the cap 65536")
                                          : fmt::format("{} .. {}", 1 << b, (2 << b) - 1);
        std::printf("  %-22s %9zu %11.2f %9.2f%s\n", label.c_str(), inks.size(), median(inks),
                    *std::min_element(inks.begin(), inks.end()),
                    (1 << b) > lower::kWalkBudget ? "  past the budget" : "");
    }
    for (size_t i = 0; i < got.size(); ++i) {
        const ref::Walking w = walkingOf(settings[i]);
        const double ratio = ref::drift(w) / settings[i].spacing;
        if (got[i].span90 <= lower::kWalkBudget) {
            within.push_back(got[i].ink);
            continue;
        }
        past.push_back(got[i].ink);
        const double off = ratio > 0 ? std::max(ratio, 1 / ratio) : INFINITY;
        worstRatio = std::max(worstRatio, off);
        if (off > 4.2) {
            ++farFromMarginal;
            // The scene's frame is the image's, so a world unit is `zoom` pixels.
            densestSpacing = std::max(densestSpacing, settings[i].spacing * settings[i].zoom);
        }
        legiblePast += got[i].ink < kLegible;
        if (got[i].span90 >= kSpanCap) {
            ++cap;
            capInk.push_back(got[i].ink);
            capMarginal += std::fabs(ratio - 1) <= 0.05;
        }
    }
    const double n = static_cast<double>(got.size());
    printRow("settings", "55,692", fmt::format("{}", got.size()));
    printRow("within the budget B = 1024", "45,774 (82%)",
             fmt::format("{} ({})", within.size(), percent(within.size() / n)));
    printRow("past the budget", "9,918", fmt::format("{}", past.size()));
    printRow("past the budget: median ink", "0.89", fmt::format("{:.2f}", median(past)));
    printRow("within the budget: median ink", "-", fmt::format("{:.2f}", median(within)));
    printRow("past the budget: widest m/s (or s/m)", "4.2", fmt::format("{:.2f}", worstRatio));
    printRow("  of them with m not within 4.2x of s", "0", fmt::format("{}", farFromMarginal));
    printRow("  their widest spacing, in pixels", "-", fmt::format("{:.2f}", densestSpacing));
    printRow("past the budget and legible (< 50% ink)", "1,472 (2.6%)",
             fmt::format("{} ({})", legiblePast, percent(legiblePast / n)));
    printRow("at the span cap", "1,170", fmt::format("{}", cap));
    printRow("at the cap: m within 5% of s", "1,155", fmt::format("{}", capMarginal));
    printRow("at the cap: median ink, least", "0.69, 0.07",
             capInk.empty() ? "-"
                            : fmt::format("{:.2f}, {:.2f}", median(capInk),
                                          *std::min_element(capInk.begin(), capInk.end())));
    printRow("kernel's interval off Theorem 4 (double) by > 1", "-",
             fmt::format("{} of {} points", disagreements, compared));

    // Part 2: the strided band against the budget raised to 131072, on a stratified sample.
    std::vector<size_t> legibleBand, solidBand;
    for (size_t i = 0; i < got.size(); ++i)
        if (got[i].strided) (got[i].ink < kLegible ? legibleBand : solidBand).push_back(i);
    const size_t wantLegible = opt.quick ? 6 : 300, wantSolid = opt.quick ? 6 : 240;
    std::vector<size_t> sample;
    for (const auto* band : {&legibleBand, &solidBand}) {
        const size_t want = band == &legibleBand ? wantLegible : wantSolid;
        const size_t step =
            std::max<size_t>(1, (band->size() + want - 1) / std::max<size_t>(1, want));
        for (size_t j = 0; j < band->size(); j += step) sample.push_back((*band)[j]);
    }
    int losing = 0, sampledLegible = 0, invented = 0;
    double meanLoss = 0, worstLoss = 0, worstInk = 0, worstLegible = 0;
    for (size_t i : sample) {
        const WalkSetting& s = settings[i];
        WalkingKernel& a = *shipped[s.shape];
        WalkingKernel& b = *raised[s.shape];
        a.set(s);
        b.set(s);
        double inkA = 0, inkB = 0;
        int lost = 0;
        for (int p = 0; p < points; ++p) {
            const double ca = coverageOf(a.at(pixels[p][0], pixels[p][1]).distance, a.band());
            const double cb = coverageOf(b.at(pixels[p][0], pixels[p][1]).distance, b.band());
            inkA += ca;
            inkB += cb;
            lost += ca < cb - 0.5;
            invented += ca > cb + 1e-6;
        }
        const double loss = inkB > 0 ? std::max(0.0, 1 - inkA / inkB) : 0.0;
        losing += double(lost) / points > 0.002;
        meanLoss += loss;
        if (loss > worstLoss) worstLoss = loss, worstInk = inkB / points;
        if (inkB / points < kLegible) {
            ++sampledLegible;
            worstLegible = std::max(worstLegible, loss);
        }
    }
    if (!sample.empty()) meanLoss /= static_cast<double>(sample.size());
    printRow("strided band: legible, saturated settings", "-",
             fmt::format("{}, {}", legibleBand.size(), solidBand.size()));
    printRow("strided band: settings sampled", "534", fmt::format("{}", sample.size()));
    printRow("  that lose ink (B = 1024 against 131072)", "217", fmt::format("{}", losing));
    printRow("  mean ink lost", "4.6%", percent(meanLoss));
    printRow("  worst ink lost (its exact ink)", "48.8% (1.00)",
             fmt::format("{} ({:.2f})", percent(worstLoss), worstInk));
    printRow("  legible ones sampled, worst ink lost", "298, 28.7%",
             fmt::format("{}, {}", sampledLegible, percent(worstLegible)));
    printRow("  points where B = 1024 drew more ink", "0", fmt::format("{}", invented));

    const bool ok = disagreements == 0 && invented == 0 && !past.empty() &&
                    median(past) > median(within) && !sample.empty();
    return verdict(ok, "the kernel's interval must be Theorem 4's, the strided scan must never "
                       "draw ink the full scan does not, and ink must rise past the budget");
}
