// The pictures in docs/gallery.md and docs/tutorial.md against the scenes they show: every
// example has its gallery picture and every picture its example, the pages show them all,
// and each picture is what moire draws of its scene today, rendered again here exactly as
// scripts/render-gallery.sh renders it (at the stored picture's size and the script's time).
#include "runtime/output/ImageIO.h"
#include "tests/support/DocImages.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <set>

using namespace moire;
namespace fs = std::filesystem;

namespace {

std::set<std::string> stems(const std::string& dir, const std::string& ext,
                            const std::string& prefix = "") {
    std::set<std::string> out;
    for (const auto& e : fs::directory_iterator(test::sourcePath(dir))) {
        std::string name = e.path().filename().string();
        if (e.path().extension() == ext && name.rfind(prefix, 0) == 0)
            out.insert(e.path().stem().string().substr(prefix.size()));
    }
    return out;
}

// Renders `scene` as the script does, at the stored picture's size, and compares.
void checkCurrent(const std::string& scene, const std::string& stored, double time, int width,
                  const test::TempDir& dir) {
    CAPTURE(scene);
    REQUIRE_MESSAGE(fs::exists(test::sourcePath(stored)), stored,
                    " is missing: run bash scripts/render-gallery.sh");
    Image ref = readImage(test::sourcePath(stored));
    CHECK(ref.width == width);
    Image fresh =
        test::renderWithMoire(scene + " --size " + std::to_string(ref.width) + "x" +
                                  std::to_string(ref.height) + " --time " + std::to_string(time),
                              dir, "fresh");
    test::checkSameAsStored(fresh, test::sourcePath(stored));
}

// Scenes `sceneDir/NAME.moire` against pictures `pictureDir/PREFIX NAME.png`: each one of a
// pair, and each named on `page`. Returns the scenes' names.
std::set<std::string> checkPairs(const std::string& sceneDir, const std::string& pictureDir,
                                 const std::string& prefix, const std::string& page) {
    std::set<std::string> scenes = stems(sceneDir, ".moire");
    std::set<std::string> pictures = stems(pictureDir, ".png", prefix);
    for (const std::string& name : scenes)
        CHECK_MESSAGE(pictures.count(name), sceneDir, "/", name,
                      ".moire has no picture: run bash scripts/render-gallery.sh");
    for (const std::string& name : pictures)
        CHECK_MESSAGE(scenes.count(name), pictureDir, "/", prefix, name, ".png has no scene");
    const std::string text = test::readFile(test::sourcePath(page));
    const std::string linked = pictureDir.substr(std::string("docs/").size()) + "/" + prefix;
    for (const std::string& name : scenes)
        CHECK_MESSAGE(text.find("](" + linked + name + ".png)") != std::string::npos, page,
                      " does not show ", name);
    return scenes;
}

} // namespace

TEST_CASE("every example has a gallery picture on the gallery page, and nothing else does") {
    const std::string page = test::readFile(test::sourcePath("docs/gallery.md"));
    for (const std::string& name :
         checkPairs("examples", "docs/images/gallery", "", "docs/gallery.md")) {
        CAPTURE(name);
        CHECK(page.find("`examples/" + name + ".moire`") != std::string::npos);
    }
}

TEST_CASE("every tutorial step has its picture on the tutorial page, and nothing else does") {
    checkPairs("docs/tutorial", "docs/images", "tutorial-", "docs/tutorial.md");
}

TEST_CASE("the gallery's pictures are what the examples draw") {
    test::TempDir dir("gallery");
    for (const std::string& name : stems("examples", ".moire"))
        checkCurrent("examples/" + name + ".moire", "docs/images/gallery/" + name + ".png", 3.6,
                     480, dir);
}

TEST_CASE("the tutorial's pictures are what its steps draw") {
    test::TempDir dir("tutorial-pictures");
    for (const std::string& name : stems("docs/tutorial", ".moire"))
        checkCurrent("docs/tutorial/" + name + ".moire", "docs/images/tutorial-" + name + ".png", 9,
                     720, dir);
}
