// docs/tutorial.md against its files and against moire: every fenced `moire` block on the
// page is the whole of the step file it names (docs/tutorial/NN-*.moire), in order, and every
// step renders with the real binary, draws some ink without drowning the paper, and changes
// the picture from the step before.
#include "tests/support/DocImages.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>

using namespace moire;
namespace fs = std::filesystem;

namespace {

std::vector<std::string> stepFiles() {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(test::sourcePath("docs/tutorial")))
        if (e.path().extension() == ".moire")
            out.push_back("docs/tutorial/" + e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
}

struct Block {
    std::string named; // the file named in the line that introduces the block
    std::string text;
};

// The page's ```moire blocks, each with the `docs/tutorial/...` file named on the nearest
// non-blank line above it.
std::vector<Block> moireBlocks(const std::string& page) {
    std::vector<std::string> ls = test::lines(page);
    std::vector<Block> out;
    for (size_t i = 0; i < ls.size(); ++i) {
        if (ls[i] != "```moire") continue;
        Block b;
        for (size_t j = i; j-- > 0;)
            if (!ls[j].empty()) {
                size_t a = ls[j].find("`docs/tutorial/"), z = ls[j].find(".moire`");
                if (a != std::string::npos && z != std::string::npos && z > a)
                    b.named = ls[j].substr(a + 1, z + 6 - a - 1);
                break;
            }
        size_t k = i + 1;
        for (; k < ls.size() && ls[k] != "```"; ++k) b.text += ls[k] + "\n";
        out.push_back(b);
        i = k;
    }
    return out;
}

} // namespace

TEST_CASE("every moire block in the tutorial is the step file it names, in order") {
    std::vector<std::string> files = stepFiles();
    REQUIRE(files.size() >= 6);
    std::vector<Block> blocks = moireBlocks(test::readFile(test::sourcePath("docs/tutorial.md")));
    REQUIRE(blocks.size() == files.size());
    for (size_t i = 0; i < files.size(); ++i) {
        CAPTURE(files[i]);
        CHECK(blocks[i].named == files[i]);
        CHECK(blocks[i].text == test::readFile(test::sourcePath(files[i])));
    }
}

TEST_CASE("every step of the tutorial renders, draws, and changes the picture") {
    test::TempDir dir("tutorial");
    Image previous;
    for (const std::string& file : stepFiles()) {
        CAPTURE(file);
        Image img = test::renderWithMoire(file + " --size 360x240 --time 9", dir, "step");
        const double ink = test::meanInk(img, 0, img.width);
        INFO("ink ", ink);
        CHECK(ink > 0.05);
        CHECK(ink < 0.95);
        if (!previous.pixels.empty()) {
            test::ImageDiff d = test::compareImages(previous, img, 0.1);
            INFO("mean change from the step before ", d.meanAbs);
            CHECK(d.meanAbs > 0.005);
        }
        previous = std::move(img);
    }
}

// What the page says about the last steps: the piece moves (t = 0 and t = 9 differ, and one
// cycle of 15 s later it is where it began), and its params are set from the command line.
TEST_CASE("the tutorial's piece moves, loops in 15 s, and takes its params with -D") {
    test::TempDir dir("tutorial-piece");
    const std::string piece = "docs/tutorial/06-finished-piece.moire --size 240x160";
    Image t0 = test::renderWithMoire(piece + " --time 0", dir, "t0");
    Image t9 = test::renderWithMoire(piece + " --time 9", dir, "t9");
    Image t15 = test::renderWithMoire(piece + " --time 15", dir, "t15");
    CHECK(test::compareImages(t0, t9, 0.1).meanAbs > 0.02);
    CHECK(test::compareImages(t0, t15, 2.0 / 255).fractionWithin() >= 0.999);
    Image blue =
        test::renderWithMoire(piece + " --time 0 -D tilt=4deg -D sun_ink=#3d5a80", dir, "blue");
    CHECK(test::compareImages(t0, blue, 0.1).meanAbs > 0.02);
}
