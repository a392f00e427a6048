// Every kernel moire can make passes spirv-val for Vulkan 1.2: the example scenes and the
// embedded default, every family and field preset of the standard library in a small scene,
// and the walking families, whose kernels nest loops and ifs, each compiled with the layer
// fields output and without. A module glslang produces but the validator rejects would be
// refused by a driver, or worse, run with undefined behaviour. The families and presets are
// read from the library's own source, so a new one is covered without touching this file.
#include "compiler/backend/glsl/GlslKernel.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <filesystem>
#include <regex>

using namespace moire;

namespace {

const std::vector<std::pair<std::string, CompileOptions>>& variants() {
    static const std::vector<std::pair<std::string, CompileOptions>> all = {
        {"plain", {}},
        {"layer fields", {.layerFields = true}},
        {"fields, probe and tally",
         {.mode = CompileOptions::Mode::Probe, .layerFields = true, .tally = true}},
    };
    return all;
}

// Compiles the scene in every variant; each kernel's SPIR-V must pass spirv-val.
void checkScene(const std::string& name, const std::string& text,
                const std::string& path = "test.moire") {
    for (const auto& [variant, options] : variants()) {
        CAPTURE(name);
        CAPTURE(variant);
        auto program = test::compileOk(text, options, path);
        std::vector<uint32_t> spirv;
        REQUIRE_NOTHROW(spirv = glsl::compileSpirv(program->kernel));
        std::string message;
        bool valid = glsl::validateSpirv(spirv, &message);
        INFO("spirv-val: ", message);
        CHECK(valid);
    }
}

std::vector<std::string> matches(const std::string& text, const std::regex& re) {
    std::vector<std::string> out;
    for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
         ++it)
        out.push_back((*it)[1]);
    return out;
}

std::string librarySource(const std::string& file) {
    return test::readFile(test::sourcePath("stdlib/" + file));
}

// How deeply ifs and loops nest in a function (0: straight-line code).
int nesting(const ir::Function& f, ir::BlockId block = 0) {
    int deepest = 0;
    for (const ir::Inst& inst : f.blocks[block].insts)
        for (ir::BlockId region : inst.regions) deepest = std::max(deepest, 1 + nesting(f, region));
    return deepest;
}

} // namespace

TEST_CASE("spirv: the validator rejects a broken module") {
    // Otherwise every check below could pass on a validator that accepts anything.
    auto program = test::compileOk("layer { family = circles }");
    std::vector<uint32_t> spirv = glsl::compileSpirv(program->kernel);
    std::string message;
    CHECK(glsl::validateSpirv(spirv, &message));
    spirv.resize(spirv.size() - 3); // cut the last instructions short
    CHECK_FALSE(glsl::validateSpirv(spirv, &message));
    CHECK_FALSE(message.empty());
}

TEST_CASE("spirv: every example scene and the default scene validate") {
    EmbeddedScene d = defaultScene();
    checkScene("default", d.text, d.path);
    std::vector<std::string> examples = test::exampleScenes();
    CHECK(examples.size() >= 4);
    for (const std::string& rel : examples)
        checkScene(std::filesystem::path(rel).stem().string(),
                   test::readFile(test::sourcePath(rel)), rel);
}

TEST_CASE("spirv: every stdlib family validates, alone and over a twin") {
    const std::vector<std::string> families = matches(
        librarySource("families.moire"), std::regex(R"((?:^|\n)(?:builtin )?family (\w+))"));
    CHECK(families.size() >= 10);
    for (const std::string& family : families) {
        checkScene(family, "layer { family = " + family + " }\n");
        checkScene(family + " over lines",
                   "layer { family = lines; spacing = 7 }\n"
                   "layer { family = " +
                       family + "; spacing = 6; rotation = 10deg; origin = (3, -2) }\n");
    }
}

TEST_CASE("spirv: walking families (nested loops and ifs) validate") {
    // The families with `facets` can walk: their kernels search for the nearest member in a
    // loop with branches inside. Each one walking, and two walking together.
    std::vector<std::string> walking;
    const std::string src = librarySource("families.moire");
    const std::regex block(R"(family (\w+)[^{\n]*\{([^}]*)\})");
    for (auto it = std::sregex_iterator(src.begin(), src.end(), block);
         it != std::sregex_iterator(); ++it)
        if ((*it)[2].str().find("facets") != std::string::npos) walking.push_back((*it)[1]);
    CHECK(walking.size() >= 4);
    for (const std::string& family : walking) {
        const std::string text =
            "layer { family = " + family + "; spacing = 8; offset = (1.1, 0.4); turn = 1.6deg }\n";
        auto program = test::compileOk(text);
        CAPTURE(family);
        CHECK(nesting(program->kernel) >= 2); // a loop with an if inside, at least
        checkScene(family + " walking", text);
    }
    checkScene("two walking", "layer { family = squares; spacing = 8; offset = (1.1, 0.4) }\n"
                              "layer { family = circles; spacing = 9; offset = (0.3, -0.7); "
                              "turn = 2deg }\n");
}

TEST_CASE("spirv: every field preset validates") {
    const std::vector<std::string> fields =
        matches(librarySource("fields.moire"), std::regex(R"((?:^|\n)field (\w+))"));
    CHECK(fields.size() >= 6);
    for (const std::string& field : fields)
        checkScene(field, "layer { family = lines; spacing = 6 }\n"
                          "layer { family = lines; spacing = 6; field = " +
                              field + "; gain = 1 }\n");
}
