// The mean filter on scenes nobody chose (docs/filtering.md, "How it is checked"): random
// scenes of one or two layers (every phase family, the lattices' points and edges, the pencil,
// fields encoded into a phase, morphs between phase families), each a small frame at a random
// zoom, turn and centre, drawn one sample a pixel under the mean filter against its exact field
// (the stroke as written, no floor, 64 x 64 samples a pixel, box-downsampled). The curated
// cases of tests/filter_test.cpp hold each regime the filter reads; this says how far those
// readings hold where members, strokes and layers fall as they may. Walking families are left
// out: past the search budget their exact field is not exact (walking_mean measures them).
// Prints the RMSE's spread over the scenes, one-layer and two-layer apart, and the five worst
// scenes of each whole. Goal: every pixel a number within [0, 1], and the mean RMSE at most 0.01.
#include "compiler/backend/llvm/LlvmJit.h"
#include "experiments/FrameMeans.h"
#include "experiments/Harness.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;

namespace {

constexpr int kWidth = 48, kHeight = 36;
constexpr int kExactSamples = 64;
constexpr double kGoal = 0.01;

struct Generator {
    std::mt19937 rng;
    double uniform(double lo, double hi) {
        return std::uniform_real_distribution<double>(lo, hi)(rng);
    }
    double logUniform(double lo, double hi) {
        return std::exp(uniform(std::log(lo), std::log(hi)));
    }
    bool chance(double p) { return uniform(0, 1) < p; }
    template <class T>
    const T& pick(const std::vector<T>& from) {
        return from[size_t(uniform(0, double(from.size()) - 1e-9))];
    }
};

std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.4g", v);
    return buf;
}

// A family and its own properties.
std::string family(Generator& g) {
    const std::vector<std::string> plain = {"circles", "squares", "triangles", "hexagons",
                                            "hyperbola"};
    switch (int(g.uniform(0, 9))) {
    case 0:
        return "lines; angle = " + number(g.uniform(0, 90)) + "deg";
    case 1:
        return "ngon; sides = " + number(std::round(g.uniform(5, 9)));
    case 2:
        return "wave; amplitude = " + number(g.uniform(0, 8));
    case 3:
        return "parabola; bend = " + number(g.uniform(0.01, 0.3));
    case 4:
        return "spiral; arms = " + number(std::round(g.uniform(-3, 3)));
    case 5:
        return "pencil; lines = " + number(std::round(g.uniform(20, 200)));
    case 6:
        return g.pick(
                   std::vector<std::string>{"square_lattice", "triangle_lattice", "hex_lattice"}) +
               "; edges = " + (g.chance(0.5) ? "1" : "0");
    case 7: {
        const std::vector<std::string> phases = {"circles", "squares", "hexagons", "lines"};
        return "morph(change, " + g.pick(phases) + ", " + g.pick(phases) + "); morph_time = 1";
    }
    default:
        return g.pick(plain);
    }
}

// A scene of one or two layers; its strokes at least 1.5 of the reference's samples wide, past
// the exact field's antialias band (0.7 of a sample), which inflates a thinner stroke's ink.
std::string scene(Generator& g, int& layers) {
    const double zoom = g.logUniform(0.3, 4);
    std::string text = "scene { size = (" + std::to_string(kWidth) + ", " +
                       std::to_string(kHeight) + ") }\ncamera { zoom = " + number(zoom) +
                       "; rotation = " + number(g.uniform(0, 30)) + "deg; center = (" +
                       number(g.uniform(-40, 40)) + ", " + number(g.uniform(-40, 40)) +
                       ") }\ntiming change { period = 2 }\n";
    layers = g.chance(0.4) ? 1 : 2;
    for (int l = 0; l < layers; ++l) {
        const std::string f = family(g);
        const double spacing = g.logUniform(0.2, 12);
        const double stroke = std::max(spacing * g.uniform(0.05, 0.6), 1.5 / zoom / kExactSamples);
        text += "layer l" + std::to_string(l) + " { family = " + f +
                "; spacing = " + number(spacing) + "; stroke = " + number(stroke) +
                "; rotation = " + number(g.uniform(0, 90)) + "deg; origin = (" +
                number(g.uniform(-30, 30)) + ", " + number(g.uniform(-30, 30)) + ")";
        const bool phase = f.find("lattice") == std::string::npos &&
                           f.find("pencil") == std::string::npos &&
                           f.find("morph") == std::string::npos;
        if (phase && g.chance(0.15))
            text += "; field = " + g.pick(std::vector<std::string>{"swirl", "ripple", "saddle"});
        text += " }\n";
    }
    return text;
}

struct Result {
    std::string text;
    int layers;
    double rmse;
    bool numbers; // every pixel a number within [0, 1]
};

Result measure(LlvmJitBackend& jit, const std::string& text, int layers, double time) {
    auto compile = [&](const CompileOptions& options) {
        CompileResult r = compileScene("random.moire", text, options);
        if (!r.program) {
            std::fprintf(stderr, "filter_random: error: a generated scene did not compile:\n%s\n%s",
                         text.c_str(), r.diagnostics.c_str());
            std::exit(2);
        }
        return std::move(r.program);
    };
    auto mean = compile({.filter = sema::FilterMode::Mean});
    auto exact = compile({.filter = sema::FilterMode::Point, .strokeFloor = false});
    const std::vector<double> got =
        frameMeans(*mean, *jit.compile(mean->kernel), kWidth, kHeight, 1, 0, 3, time);
    const std::vector<double> want =
        frameMeans(*exact, *jit.compile(exact->kernel), kWidth, kHeight, kExactSamples, 0, 3, time);
    bool numbers = true;
    for (double v : got) numbers &= std::isfinite(v) && v >= -1e-6 && v <= 1 + 1e-6;
    return {text, layers, rmse(got, want), numbers};
}

struct Spread {
    double mean = 0, median = 0, p90 = 0, worst = 0;
    int count = 0;
};
Spread spreadOf(std::vector<double> v) {
    Spread s;
    s.count = int(v.size());
    if (v.empty()) return s;
    std::sort(v.begin(), v.end());
    for (double x : v) s.mean += x / double(v.size());
    s.median = v[v.size() / 2];
    s.p90 = v[std::min(v.size() - 1, v.size() * 9 / 10)];
    s.worst = v.back();
    return s;
}

} // namespace

int main(int argc, char** argv) {
    const Options options =
        parseOptions(argc, argv, "the mean filter on random scenes against their exact field");
    const int count = options.quick ? 24 : 300;
    Generator g{std::mt19937(20261201)};
    LlvmJitBackend jit;
    std::vector<Result> results;
    for (int i = 0; i < count; ++i) {
        int layers = 0;
        const std::string text = scene(g, layers);
        results.push_back(measure(jit, text, layers, g.uniform(0, 2)));
    }
    std::vector<double> one, two, all;
    bool numbers = true;
    for (const Result& r : results) {
        (r.layers == 1 ? one : two).push_back(r.rmse);
        all.push_back(r.rmse);
        numbers &= r.numbers;
    }
    std::printf("filter_random: %d random scenes of %d x %d pixels, the mean filter against the "
                "exact field at %d x %d samples a pixel; RMSE\n",
                count, kWidth, kHeight, kExactSamples, kExactSamples);
    std::printf("  %-12s %6s %9s %9s %9s %9s\n", "scenes", "count", "mean", "median", "90%",
                "worst");
    for (const auto& [name, v] :
         {std::pair{"one layer", one}, std::pair{"two layers", two}, std::pair{"all", all}}) {
        const Spread s = spreadOf(v);
        std::printf("  %-12s %6d %9.4f %9.4f %9.4f %9.4f\n", name, s.count, s.mean, s.median, s.p90,
                    s.worst);
    }
    std::sort(results.begin(), results.end(),
              [](const Result& a, const Result& b) { return a.rmse > b.rmse; });
    for (int layers : {1, 2}) {
        std::printf("\nthe worst scenes of %s:\n", layers == 1 ? "one layer" : "two layers");
        int shown = 0;
        for (const Result& r : results)
            if (r.layers == layers && shown++ < (options.quick ? 2 : 5))
                std::printf("RMSE %.4f\n%s\n", r.rmse, r.text.c_str());
    }
    const Spread s = spreadOf(all);
    if (!numbers) return verdict(false, "a pixel's value is not a number within [0, 1]");
    return verdict(s.mean <= kGoal, "mean RMSE " + number(s.mean) + " over " + number(kGoal));
}
