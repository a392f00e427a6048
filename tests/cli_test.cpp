// The `moire` command line, run as a user runs it: exit statuses, files written (and not
// written), and what each dump shows.
#include "runtime/output/ImageIO.h"
#include "tests/support/Support.h"

#include <algorithm>
#include <doctest/doctest.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

namespace fs = std::filesystem;
using namespace moire;

namespace {

// A scratch directory to run moire in.
struct Workdir : test::TempDir {
    Workdir() : test::TempDir("cli") {}
    // Runs moire with `args` inside this directory.
    test::CommandResult moire(const std::string& args) const {
        return test::runCommand("cd '" + path() + "' && '" + test::moireBinary() + "' " + args);
    }
};

const char* kSmall = "scene { size = (64, 40) }\nlayer { family = circles; spacing = 4 }\n";

} // namespace

TEST_CASE("--version and --help") {
    Workdir w;
    auto v = w.moire("--version");
    CHECK(v.status == 0);
    CHECK(v.out.find("moire 0.") != std::string::npos);
    auto h = w.moire("--help");
    CHECK(h.status == 0);
    for (const char* cmd : {"render", "check", "compile"})
        CHECK(h.out.find(cmd) != std::string::npos);
    auto none = w.moire("");
    CHECK(none.status == 0);
    CHECK(none.out.find("render") != std::string::npos);
}

TEST_CASE("render with no scene writes the default scene to default.png") {
    Workdir w;
    auto r = w.moire("render --size 120x80");
    INFO(r.err);
    REQUIRE(r.status == 0);
    Image img = readImage(w.file("default.png"));
    CHECK(img.width == 120);
    CHECK(img.height == 80);
    CHECK(r.err.find("wrote default.png") != std::string::npos);
}

TEST_CASE("render writes every format, at the scene's size unless told otherwise") {
    Workdir w;
    w.write("s.moire", kSmall);
    for (const char* out : {"a.png", "b.tif", "c.exr", "d.jpg"}) {
        CAPTURE(out);
        auto r = w.moire(std::string("render s.moire -q -o ") + out);
        INFO(r.err);
        REQUIRE(r.status == 0);
        CHECK(r.err.empty()); // --quiet
        Image img = readImage(w.file(out));
        CHECK(img.width == 64);
        CHECK(img.height == 40);
    }
    auto r = w.moire("render s.moire -q -o big.png --size 128x80 --depth 16 --backend interp "
                     "--time 2 --dpi 300");
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(readImage(w.file("big.png")).width == 128);
}

TEST_CASE("the two backends render the same picture from the command line") {
    Workdir w;
    w.write("s.moire", kSmall);
    REQUIRE(w.moire("render s.moire -q -o jit.png --backend jit").status == 0);
    REQUIRE(w.moire("render s.moire -q -o interp.png --backend interp").status == 0);
    test::ImageDiff d = test::compareImages(readImage(w.file("jit.png")),
                                            readImage(w.file("interp.png")), 2.0 / 255);
    CHECK(d.fractionWithin() >= 0.999);
}

TEST_CASE("bad command lines exit with status 2 and write nothing") {
    Workdir w;
    w.write("s.moire", kSmall);
    for (const char* args :
         {"render s.moire --size 0x10", "render s.moire --size 12", "render s.moire --backend gpu",
          "render s.moire -o out.bmpx", "render s.moire --depth 12", "compile s.moire --dump=asm",
          "render s.moire --nonsense", "frobnicate"}) {
        CAPTURE(args);
        auto r = w.moire(args);
        CHECK(r.status == 2);
        CHECK_FALSE(r.err.empty());
    }
    CHECK(w.moire("render s.moire --depth float -o f.png").status == 2); // PNG cannot hold float
    CHECK(w.names() == std::vector<std::string>{"s.moire"});
}

TEST_CASE("a scene with errors gives diagnostics, status 1 and no image") {
    Workdir w;
    w.write("bad.moire", "layer {\n  family = circels\n}\n");
    auto r = w.moire("render bad.moire -o out.png");
    CHECK(r.status == 1);
    CHECK(r.err.find("bad.moire:2:12: error: unknown family 'circels'; did you mean 'circles'?") !=
          std::string::npos);
    CHECK_FALSE(fs::exists(w.file("out.png")));
    auto missing = w.moire("render nowhere.moire");
    CHECK(missing.status == 3);
    CHECK(missing.err.find("cannot read 'nowhere.moire'") != std::string::npos);
}

TEST_CASE("an existing image survives a failed render") {
    Workdir w;
    w.write("bad.moire", "layer { family = circles; spacing = }\n");
    w.write("out.png", "previous");
    CHECK(w.moire("render bad.moire -o out.png").status == 1);
    CHECK(test::readFile(w.file("out.png")) == "previous");
}

TEST_CASE("compile --dump shows each stage") {
    Workdir w;
    w.write("s.moire", kSmall);
    auto ast = w.moire("compile s.moire --dump=ast");
    CHECK(ast.status == 0);
    CHECK(ast.out.find("layer") != std::string::npos);
    CHECK(ast.out.find("family =") != std::string::npos);

    // Before AD the derivative markers are there; after it they are gone.
    auto ir = w.moire("compile s.moire --dump=ir");
    CHECK(ir.status == 0);
    CHECK(ir.out.find("deriv.x") != std::string::npos);
    auto ad = w.moire("compile s.moire --dump=ir-ad");
    CHECK(ad.status == 0);
    CHECK(ad.out.find("deriv.x") == std::string::npos);
    CHECK(ad.out.find("mulz") != std::string::npos);

    auto kernel = w.moire("compile s.moire --dump=kernel");
    CHECK(kernel.out.find("uniform") != std::string::npos);
    CHECK(kernel.out.find("param") == std::string::npos); // literals live in the frame program
    auto frame = w.moire("compile s.moire --dump=frame");
    CHECK(frame.out.find("param") != std::string::npos);

    auto llvm = w.moire("compile s.moire --dump=llvm");
    CHECK(llvm.status == 0);
    CHECK(llvm.out.find("define void @moire_kernel") != std::string::npos);
}

TEST_CASE("check reports ok scenes and fails on bad ones") {
    Workdir w;
    w.write("good.moire", kSmall);
    w.write("bad.moire", "scene { size = (0, 10) }\n");
    auto good = w.moire("check good.moire");
    CHECK(good.status == 0);
    CHECK(good.out.find("good.moire: ok") != std::string::npos);
    auto bad = w.moire("check good.moire bad.moire");
    CHECK(bad.status == 1);
    CHECK(bad.err.find("bad.moire:1:16: error: image size") != std::string::npos);
}

namespace {

// Splits text into its lines (without the newlines).
std::vector<std::string> lines(const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) out.push_back(line);
    return out;
}

// A user-facing failure: exactly one line on stderr, "moire: error: ...".
bool oneLineError(const std::string& err) {
    return err.rfind("moire: error: ", 0) == 0 && err.find('\n') == err.size() - 1;
}

// No Vulkan driver for the command: the loader finds none through either variable (the
// loader of Vulkan 1.3.234 on reads VK_DRIVER_FILES, older ones VK_ICD_FILENAMES).
const char* kNoDriver = "VK_ICD_FILENAMES=/nonexistent VK_DRIVER_FILES=/nonexistent ";

} // namespace

TEST_CASE("devices lists the Vulkan devices, one a line, or says there are none") {
    Workdir w;
    CHECK(w.moire("--help").out.find("devices") != std::string::npos);
    auto r = w.moire("devices");
    if (r.status != 0) {
        CHECK(r.status == 4);
        CHECK(oneLineError(r.err));
        test::skip("no Vulkan device here: " + r.err);
        return;
    }
    // "INDEX  TYPE  Vulkan X.Y.Z  NAME[  (default)]", indices from 0 in order.
    std::vector<std::string> names;
    int defaults = 0;
    for (const std::string& line : lines(r.out)) {
        CAPTURE(line);
        std::istringstream in(line);
        int index = -1;
        std::string type, api, version;
        in >> index >> type >> api >> version;
        CHECK(index == static_cast<int>(names.size()));
        CHECK((type == "discrete" || type == "integrated" || type == "virtual" || type == "cpu" ||
               type == "other"));
        CHECK(api == "Vulkan");
        CHECK(std::count(version.begin(), version.end(), '.') == 2);
        std::string name;
        std::getline(in >> std::ws, name);
        const std::string mark = "  (default)";
        if (name.size() > mark.size() &&
            name.compare(name.size() - mark.size(), mark.size(), mark) == 0) {
            ++defaults;
            name.resize(name.size() - mark.size());
        }
        names.push_back(name.substr(0, name.find("  (unusable")));
    }
    REQUIRE_FALSE(names.empty());
    CHECK(defaults == 1);
    // The same devices as Vulkan's own tool lists, where it is installed.
    auto info = test::runCommand("vulkaninfo --summary");
    if (info.status == 0) {
        std::vector<std::string> theirs;
        for (const std::string& line : lines(info.out))
            if (auto at = line.find("deviceName"); at != std::string::npos)
                theirs.push_back(line.substr(line.find("= ", at) + 2));
        CHECK(names == theirs);
    }
}

TEST_CASE("--backend vulkan draws what the JIT draws") {
    Workdir w;
    w.write("s.moire", kSmall);
    if (w.moire("devices").status != 0) {
        test::skip("no Vulkan device here");
        return;
    }
    auto v = w.moire("render s.moire -o vk.exr --depth float --backend vulkan --device 0");
    INFO(v.err);
    REQUIRE(v.status == 0);
    CHECK(v.err.find("wrote vk.exr (64x40, vulkan") != std::string::npos);
    REQUIRE(w.moire("render s.moire -q -o jit.exr --depth float --backend jit").status == 0);
    // examples_test.cpp's criteria for Vulkan against the interpreter.
    test::ImageDiff d =
        test::compareImages(readImage(w.file("jit.exr")), readImage(w.file("vk.exr")), 2.0 / 255);
    INFO("max ", d.maxAbs * 255, "/255, mean ", d.meanAbs * 255, "/255");
    CHECK(d.fractionWithin() >= 0.999);
    CHECK(d.meanAbs < 0.5 / 255);
}

TEST_CASE("no Vulkan device: one line, status 4, and no image written") {
    Workdir w;
    w.write("s.moire", kSmall);
    w.write("kept.png", "previous");
    for (const std::string& args :
         {std::string("render s.moire -o out.png --backend vulkan --device 99"),
          std::string("render s.moire -o kept.png --backend vulkan --device 99"),
          std::string(kNoDriver) + test::moireBinary() +
              " render s.moire -o out.png --backend vulkan",
          std::string(kNoDriver) + test::moireBinary() + " devices"}) {
        CAPTURE(args);
        // The driverless runs name the binary themselves, after the variables.
        auto r = args.rfind("VK_", 0) == 0 ? test::runCommand("cd '" + w.path() + "' && " + args)
                                           : w.moire(args);
        CHECK(r.status == 4);
        CHECK(oneLineError(r.err));
        CHECK(r.out.empty());
    }
    auto bad = w.moire("render s.moire -o out.png --backend vulkan --device 99");
    CHECK((bad.err.find("device 99") != std::string::npos ||
           bad.err.find("no Vulkan") != std::string::npos));
    CHECK(test::readFile(w.file("kept.png")) == "previous");
    // --device is for Vulkan only, and an index is never negative: command-line errors.
    CHECK(w.moire("render s.moire -o out.png --device 0").status == 2);
    CHECK(w.moire("render s.moire -o out.png --backend vulkan --device -1").status == 2);
    CHECK(w.names() == std::vector<std::string>{"kept.png", "s.moire"});
}
