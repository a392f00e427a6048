#include "runtime/Probe.h"
#include "tests/support/Support.h"

#include <doctest/doctest.h>

using namespace moire;

TEST_CASE("the default scene compiles and renders on every backend") {
    EmbeddedScene scene = defaultScene();
    auto program = test::compileOk(scene.text, {}, scene.path);
    for (const std::string& name : test::availableBackends()) {
        CAPTURE(name);
        auto backend = test::makeBackendOrSkip(name);
        if (!backend) continue;
        Image img = test::renderScene(*program, *backend, 64, 40);
        CHECK(img.width == 64);
        CHECK(img.height == 40);
    }
}

TEST_CASE("a probe reads a circle family's distance") {
    auto program = test::compileOk("layer { family = circles; spacing = 10 }",
                                   {.mode = CompileOptions::Mode::Probe, .layerFields = true});
    Prober probe(*program, nullptr);
    std::vector<double> out = probe.at(3.0, 4.0); // r = 5: half way between members 0 and 1
    CHECK(out[program->layout.indexSlot(0)] == doctest::Approx(0.5));
    CHECK(out[program->layout.distanceSlot(0)] == doctest::Approx(5.0));
    out = probe.at(0.0, 27.0);
    CHECK(out[program->layout.distanceSlot(0)] == doctest::Approx(3.0));
}
