// Semantic checks on small scenes, with the real standard library in scope: name
// resolution, field cycles, types and units, arity, what may depend on the position or the
// clock, duplicates and reserved names. Errors are checked by message id and text; valid
// scenes by the annotations the checks leave on the tree.
#include "compiler/parse/Parser.h"
#include "compiler/sema/Sema.h"
#include "compiler/stdlib/Embedded.h"

#include <doctest/doctest.h>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::ast;

namespace {

struct Checked {
    std::unique_ptr<SourceManager> sm = std::make_unique<SourceManager>();
    std::unique_ptr<DiagEngine> diags;
    std::vector<std::unique_ptr<Module>> modules;
    sema::CheckedScene scene;

    const Module& user() const { return *modules.back(); }
    const Decl& decl(const std::string& name) const {
        for (const DeclPtr& d : user().decls)
            if (d->name == name) return *d;
        FAIL("no declaration named ", name);
        throw;
    }
    std::vector<Msg> msgs() const {
        std::vector<Msg> m;
        for (const Diagnostic& d : diags->all()) m.push_back(d.msg);
        return m;
    }
    std::string firstText() const { return diags->all().empty() ? "" : diags->all()[0].text; }
};

// Parses the standard library and `text`, then runs the semantic checks (as compileScene
// does, without lowering).
Checked check(const std::string& text) {
    Checked c;
    c.diags = std::make_unique<DiagEngine>(*c.sm);
    for (const embedded::File& f : embedded::files()) {
        std::string_view path = f.path;
        if (!path.starts_with("stdlib/")) continue;
        uint32_t id = c.sm->add(std::string(path), std::string(f.text), true);
        c.modules.push_back(std::make_unique<Module>(Parser(*c.sm, id, *c.diags).parseModule()));
    }
    uint32_t id = c.sm->add("sema.moire", text);
    c.modules.push_back(std::make_unique<Module>(Parser(*c.sm, id, *c.diags).parseModule()));
    REQUIRE_MESSAGE(!c.diags->hasErrors(), "parse errors:\n", c.diags->render());
    std::vector<Module*> mods;
    for (auto& m : c.modules) mods.push_back(m.get());
    c.scene = sema::check(mods, *c.diags);
    return c;
}

Checked ok(const std::string& text) {
    Checked c = check(text);
    INFO(text, "\n", c.diags->render());
    REQUIRE_FALSE(c.diags->hasErrors());
    return c;
}

// The one error a scene must give.
std::string error(const std::string& text, Msg want) {
    Checked c = check(text);
    INFO(text, "\n", c.diags->render());
    REQUIRE(c.diags->errorCount() == 1);
    CHECK(c.diags->all()[0].msg == want);
    return c.firstText();
}

const Expr& fieldValue(const Checked& c, const std::string& name) {
    return *c.decl(name).value;
}

} // namespace

TEST_CASE("sema: names resolve to fields, parameters, lets, spacing and built-ins") {
    Checked c = ok("field f = x + 1\n"
                   "family fam(k = 2) { let w = k * spacing; phase = w + f + pi }\n"
                   "layer { family = fam }\n");
    const Decl& fam = c.decl("fam");
    const Expr& let = *fam.lets[0].value; // k * spacing
    CHECK(let.args[0]->ref == RefKind::FamilyParam);
    CHECK(let.args[0]->refIndex == 0);
    CHECK(let.args[1]->ref == RefKind::Spacing);
    const Expr& phase = *fam.prop("phase")->value; // (w + f) + pi
    const Expr& w = *phase.args[0]->args[0];
    CHECK(w.ref == RefKind::Let);
    CHECK(w.refIndex == 0);
    CHECK(w.refDecl == &fam);
    const Expr& f = *phase.args[0]->args[1];
    CHECK(f.ref == RefKind::Field);
    CHECK(f.refDecl == &c.decl("f"));
    CHECK(phase.args[1]->ref == RefKind::Builtin);
    // The layer's family is the user's family.
    REQUIRE(c.scene.layers.size() == 1);
    REQUIRE(c.scene.layers[0].family);
    CHECK(c.scene.layers[0].family->decl == &fam);
}

TEST_CASE("sema: spacing exists only inside families and anonymous phases") {
    ok("layer { family = x + spacing / 2 }");
    ok("layer { family = spacing }"); // a constant phase, not an unknown family
    CHECK(error("field f = x / spacing", Msg::NameNotHere) ==
          "'spacing' can only be used in a family's phase");
    error("layer { family = circles; phase = spacing }", Msg::NameNotHere);
}

TEST_CASE("sema: a let is visible only after it is defined") {
    CHECK(error("family f { let a = b; let b = 1; phase = a }", Msg::NameNotHere) ==
          "'b' can only be used after 'let b = ...' defines it");
    error("family f { let a = a + 1; phase = a }", Msg::NameNotHere);
    // ... but a let may hide a field of the same name, which its own value can still use.
    ok("field a = 1\nfamily f { let a = a * 2; phase = x * a }");
}

TEST_CASE("sema: unknown names suggest only near candidates") {
    CHECK(error("field f = thta", Msg::UnknownName) ==
          "unknown name 'thta'; did you mean 'theta'?");
    // Every one-letter name is one edit from every other: no suggestion for those.
    CHECK(error("field f = a", Msg::UnknownName) == "unknown name 'a'");
    CHECK(error("field f = sinn(x)", Msg::UnknownFunction) ==
          "unknown function 'sinn'; did you mean 'sin'?");
    // An easing's name called like a function: more likely a slip for a function.
    CHECK(error("field f = sine(x)", Msg::NotAFunction) ==
          "'sine' is an easing, not a function; did you mean 'sin'?");
    CHECK(error("layer { family = circle }", Msg::UnknownFamily) ==
          "unknown family 'circle'; did you mean 'circles'?");
}

TEST_CASE("sema: fields may not depend on themselves") {
    CHECK(error("field a = b + 1\nfield b = a * 2", Msg::FieldCycle) ==
          "field 'a' depends on itself (a -> b -> a)");
    CHECK(error("field a = a", Msg::FieldCycle) == "field 'a' depends on itself (a -> a)");
    ok("field a = b + 1\nfield b = x"); // used before its declaration is fine
}

TEST_CASE("sema: expression types") {
    Checked c = ok("field n = 1 + 2\n"
                   "field a = 30deg + 1rad\n"
                   "field ratio = 30deg / 10deg\n"
                   "field scaled = 2 * 30deg\n"
                   "field v = (1, 2) * 3\n"
                   "field col = mix(#000000, #ffffff, 0.5)\n"
                   "field len = length((3, 4))\n"
                   "field s = sin(30deg) + sin(1)\n"
                   "field m = min(10deg, 0)\n"
                   "field rgbc = rgb(1, 0, 0)\n");
    CHECK(fieldValue(c, "n").type == Type::Num);
    CHECK(fieldValue(c, "a").type == Type::Angle);
    CHECK(fieldValue(c, "ratio").type == Type::Num); // angle / angle
    CHECK(fieldValue(c, "scaled").type == Type::Angle);
    CHECK(fieldValue(c, "v").type == Type::Vec2);
    CHECK(fieldValue(c, "col").type == Type::Color);
    CHECK(fieldValue(c, "len").type == Type::Num);
    CHECK(fieldValue(c, "s").type == Type::Num);
    CHECK(fieldValue(c, "m").type == Type::Angle); // 0 is zero in every unit
    CHECK(fieldValue(c, "rgbc").type == Type::Color);
}

TEST_CASE("sema: type errors") {
    CHECK(error("field f = 30deg + 1", Msg::BinaryTypes) ==
          "cannot apply '+' to an angle and a number; give the number a unit, as in 30deg");
    CHECK(error("field f = 30deg * 30deg", Msg::BinaryTypes) ==
          "cannot apply '*' to an angle and an angle");
    CHECK(error("field f = 1 / 30deg", Msg::BinaryTypes) ==
          "cannot apply '/' to a number and an angle");
    CHECK(error("field f = #ffffff + #000000", Msg::BinaryTypes) ==
          "cannot apply '+' to a colour and a colour");
    CHECK(error("field f = 2 ^ 30deg", Msg::BinaryTypes) ==
          "cannot apply '^' to a number and an angle");
    CHECK(error("field f = -#ffffff", Msg::UnaryType) == "cannot apply '-' to a colour");
    CHECK(error("field f = sqrt(30deg)", Msg::ArgumentType) ==
          "argument 1 of 'sqrt' must be a number, but this is an angle");
    CHECK(error("field f = max(1, 30deg)", Msg::SameTypeArgs) ==
          "the arguments of 'max' must have the same type, but they are a number and an angle");
    CHECK(error("field f = mix(1, #000000, 0.5)", Msg::SameTypeArgs) ==
          "the arguments of 'mix' must have the same type, but they are a number and a colour");
    CHECK(error("field f = (1, 2, 3)", Msg::VectorSize) == "a vector has 2 components, not 3");
    CHECK(error("field f = (1, #000000)", Msg::TypeMismatch) ==
          "a vector component expects a number, but this is a colour");
    CHECK(error("layer { family = circles; spacing = #ff0000 }", Msg::TypeMismatch) ==
          "'spacing' expects a number, but this is a colour");
    CHECK(error("layer { family = (x, y) }", Msg::TypeMismatch) ==
          "'family' expects a family name or a number (a phase), but this is a 2-vector");
}

TEST_CASE("sema: angles need a unit, except a literal zero") {
    CHECK(error("camera { rotation = 30 }", Msg::AngleNeedsUnit) ==
          "'rotation' is an angle: write the number with a unit, as in 30deg or 30rad");
    CHECK(error("camera { rotation = -12.5 }", Msg::AngleNeedsUnit) ==
          "'rotation' is an angle: write the number with a unit, as in -12.5deg or -12.5rad");
    ok("camera { rotation = 0 }");
    ok("camera { rotation = -0 }");
    ok("camera { rotation = 30deg }");
    ok("layer { family = circles; rotation = 1rad * t }");
    // A stdlib family's angle parameter takes the same rule.
    CHECK(error("layer { family = lines; angle = 45 }", Msg::AngleNeedsUnit) ==
          "'angle' is an angle: write the number with a unit, as in 45deg or 45rad");
    ok("layer { family = lines; angle = 45deg }");
}

TEST_CASE("sema: calls take the number of arguments their function has") {
    CHECK(error("field f = sin(1, 2)", Msg::Arity) == "'sin' takes 1 argument, but 2 were given");
    CHECK(error("field f = atan2(1)", Msg::Arity) == "'atan2' takes 2 arguments, but 1 was given");
    CHECK(error("field f = rgba()", Msg::Arity) == "'rgba' takes 4 arguments, but 0 were given");
    CHECK(error("field f = x(2)", Msg::NotAFunction) == "'x' is a built-in value, not a function");
    CHECK(error("field g = 1\nfield f = g(2)", Msg::NotAFunction) ==
          "'g' is a field, not a function");
    CHECK(error("field f = circles(2)", Msg::NotAFunction) ==
          "'circles' is a family, not a function");
    CHECK(error("field f = sin", Msg::FunctionAsValue) ==
          "'sin' is a function; call it with arguments, as in sin(...)");
    CHECK(error("field f = circles", Msg::FamilyAsValue) ==
          "'circles' is a family; give it to a layer, as in: family = circles");
}

TEST_CASE("sema: settings that are fixed for a frame or a whole render") {
    CHECK(error("camera { zoom = 1 + x / 100 }", Msg::MustBeConstant) ==
          "'zoom' cannot depend on the position (x, y, r or theta)");
    ok("camera { zoom = 1 + t / 10 }"); // the camera may move over time
    CHECK(error("scene { size = (100 + t, 100) }", Msg::MustBeConstant) ==
          "'size' cannot depend on the clock t");
    // Through a field, too.
    error("field g = theta\ncamera { center = (g, 0) }", Msg::MustBeConstant);
    // Layers may vary in space and time.
    ok("layer { family = circles; spacing = 5 + x / 100; color = rgb(t, 0, 0) }");
}

TEST_CASE("sema: position and time dependence is annotated") {
    Checked c = ok("field p = x * 2\n"
                   "field q = t\n"
                   "field both = p + q\n"
                   "field none = pi * 2\n"
                   "field polar = r + theta\n");
    CHECK(fieldValue(c, "p").dependsOnPosition);
    CHECK_FALSE(fieldValue(c, "p").dependsOnTime);
    CHECK_FALSE(fieldValue(c, "q").dependsOnPosition);
    CHECK(fieldValue(c, "q").dependsOnTime);
    CHECK(fieldValue(c, "both").dependsOnPosition);
    CHECK(fieldValue(c, "both").dependsOnTime);
    CHECK_FALSE(fieldValue(c, "none").dependsOnPosition);
    CHECK_FALSE(fieldValue(c, "none").dependsOnTime);
    CHECK(fieldValue(c, "polar").dependsOnPosition);
}

TEST_CASE("sema: duplicates are reported with a note at the first") {
    Checked props = check("layer { family = circles; spacing = 4; spacing = 5 }");
    CHECK(props.msgs() == std::vector<Msg>{Msg::DuplicateProperty, Msg::FirstSeenHere});
    CHECK(props.firstText() == "'spacing' is set twice in this layer");
    Checked fields = check("field f = 1\nfield f = 2");
    CHECK(fields.msgs() == std::vector<Msg>{Msg::DuplicateDecl, Msg::FirstDefinedHere});
    CHECK(fields.firstText() == "there is already a field named 'f'");
    // A scene's own declaration hides the library's of the same name, rather than clashing.
    CHECK(
        check(
            "family circles = r * 2\nfield ripple = x\nlayer { family = circles; field = ripple }")
            .msgs()
            .empty());
    CHECK(check("layer a { family = circles }\nlayer a { family = circles }").firstText() ==
          "there is already a layer named 'a'");
    Checked scenes = check("scene { }\nscene { }");
    CHECK(scenes.msgs() == std::vector<Msg>{Msg::DuplicateBlock, Msg::FirstDefinedHere});
    CHECK(scenes.firstText() ==
          "there is already a scene block; put all its settings in one block");
    Checked params = check("family f(k, k) = x * k");
    CHECK(params.msgs() == std::vector<Msg>{Msg::DuplicateDecl, Msg::FirstDefinedHere});
    CHECK(check("family f(k = 1) { let k = 2; phase = x }").firstText() ==
          "there is already a parameter named 'k'");
    CHECK(check("family f { let a = 1; let a = 2; phase = x }").firstText() ==
          "there is already a let named 'a'");
}

TEST_CASE("sema: built-in names cannot be redefined") {
    for (const char* text :
         {"field x = 1", "field sin = 1", "family theta = r", "family f(t = 1) = x",
          "family f { let pi = 3; phase = x }", "field spacing = 2"}) {
        CAPTURE(text);
        Checked c = check(text);
        REQUIRE_FALSE(c.msgs().empty());
        CHECK(c.msgs()[0] == Msg::ReservedName);
    }
    CHECK(error("field tau = 6", Msg::ReservedName) ==
          "'tau' is a built-in name and cannot be redefined");
    CHECK(error("family f(stroke = 1) = x * stroke", Msg::ParamIsLayerProperty) ==
          "a family parameter cannot be called 'stroke': that is the name of a layer property");
}

TEST_CASE("sema: the standard library's families are visible to layers") {
    Checked c =
        ok("layer { family = wave; amplitude = 5; shift = 10deg }\nlayer { family = hyperbola }");
    REQUIRE(c.scene.layers.size() == 2);
    REQUIRE(c.scene.layers[0].family);
    CHECK(c.scene.layers[0].family->decl->name == "wave");
    REQUIRE(c.scene.layers[0].args.size() == 3);
    CHECK(c.scene.layers[0].args[0] != nullptr); // amplitude set
    CHECK(c.scene.layers[0].args[1] == nullptr); // frequency left at its default
    CHECK(c.scene.layers[1].family->first == 1);
    CHECK(error("layer { family = wave; amplitud = 5 }", Msg::UnknownProperty) ==
          "'amplitud' is not a property of a layer of family 'wave'; did you mean 'amplitude'?");
}

TEST_CASE("sema: layers and families need what they need") {
    error("layer { spacing = 4 }", Msg::MissingFamily);
    CHECK(error("family ring(radius) = abs(r - radius)\nlayer { family = ring }",
                Msg::MissingParam) == "family 'ring' needs a value for its parameter 'radius'; set "
                                      "it in the layer, as in: radius = 1");
    ok("family ring(radius) = abs(r - radius)\nlayer { family = ring; radius = 20 }");
    CHECK(error("family blank { first = 1 }", Msg::FamilyNeedsPhase) ==
          "family 'blank' has no phase or distance; add one, as in: phase = r");
    error("family f { phase = r; first = 0.5 }", Msg::FirstNotInteger);
    error("family f { phase = r; first = x }", Msg::FirstNotInteger);
    Checked negative = ok("family f { phase = r; first = -2 }");
    CHECK(negative.scene.families.at(&negative.decl("f")).first == -2);
    CHECK(error("family f { phase = r; w = 2 }", Msg::UnknownProperty) ==
          "'w' is not a property of a family (its properties are phase, first, facets, distance "
          "and index); to name a "
          "value, write: let w = ...");
    CHECK(error("scene { sise = (1, 2) }", Msg::UnknownProperty) ==
          "'sise' is not a property of the scene; did you mean 'size'?");
}

TEST_CASE("sema: a chain of fields too deep to inline is an error, not a stack overflow") {
    // f_k = f_(k-1) + 1 is 2k + 1 levels tall once the fields are filled in.
    auto chain = [](int n, bool reversed) {
        std::string text = "field f0 = x\n";
        for (int k = 1; k <= n; ++k)
            text += "field f" + std::to_string(k) + " = f" + std::to_string(k - 1) + " + 1\n";
        if (reversed) { // declared from the top down: checking f0 recurses through them all
            text.clear();
            for (int k = 0; k < n; ++k)
                text += "field f" + std::to_string(k) + " = f" + std::to_string(k + 1) + " + 1\n";
            text += "field f" + std::to_string(n) + " = x\n";
        }
        return text;
    };
    ok(chain(500, false));
    // f512 is 1025 levels tall: the name f512 in f513 is the first past the limit of 1024.
    CHECK(error(chain(600, false), Msg::FieldsTooDeep) ==
          "'f512' is nested too deeply once the fields and lets it uses are filled in (more than "
          "1024 levels)");
    // 100,000 fields, each named by the one before: one error, no crash.
    Checked c = check(chain(100000, true));
    CHECK(c.msgs() == std::vector<Msg>{Msg::FieldsTooDeep});
}

// Animation: easings, timings, ramp/progress and morphs (spec §8.3, §8.5).

TEST_CASE("sema: u is the progress inside an easing and nowhere else") {
    Checked c = ok("field k = 2\neasing w = u ^ k * (3 - 2 * u)");
    const Expr& value = *c.decl("w").value; // (u ^ k) * (3 - 2 * u)
    CHECK(value.args[0]->args[0]->ref == RefKind::EasingVar);
    CHECK(value.args[0]->args[1]->ref == RefKind::Field); // a constant field is fine
    CHECK(value.type == Type::Num);
    CHECK(error("field f = u", Msg::UnknownName) == "unknown name 'u'");
    error("layer { family = circles; spacing = 10 * u }", Msg::UnknownName);
    // A field is checked in its own scope, even when an easing uses it.
    error("field g = u\neasing w = g", Msg::UnknownName);
    // An easing is a function of u alone.
    CHECK(error("easing w = u * x", Msg::MustBeConstant) ==
          "easing 'w' cannot depend on the position (x, y, r or theta)");
    CHECK(error("easing w = u + t", Msg::MustBeConstant) ==
          "easing 'w' cannot depend on the clock t");
    CHECK(error("easing w = (u, u)", Msg::TypeMismatch) ==
          "easing 'w' expects a number, but this is a 2-vector");
}

TEST_CASE("sema: timings: their properties, modes and easings") {
    Checked c = ok("timing a { period = 2 }\n"
                   "timing b { period = 1.5; delay = 0.5; mode = pingpong; easing = sine }\n"
                   "easing mine = u\ntiming d { period = 1; mode = once; easing = mine }\n");
    const sema::CheckedTiming& a = c.scene.timings.at(&c.decl("a"));
    CHECK(a.mode == sema::TimingMode::Loop); // the default
    CHECK(a.easing == nullptr);              // linear
    CHECK(a.delay == nullptr);
    const sema::CheckedTiming& b = c.scene.timings.at(&c.decl("b"));
    CHECK(b.mode == sema::TimingMode::PingPong);
    REQUIRE(b.easing);
    CHECK(b.easing->name == "sine");
    CHECK(c.scene.timings.at(&c.decl("d")).easing == &c.decl("mine"));
    CHECK(c.scene.timingOrder ==
          std::vector<const Decl*>{&c.decl("a"), &c.decl("b"), &c.decl("d")});
    CHECK(error("timing a { delay = 1 }", Msg::MissingProperty) ==
          "timing 'a' needs its period; add one, as in: period = 4");
    CHECK(error("timing a { period = 1; mode = forever }", Msg::BadMode) ==
          "a timing's mode is once, loop or pingpong, not 'forever'; did you mean 'loop'?");
    // No guess from a poor spelling match: 'bounce' is two edits from 'once', and means pingpong.
    CHECK(error("timing a { period = 1; mode = bounce }", Msg::BadMode) ==
          "a timing's mode is once, loop or pingpong, not 'bounce'; did you mean 'pingpong'?");
    CHECK(error("timing a { period = 1; mode = ponce }", Msg::BadMode) ==
          "a timing's mode is once, loop or pingpong, not 'ponce'; did you mean 'once'?");
    CHECK(error("timing a { period = 1; mode = bounced }", Msg::BadMode) ==
          "a timing's mode is once, loop or pingpong, not 'bounced'");
    CHECK(error("timing a { period = 1; mode = 2 }", Msg::BadMode) ==
          "a timing's mode is once, loop or pingpong, not this");
    CHECK(error("timing a { period = 1; easing = sin }", Msg::NotAnEasing) ==
          "'sin' is not an easing; did you mean 'sine'?");
    CHECK(error("timing a { period = 1; easing = circles }", Msg::NotAnEasing) ==
          "'circles' is not an easing; the easings are cubic_in, cubic_in_out, cubic_out, linear, "
          "quad_in, quad_in_out, quad_out, sine, sine_in and sine_out, or declare one, as in: "
          "easing mine = u * u");
    CHECK(error("timing a { period = 1; speed = 2 }", Msg::UnknownProperty) ==
          "'speed' is not a property of a timing (its properties are period, delay, mode and "
          "easing)");
    // The period and delay set the clip's length: fixed for the whole animation.
    CHECK(error("timing a { period = 1 + t }", Msg::MustBeConstant) ==
          "'period' cannot depend on the clock t");
    error("timing a { period = 1; delay = x }", Msg::MustBeConstant);
    error("timing a { period = 1 }\ntiming b { period = 1 + progress(a) }", Msg::MustBeConstant);
    Checked twice = check("timing a { period = 1; period = 2 }");
    CHECK(twice.msgs() == std::vector<Msg>{Msg::DuplicateProperty, Msg::FirstSeenHere});
    CHECK(error("field a = 1\ntiming a { period = 1 }", Msg::DuplicateDecl) ==
          "there is already a field named 'a'");
    error("timing t { period = 1 }", Msg::ReservedName);
}

TEST_CASE("sema: a timing's or an easing's name is not a value") {
    CHECK(error("timing drift { period = 1 }\nfield f = drift * 2", Msg::TimingAsValue) ==
          "'drift' is a timing; use it as in ramp(drift, from, to) or progress(drift)");
    error("timing drift { period = 1 }\ncamera { zoom = drift }", Msg::TimingAsValue);
    CHECK(error("field f = cubic_out", Msg::EasingAsValue) ==
          "'cubic_out' is an easing; name it in a timing, as in: easing = cubic_out");
}

TEST_CASE("sema: ramp and progress take a timing and values of one type") {
    Checked c = ok("timing tm { period = 1 }\n"
                   "field n = ramp(tm, 1, 2)\nfield a = ramp(tm, 0deg, 30deg)\n"
                   "field v = ramp(tm, (0, 0), (1, 2))\nfield col = ramp(tm, #000000, #ffffff)\n"
                   "field p = progress(tm)\n");
    CHECK(fieldValue(c, "n").type == Type::Num);
    CHECK(fieldValue(c, "a").type == Type::Angle);
    CHECK(fieldValue(c, "v").type == Type::Vec2);
    CHECK(fieldValue(c, "col").type == Type::Color);
    CHECK(fieldValue(c, "p").type == Type::Num);
    CHECK(fieldValue(c, "p").args[0]->ref == RefKind::Timing);
    CHECK(fieldValue(c, "p").args[0]->refDecl == &c.decl("tm"));
    // Both follow the clock, and nothing else.
    CHECK(fieldValue(c, "n").dependsOnTime);
    CHECK_FALSE(fieldValue(c, "n").dependsOnPosition);
    CHECK(fieldValue(c, "p").dependsOnTime);
    const std::string tm = "timing tm { period = 1 }\n";
    CHECK(error(tm + "field f = ramp(tm, 1, 30deg)", Msg::SameTypeArgs) ==
          "the arguments of 'ramp' must have the same type, but they are a number and an angle");
    error(tm + "field f = ramp(tm, (1, 2), #ffffff)", Msg::SameTypeArgs);
    CHECK(error(tm + "field f = ramp(tm, 1)", Msg::Arity) ==
          "'ramp' takes 3 arguments, but 2 were given");
    CHECK(error(tm + "field f = progress(tm, 1)", Msg::Arity) ==
          "'progress' takes 1 argument, but 2 were given");
    CHECK(error("field f = ramp(1, 2, 3)", Msg::NotATiming) ==
          "'ramp' takes a timing's name first, as in ramp(drift, 0, 1)");
    CHECK(error("field g = 1\nfield f = progress(g)", Msg::NotATiming) ==
          "'progress' takes a timing's name first, as in progress(drift)");
    CHECK(error(tm + "scene { size = ramp(tm, (100, 100), (200, 200)) }", Msg::MustBeConstant) ==
          "'size' cannot depend on the clock t");
    ok(tm + "camera { zoom = 1 + progress(tm); rotation = ramp(tm, 0deg, 90deg) }");
}

TEST_CASE("sema: a morph: a timing and two or more families, which share the layer's parameters") {
    const std::string tm = "timing tm { period = 3 }\n";
    Checked c =
        ok(tm + "layer { family = morph(tm, lines, wave, circles); angle = 30deg; amplitude = 4 }");
    const sema::CheckedLayer& layer = c.scene.layers.at(0);
    CHECK(layer.morphTiming == &c.decl("tm"));
    REQUIRE(layer.morph.size() == 3);
    CHECK(layer.morph[0].family->decl->name == "lines");
    CHECK(layer.morph[1].family->decl->name == "wave");
    CHECK(layer.family == layer.morph[0].family); // the first member is the layer's family
    CHECK(layer.morph[0].args[0] != nullptr);     // lines' angle
    CHECK(layer.morph[1].args[0] != nullptr);     // wave's amplitude
    CHECK(layer.morph[1].args[1] == nullptr);     // wave's frequency: its default
    // A parameter of the same name in two members is one setting, checked against both.
    const std::string two = "family a(k = 1) = x * k\nfamily b(k = 0deg) = r * cos(k)\n";
    Checked shared = ok(tm + "family a2(k = 1) = x * k\nfamily b2(k = 2) = y * k\n"
                             "layer { family = morph(tm, a2, b2); k = 3 }");
    const sema::CheckedLayer& sl = shared.scene.layers.at(0);
    CHECK(sl.morph[0].args[0] == sl.morph[1].args[0]);
    CHECK(sl.morph[0].args[0] != nullptr);
    CHECK(error(tm + two + "layer { family = morph(tm, a, b); k = 3 }", Msg::AngleNeedsUnit) ==
          "'k' is an angle: write the number with a unit, as in 3deg or 3rad");
    error(tm + "family ring(radius) = abs(r - radius)\nlayer { family = morph(tm, circles, ring) }",
          Msg::MissingParam);
    CHECK(error(tm + "layer { family = morph(tm, lines, wave); amplitud = 4 }",
                Msg::UnknownProperty) ==
          "'amplitud' is not a property of a layer; did you mean 'amplitude'?");
    // The arguments.
    CHECK(error(tm + "layer { family = morph(tm, circles) }", Msg::MorphArgs) ==
          "morph takes a timing and then two or more families, as in: family = morph(cycle, "
          "circles, hexagons)");
    error(tm + "layer { family = morph(tm) }", Msg::MorphArgs);
    CHECK(error("layer { family = morph(circles, squares, hexagons) }", Msg::NotATiming) ==
          "'morph' takes a timing's name first, as in morph(drift, circles, hexagons)");
    CHECK(error(tm + "layer { family = morph(tm, circles, hexagon) }", Msg::UnknownFamily) ==
          "unknown family 'hexagon'; did you mean 'hexagons'?");
    // Walking needs one member that can walk; the others ignore it.
    Checked walks = ok(tm + "layer { family = morph(tm, lines, circles); offset = (1, 0) }");
    CHECK(walks.scene.layers.at(0).walking);
    CHECK(error(tm + "layer { family = morph(tm, lines, wave); turn = 2deg }", Msg::NotWalkable) ==
          "'turn' moves the members of a family whose phase is a support function (circles, "
          "squares, triangles, hexagons, ngon); this layer's family is not one");
    ok(tm + "layer { family = morph(tm, circles, squares); morph_time = 0.5 }");
}
