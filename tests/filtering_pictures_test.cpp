// The pictures of docs/filtering.md's "Before and after" against the scenes they show: every
// scene under docs/filtering/ has its two pictures (--filter point and --filter mean) on the
// page, and each picture is what moire draws of its scene today, rendered again here as
// scripts/render-filtering.sh renders it; the hairline's print (6 times larger, each 6x6
// block averaged) is averaged here on its own, not by the script's ffmpeg.
#include "runtime/output/ImageIO.h"
#include "tests/support/DocImages.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <set>

using namespace moire;
namespace fs = std::filesystem;

namespace {

constexpr int kWidth = 480, kHeight = 320, kPrintFactor = 6;

std::set<std::string> scenes() {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(test::sourcePath("docs/filtering")))
        if (e.path().extension() == ".moire") out.insert(e.path().stem().string());
    return out;
}

// Each k x k block of `big` averaged into one pixel (sRGB values, as ffmpeg's area scaler
// averages them), every channel.
Image boxDownsample(const Image& big, int k) {
    Image out(big.width / k, big.height / k, big.channels);
    for (int y = 0; y < out.height; ++y)
        for (int x = 0; x < out.width; ++x)
            for (int c = 0; c < big.channels; ++c) {
                double sum = 0.0;
                for (int j = 0; j < k; ++j)
                    for (int i = 0; i < k; ++i) sum += big.at(x * k + i, y * k + j, c);
                out.pixels[(static_cast<size_t>(y) * out.width + x) * out.channels + c] =
                    static_cast<float>(sum / (k * k));
            }
    return out;
}

// The flags a scene's comment asks it to be drawn with, `// render: FLAGS` (a morph half-way
// through its change: `--time 0.5`), as scripts/render-filtering.sh reads them; "" for none.
std::string renderFlags(const std::string& name) {
    const std::string text =
        "\n" + test::readFile(test::sourcePath("docs/filtering/" + name + ".moire"));
    const std::string mark = "// render: ";
    const size_t at = text.find("\n" + mark);
    if (at == std::string::npos) return "";
    const size_t from = at + 1 + mark.size();
    return " " + text.substr(from, text.find('\n', from) - from);
}

} // namespace

TEST_CASE("filtering pictures: every scene has both pictures, and the page shows them") {
    const std::string page = test::readFile(test::sourcePath("docs/filtering.md"));
    REQUIRE(scenes().size() >= 4);
    for (const std::string& name : scenes())
        for (const char* filter : {"point", "mean"}) {
            const std::string picture = "images/filtering-" + name + "-" + filter + ".png";
            CAPTURE(picture);
            CHECK_MESSAGE(fs::exists(test::sourcePath("docs/" + picture)),
                          "missing: run bash scripts/render-filtering.sh");
            CHECK_MESSAGE(page.find("](" + picture + ")") != std::string::npos,
                          "docs/filtering.md does not show it");
        }
    CHECK(page.find("](images/filtering-hairline-print.png)") != std::string::npos);
}

TEST_CASE("filtering pictures: each is what its scene draws today") {
    test::TempDir dir("filtering-pictures");
    for (const std::string& name : scenes())
        for (const char* filter : {"point", "mean"}) {
            CAPTURE(name);
            CAPTURE(filter);
            Image fresh = test::renderWithMoire(
                "docs/filtering/" + name + ".moire --size " + std::to_string(kWidth) + "x" +
                    std::to_string(kHeight) + " --filter " + filter + renderFlags(name),
                dir, name + "-" + filter);
            test::checkSameAsStored(
                fresh, test::sourcePath("docs/images/filtering-" + name + "-" + filter + ".png"));
        }
    // The print: the frame 6 times larger, each 6x6 block averaged.
    Image big = test::renderWithMoire("docs/filtering/hairline.moire --size " +
                                          std::to_string(kWidth * kPrintFactor) + "x" +
                                          std::to_string(kHeight * kPrintFactor),
                                      dir, "print");
    test::checkSameAsStored(boxDownsample(big, kPrintFactor),
                            test::sourcePath("docs/images/filtering-hairline-print.png"));
}
