// The property table is the one source of the defaults: the checks accept every default as
// the property's type, and a scene that writes a default out renders exactly as one that
// leaves it unwritten (so the lowering reads the same table). Each property is tried where it
// means something (a walking layer for `offset` and `turn`, an encoded one for `gain`, a
// morph under way for `morph_time`).
#include "compiler/sema/Properties.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>
#include <fmt/format.h>
#include <string>

using namespace moire;

namespace {

// The default as the language writes it.
std::string written(const sema::PropertySpec& spec) {
    const std::vector<double>& d = spec.defaults;
    switch (spec.type) {
    case ast::Type::Num:
        return fmt::format("{}", d.at(0));
    case ast::Type::Angle:
        return fmt::format("{}rad", d.at(0));
    case ast::Type::Vec2:
        return fmt::format("({}, {})", d.at(0), d.at(1));
    case ast::Type::Color:
        return fmt::format("rgba({}, {}, {}, {})", d.at(0), d.at(1), d.at(2), d.at(3));
    case ast::Type::Error: // a name from a list: the pattern unless set, the overlay off
        if (std::string_view(spec.name) == "view") return "pattern";
        if (std::string_view(spec.name) == "overlay") return "false";
        if (std::string_view(spec.name) == "filter") return "mean";
        FAIL("no way to write a default of ", spec.name);
        return "";
    default:
        FAIL("no way to write a default of ", spec.name);
        return "";
    }
}

size_t components(ast::Type type) {
    return type == ast::Type::Vec2 ? 2 : type == ast::Type::Color ? 4 : 1;
}

// Renders `text` at t on the reference interpreter, small.
Image render(const std::string& text, double t) {
    auto program = test::compileOk(text);
    auto interp = test::makeBackendOrSkip("interp");
    return test::renderScene(*program, *interp, 96, 64, t);
}

void checkSame(const std::string& unwritten, const std::string& explicitly, double t = 0.0) {
    INFO("unwritten:  ", unwritten);
    INFO("explicitly: ", explicitly);
    const test::ImageDiff diff =
        test::compareImages(render(unwritten, t), render(explicitly, t), 0.0);
    CHECK(diff.maxAbs == 0.0);
}

} // namespace

TEST_CASE("properties: every default has the components of its property's type") {
    for (const auto* table :
         {&sema::sceneProperties(), &sema::cameraProperties(), &sema::layerProperties()})
        for (const sema::PropertySpec& spec : *table) {
            INFO(spec.name);
            if (!spec.defaults.empty()) CHECK(spec.defaults.size() == components(spec.type));
        }
    CHECK(sema::propertySpec(sema::sceneProperties(), "size").defaults ==
          std::vector<double>{sema::kDefaultWidth, sema::kDefaultHeight});
}

TEST_CASE("properties: a layer renders the same with its defaults written out") {
    const std::string timing = "timing shapes { period = 12; mode = loop }\n";
    for (const sema::PropertySpec& spec : sema::layerProperties()) {
        if (spec.defaults.empty()) continue;
        const std::string name = spec.name;
        // Where the property means something, and a time that shows it; a spacing and a
        // stroke of its own so that the default differs from what the layer draws otherwise.
        std::string family = "circles", extra, pre;
        double t = 0.0;
        if (name == "offset") family = "squares", extra = "; turn = 4deg";
        if (name == "turn") family = "squares", extra = "; offset = (1, 0.5)";
        if (name == "gain") extra = "; field = x * y / 400";
        if (name == "morph_time") {
            pre = timing;
            family = "morph(shapes, circles, squares)";
            t = 5.9; // in the change from circles to squares
        }
        std::string head = pre + "layer { family = " + family + extra;
        if (name != "spacing") head += "; spacing = 7";
        if (name != "stroke") head += "; stroke = 2";
        INFO(name);
        checkSame(head + " }\n", head + "; " + name + " = " + written(spec) + " }\n", t);
    }
}

TEST_CASE("properties: the scene and the camera render the same with their defaults written out") {
    const std::string layers =
        "layer { family = circles; spacing = 7; stroke = 2; field = x / 3 }\n"
        "layer { family = lines; rotation = 30deg; color = #cc2200 }\n";
    std::string scene, camera;
    for (const sema::PropertySpec& spec : sema::sceneProperties())
        scene += fmt::format("{} = {}; ", spec.name, written(spec));
    for (const sema::PropertySpec& spec : sema::cameraProperties())
        camera += fmt::format("{} = {}; ", spec.name, written(spec));
    checkSame(layers, "scene { " + scene + "}\ncamera { " + camera + "}\n" + layers);
}
