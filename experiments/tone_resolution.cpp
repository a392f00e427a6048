// Tone at any resolution (docs/filtering.md, issue: the preview lies about the print): every
// example rendered at 1200 x 800 against the same frame rendered at 7200 x 4800 and
// box-downsampled 6 x 6 to 1200 x 800, point-sampled and with the mean filter. The RMSE of the
// straight RGB (each channel in [0, 1]) says how far a preview's tone is from a print's. A box
// filter composes exactly (the mean of 36 box-filtered small pixels is the box filter of the
// big pixel), so under the mean the two agree up to what the filter assumes (an index linear
// across the pixel, the members' strokes across their normals for families without an index,
// two layers' strokes straight across a pixel where they meet in it); the point rule's floor
// holds strokes at 2.3 pixels whatever the pixel, so its preview is darker than its print.
// Goal: RMSE at most 0.02 under the mean, for each layer alone and for the whole picture. A
// last column holds the mean's preview against the exact field (exactError), which does not
// share the filter's maths.
#include "compiler/backend/llvm/LlvmJit.h"
#include "experiments/FrameMeans.h"
#include "experiments/Harness.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::exp;

namespace {

constexpr int kFactor = 6; // the large frame is 6 x 6 small pixels to each preview pixel
constexpr double kGoal = 0.02;

// Quick: six examples (phase families, a lattice, a walking family, encoded fields) at half the
// size (600 x 400 against 3600 x 2400), where their members are twice as fine against the
// preview's pixels.
const char* const kQuickExamples[] = {"counter_spirals", "drifting_walks", "hexagonal_twist",
                                      "radial_fans",     "two_fields",     "two_rings"};

[[noreturn]] void fail(const std::string& what) {
    std::fprintf(stderr, "tone_resolution: error: %s\n", what.c_str());
    std::exit(2);
}

struct Row {
    std::string name;
    double error[2]; // point, mean: the whole picture's RGB
    double alone[2]; // point, mean: the worst of its layers alone (their ink, the alpha)
    double exact;    // the mean's whole picture against the exact field (exactError)
    double seconds;
};

// The preview's error against the downsampled print: one compile of the scene, rendered twice.
double previewError(const std::string& file, const std::string& text, LlvmJitBackend& jit,
                    const CompileOptions& options, int width, int height, int c0, int count) {
    CompileResult r = compileScene(file, text, options);
    if (!r.program) fail(r.diagnostics);
    auto kernel = jit.compile(r.program->kernel);
    return rmse(frameMeans(*r.program, *kernel, width, height, 1, c0, count),
                frameMeans(*r.program, *kernel, width, height, kFactor, c0, count));
}

// The preview under the mean filter against the exact field: the frame rendered kFactor times
// larger by the point rule with no floor (each stroke as written, its antialias band a sixth of
// a preview pixel) and box-downsampled. Independent of the filter's own maths, so it says what
// the comparison with the mean's own print cannot: how far the filter's assumptions hold.
double exactError(const std::string& file, const std::string& text, LlvmJitBackend& jit, int width,
                  int height) {
    CompileResult mean = compileScene(file, text, {.filter = sema::FilterMode::Mean});
    CompileResult exact =
        compileScene(file, text, {.filter = sema::FilterMode::Point, .strokeFloor = false});
    if (!mean.program) fail(mean.diagnostics);
    if (!exact.program) fail(exact.diagnostics);
    auto meanKernel = jit.compile(mean.program->kernel);
    auto exactKernel = jit.compile(exact.program->kernel);
    return rmse(frameMeans(*mean.program, *meanKernel, width, height, 1, 0, 3),
                frameMeans(*exact.program, *exactKernel, width, height, kFactor, 0, 3));
}

Row measure(const std::filesystem::path& file, LlvmJitBackend& jit, int width, int height) {
    std::ifstream in(file);
    std::stringstream text;
    text << in.rdbuf();
    Row row{file.stem().string(), {0, 0}, {0, 0}, 0, 0};
    const auto start = std::chrono::steady_clock::now();
    CompileResult parsed = compileScene(file.string(), text.str());
    if (!parsed.program) fail(parsed.diagnostics);
    const int layers = int(parsed.program->checked.layers.size());
    const sema::FilterMode filters[2] = {sema::FilterMode::Point, sema::FilterMode::Mean};
    for (int f = 0; f < 2; ++f) {
        // The whole picture's colour; then each layer alone on a transparent paper (a print's
        // separation), whose ink is its alpha: laid over one another, layers that cross within a
        // pixel share ink that each one's own mean cannot know of (docs/filtering.md).
        row.error[f] = previewError(file.string(), text.str(), jit, {.filter = filters[f]}, width,
                                    height, 0, 3);
        for (int l = 0; l < layers && layers > 1; ++l)
            row.alone[f] =
                std::max(row.alone[f], previewError(file.string(), text.str(), jit,
                                                    {.filter = filters[f], .separateLayer = l},
                                                    width, height, 3, 1));
        if (layers == 1) row.alone[f] = row.error[f];
    }
    row.exact = exactError(file.string(), text.str(), jit, width, height);
    row.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return row;
}

} // namespace

int main(int argc, char** argv) {
    const Options opt = parseOptions(
        argc, argv,
        "every example at 1200 x 800 against 7200 x 4800 box-downsampled: RMSE, point and mean");
    const int width = opt.quick ? 600 : 1200, height = opt.quick ? 400 : 800;
    const std::filesystem::path examples = std::filesystem::path(MOIRE_SOURCE_DIR) / "examples";
    std::vector<std::filesystem::path> files;
    if (opt.quick)
        for (const char* name : kQuickExamples)
            files.push_back(examples / (std::string(name) + ".moire"));
    else
        for (const auto& e : std::filesystem::directory_iterator(examples))
            if (e.path().extension() == ".moire") files.push_back(e.path());
    std::sort(files.begin(), files.end());

    std::printf("tone_resolution: %d x %d against %d x %d box-downsampled %d x %d, RMSE of "
                "straight RGB in [0, 1]\n\n",
                width, height, width * kFactor, height * kFactor, kFactor, kFactor);
    std::printf("  %-22s %21s   %21s   %10s %8s\n", "", "whole picture (RGB)",
                "worst layer alone (ink)", "mean vs", "");
    std::printf("  %-22s %10s %10s   %10s %10s   %10s %8s\n", "example", "point", "mean", "point",
                "mean", "exact", "seconds");
    LlvmJitBackend jit(LlvmJitBackend::Options{});
    double worst[2] = {0, 0}, worstAlone[2] = {0, 0};
    double worstExact = 0;
    std::string worstName, worstAloneName, worstExactName, why;
    for (const auto& file : files) {
        const Row row = measure(file, jit, width, height);
        std::printf("  %-22s %10.4f %10.4f   %10.4f %10.4f   %10.4f %8.1f\n", row.name.c_str(),
                    row.error[0], row.error[1], row.alone[0], row.alone[1], row.exact, row.seconds);
        std::fflush(stdout);
        if (row.error[1] > worst[1]) worstName = row.name;
        if (row.alone[1] > kGoal)
            why += " " + row.name + ": a layer's own tone differs by more than 0.02 RMSE;";
        if (row.error[1] > kGoal)
            why += " " + row.name + ": the picture's tone differs by more than 0.02 RMSE;";
        if (row.exact > kGoal)
            why += " " + row.name + ": the picture differs from its exact field by more than 0.02;";
        if (row.alone[1] > worstAlone[1]) worstAloneName = row.name;
        if (row.exact > worstExact) {
            worstExact = row.exact;
            worstExactName = row.name;
        }
        for (int f = 0; f < 2; ++f) {
            worst[f] = std::max(worst[f], row.error[f]);
            worstAlone[f] = std::max(worstAlone[f], row.alone[f]);
        }
        if (!(row.error[1] <= row.error[0])) why += " " + row.name + ": the mean's tone is worse;";
    }
    std::printf("\n");
    printTitle("worst RMSE over the examples, preview against the downsampled print");
    printRow("whole picture, point sampling (the stroke floor)", "0.158 (one example)",
             std::to_string(worst[0]));
    printRow("whole picture, the mean filter", "at most 0.02",
             std::to_string(worst[1]) + " (" + worstName + ")");
    printRow("each layer alone, point sampling", "-", std::to_string(worstAlone[0]));
    printRow("each layer alone, the mean filter", "at most 0.02",
             std::to_string(worstAlone[1]) + " (" + worstAloneName + ")");
    printRow("whole picture, the mean against the exact field", "at most 0.02",
             std::to_string(worstExact) + " (" + worstExactName + ")");
    const bool ok = why.empty();
    return verdict(ok, why);
}
