// The parser: operator precedence and associativity (checked on the fully parenthesised
// print of the tree), vectors and calls, every form of declaration, optional separators,
// source ranges, error recovery, the nesting limit and the literal table.
#include "compiler/parse/Parser.h"

#include <doctest/doctest.h>
#include <numbers>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::ast;

namespace {

struct Parsed {
    std::unique_ptr<SourceManager> sm = std::make_unique<SourceManager>();
    std::unique_ptr<DiagEngine> diags;
    Module module;
    ExprPtr expr;
    std::vector<Msg> msgs() const {
        std::vector<Msg> m;
        for (const Diagnostic& d : diags->all()) m.push_back(d.msg);
        return m;
    }
};

Parsed parseModule(std::string text, bool stdlib = false) {
    Parsed p;
    uint32_t id = p.sm->add("parse.moire", std::move(text), stdlib);
    p.diags = std::make_unique<DiagEngine>(*p.sm);
    p.module = Parser(*p.sm, id, *p.diags).parseModule();
    return p;
}

Parsed parseExpr(std::string text) {
    Parsed p;
    uint32_t id = p.sm->add("expr.moire", std::move(text));
    p.diags = std::make_unique<DiagEngine>(*p.sm);
    p.expr = Parser(*p.sm, id, *p.diags).parseStandaloneExpr();
    return p;
}

// The fully parenthesised form of a valid expression.
std::string tree(const std::string& text) {
    Parsed p = parseExpr(text);
    INFO("text: ", text, "\n", p.diags->render());
    REQUIRE_FALSE(p.diags->hasErrors());
    return printExpr(*p.expr);
}

// The source text a range covers.
std::string covered(const Parsed& p, SourceRange r) {
    return p.sm->file(r.begin.file).text().substr(r.begin.offset, r.length);
}

} // namespace

TEST_CASE("parser: binary operators bind by precedence") {
    CHECK(tree("1 + 2 * 3") == "(1 + (2 * 3))");
    CHECK(tree("1 * 2 + 3") == "((1 * 2) + 3)");
    CHECK(tree("(1 + 2) * 3") == "((1 + 2) * 3)");
    CHECK(tree("a * b + c / d") == "((a * b) + (c / d))");
    CHECK(tree("a + b ^ 2") == "(a + (b ^ 2))");
    CHECK(tree("2 * x ^ 2") == "(2 * (x ^ 2))");
}

TEST_CASE("parser: + - * / are left-associative, ^ is right-associative") {
    CHECK(tree("a - b - c") == "((a - b) - c)");
    CHECK(tree("a / b / c") == "((a / b) / c)");
    CHECK(tree("a - b + c") == "((a - b) + c)");
    CHECK(tree("a / b * c") == "((a / b) * c)");
    CHECK(tree("2 ^ 3 ^ 2") == "(2 ^ (3 ^ 2))");
}

TEST_CASE("parser: ^ binds tighter than unary minus, and its exponent may be signed") {
    CHECK(tree("-x^2") == "(-(x ^ 2))");
    CHECK(tree("-x * y") == "((-x) * y)");
    CHECK(tree("2 ^ -1") == "(2 ^ (-1))");
    CHECK(tree("-2 ^ -x ^ 2") == "(-(2 ^ (-(x ^ 2))))");
    CHECK(tree("- - x") == "(-(-x))");
    CHECK(tree("+x") == "(+x)");
    CHECK(tree("x * -y") == "(x * (-y))");
    CHECK(tree("(-x)^2") == "((-x) ^ 2)");
}

TEST_CASE("parser: vectors, calls and parentheses") {
    Parsed v = parseExpr("(1, y + 2)");
    REQUIRE_FALSE(v.diags->hasErrors());
    CHECK(v.expr->kind == ExprKind::Vector);
    CHECK(printExpr(*v.expr) == "(1, (y + 2))");
    CHECK(parseExpr("(x)").expr->kind == ExprKind::Name); // parentheses only group
    CHECK(tree("sin(x)") == "sin(x)");
    CHECK(tree("atan2(y, x - 1)") == "atan2(y, (x - 1))");
    CHECK(tree("f()") == "f()");
    CHECK(tree("max(min(a, b), -c)") == "max(min(a, b), (-c))");
    // Three components parse (and the semantic checks reject them with a clear message).
    Parsed three = parseExpr("(1, 2, 3)");
    CHECK_FALSE(three.diags->hasErrors());
    CHECK(three.expr->args.size() == 3);
}

TEST_CASE("parser: literals keep their units and colours") {
    Parsed deg = parseExpr("30deg");
    CHECK(deg.expr->kind == ExprKind::Number);
    CHECK(deg.expr->unit == Unit::Deg);
    Parsed col = parseExpr("#00ff00");
    CHECK(col.expr->kind == ExprKind::Color);
    CHECK(col.expr->rgba == std::array<double, 4>{0, 1, 0, 1});
}

TEST_CASE("parser: ranges cover whole expressions, and opRange is the operator or name") {
    Parsed p = parseExpr("a + sin(x) * 2");
    REQUIRE_FALSE(p.diags->hasErrors());
    CHECK(covered(p, p.expr->range) == "a + sin(x) * 2");
    CHECK(covered(p, p.expr->opRange) == "+");
    const Expr& product = *p.expr->args[1];
    CHECK(covered(p, product.range) == "sin(x) * 2");
    CHECK(covered(p, product.args[0]->range) == "sin(x)");
    CHECK(covered(p, product.args[0]->opRange) == "sin");
    Parsed neg = parseExpr("-(x, y)");
    CHECK(covered(neg, neg.expr->range) == "-(x, y)");
    CHECK(covered(neg, neg.expr->args[0]->range) == "(x, y)");
    Parsed paren = parseExpr("(a - b)");
    CHECK(covered(paren, paren.expr->range) == "(a - b)");
    CHECK(covered(paren, paren.expr->opRange) == "-");
}

TEST_CASE("parser: one declaration of each kind") {
    Parsed p = parseModule(R"(
        scene { size = (640, 480); background = #ffffff }
        camera { zoom = 2 }
        field f = x^2 - y^2
        family lines2(angle = 0deg, k) { let c = cos(angle); phase = x * c; first = 1 }
        family ring(radius = 10) = abs(r - radius)
        family plain { phase = r }
        layer left { family = circles; spacing = 7 }
        layer { family = x * y }
    )");
    INFO(p.diags->render());
    REQUIRE_FALSE(p.diags->hasErrors());
    REQUIRE(p.module.decls.size() == 8);
    std::vector<DeclKind> kinds;
    std::vector<std::string> names;
    for (const DeclPtr& d : p.module.decls) {
        kinds.push_back(d->kind);
        names.push_back(d->name);
    }
    CHECK(kinds == std::vector<DeclKind>{DeclKind::Scene, DeclKind::Camera, DeclKind::Field,
                                         DeclKind::Family, DeclKind::Family, DeclKind::Family,
                                         DeclKind::Layer, DeclKind::Layer});
    CHECK(names == std::vector<std::string>{"", "", "f", "lines2", "ring", "plain", "left", ""});

    const Decl& scene = *p.module.decls[0];
    REQUIRE(scene.props.size() == 2);
    CHECK(scene.props[0].name == "size");
    CHECK(scene.props[1].name == "background");
    CHECK(printExpr(*p.module.decls[2]->value) == "((x ^ 2) - (y ^ 2))");

    const Decl& lines2 = *p.module.decls[3];
    REQUIRE(lines2.params.size() == 2);
    CHECK(lines2.params[0].name == "angle");
    REQUIRE(lines2.params[0].defaultValue);
    CHECK(lines2.params[1].name == "k");
    CHECK_FALSE(lines2.params[1].defaultValue); // the layer must set it
    REQUIRE(lines2.lets.size() == 1);
    CHECK(lines2.lets[0].name == "c");
    CHECK(printExpr(*lines2.lets[0].value) == "cos(angle)");
    REQUIRE(lines2.props.size() == 2);
    CHECK(lines2.props[0].name == "phase");
    CHECK(lines2.props[1].name == "first");

    // The shorthand form is a family whose only property is its phase.
    const Decl& ring = *p.module.decls[4];
    REQUIRE(ring.props.size() == 1);
    CHECK(ring.props[0].name == "phase");
    CHECK(printExpr(*ring.props[0].value) == "abs((r - radius))");
    CHECK(covered(p, ring.props[0].nameRange) == "ring");

    CHECK(p.module.decls[5]->params.empty());
    CHECK(printExpr(*p.module.decls[7]->prop("family")->value) == "(x * y)");
}

TEST_CASE("parser: separators between properties are optional") {
    for (const char* text : {"layer { family = circles; spacing = 4; stroke = 2; }",
                             "layer { family = circles, spacing = 4, stroke = 2 }",
                             "layer {\n family = circles\n spacing = 4\n stroke = 2\n}",
                             "layer { family = circles spacing = 4 stroke = 2 }"}) {
        CAPTURE(text);
        Parsed p = parseModule(text);
        CHECK_FALSE(p.diags->hasErrors());
        REQUIRE(p.module.decls.size() == 1);
        std::vector<std::string> props;
        for (const Property& prop : p.module.decls[0]->props) props.push_back(prop.name);
        CHECK(props == std::vector<std::string>{"family", "spacing", "stroke"});
    }
}

TEST_CASE("parser: errors in several declarations are all reported, and parsing goes on") {
    // After an error in a declaration, parsing resumes at the next declaration keyword.
    Parsed p = parseModule("scene { size = }\n"                     // 1: no value
                           "layer { family = circles spacing 7 }\n" // 2: no '='
                           "fild g = 1\n"                           // 3: misspelt keyword
                           "field = 3\n"                            // 4: no name
                           "field ok = 2 (x + 1)\n"                 // 5: no operator
                           "field fine = 1\n");
    std::vector<uint32_t> lines;
    for (const Diagnostic& d : p.diags->all())
        lines.push_back(p.sm->file(0).lineCol(d.range.begin.offset).line);
    CHECK(lines == std::vector<uint32_t>{1, 2, 3, 4, 5});
    std::vector<std::string> texts;
    for (const Diagnostic& d : p.diags->all()) texts.push_back(d.text);
    REQUIRE(texts.size() == 5);
    CHECK(texts[0] == "expected an expression, found '}'");
    CHECK(texts[1] == "expected '=' after 'spacing', found a number '7'");
    CHECK(texts[2] == "expected a declaration (scene, camera, layer, field, family, timing, easing "
                      "or param), found "
                      "'fild'; did you mean 'field'?");
    CHECK(texts[3] == "expected a name for the field, found '='");
    CHECK(texts[4] == "expected an operator such as '*' between two values, found '('");
    // The declaration after the errors is intact.
    REQUIRE_FALSE(p.module.decls.empty());
    CHECK(p.module.decls.back()->name == "fine");
}

TEST_CASE("parser: a block left open ends at the next declaration") {
    Parsed p = parseModule("scene { size = (1, 2)\nlayer { family = circles }\n");
    REQUIRE(p.diags->all().size() == 1);
    CHECK(p.diags->all()[0].text == "expected '}' to close the scene, found 'layer'");
    REQUIRE(p.module.decls.size() == 2);
    CHECK(p.module.decls[1]->kind == DeclKind::Layer);
    CHECK(p.module.decls[1]->props.size() == 1);
}

TEST_CASE("parser: 'found end of file' points just after the last token") {
    Parsed p = parseModule("scene {\n  size = (1, 2)\n\n\n");
    REQUIRE(p.diags->all().size() == 1);
    LineCol lc = p.sm->file(0).lineCol(p.diags->all()[0].range.begin.offset);
    CHECK(lc.line == 2);
    CHECK(lc.column == 16); // after "  size = (1, 2)"
}

TEST_CASE("parser: a missing value is one error, not two") {
    for (const char* text :
         {"field f = ()", "field f = sin(1, )", "scene { size = ; background = #000000 }"}) {
        CAPTURE(text);
        Parsed p = parseModule(text);
        CHECK(p.msgs() == std::vector<Msg>{Msg::Expected});
    }
}

TEST_CASE("parser: never crashes on a runaway nesting, and reports one TooDeep error") {
    // Each would overflow the stack of a recursive parser (or of a later stage walking the
    // tree) without the limit.
    std::vector<std::string> deep = {
        "field f = " + std::string(10000, '(') + "x" + std::string(10000, ')'),
        "field f = " + std::string(10000, '-') + "x",
        "field f = sin(" + std::string(5000, '(') + "x",
        "field f = 2",
    };
    for (int i = 0; i < 10000; ++i) deep[3] += "^2";
    for (const std::string& text : deep) {
        CAPTURE(text.substr(0, 20));
        Parsed p = parseModule(text + "\nlayer { family = circles }");
        CHECK(p.msgs() == std::vector<Msg>{Msg::TooDeep});
        CHECK(p.diags->all()[0].text.find("more than 256 levels") != std::string::npos);
    }
    // Well inside the limit is fine.
    CHECK_FALSE(parseModule("field f = " + std::string(200, '(') + "x" + std::string(200, ')'))
                    .diags->hasErrors());
    std::string sum = "field f = 1";
    for (int i = 0; i < 200; ++i) sum += " + 1";
    CHECK_FALSE(parseModule(sum).diags->hasErrors());
}

TEST_CASE("parser: user literals get slots in order, and a colour takes four") {
    Parsed p = parseModule("scene { background = #336699 }\n"
                           "layer { family = circles; spacing = 7; rotation = -90deg }\n");
    REQUIRE_FALSE(p.diags->hasErrors());
    const Expr& bg = *p.module.decls[0]->prop("background")->value;
    const Expr& spacing = *p.module.decls[1]->prop("spacing")->value;
    const Expr& rotation = *p.module.decls[1]->prop("rotation")->value;
    CHECK(bg.literalSlot == 0);
    CHECK(spacing.literalSlot == 4);
    REQUIRE(rotation.kind == ExprKind::Unary); // the literal is 90deg; the minus is an operator
    CHECK(rotation.args[0]->literalSlot == 5);
    REQUIRE(p.module.literals.size() == 6);
    CHECK(p.module.literals[0] == 0x33 / 255.0);
    CHECK(p.module.literals[1] == 0x66 / 255.0);
    CHECK(p.module.literals[2] == 0x99 / 255.0);
    CHECK(p.module.literals[3] == 1.0);
    CHECK(p.module.literals[4] == 7.0);
    CHECK(p.module.literals[5] == doctest::Approx(std::numbers::pi / 2).epsilon(1e-15));
}

TEST_CASE("parser: standard-library literals are structural constants, without slots") {
    Parsed p = parseModule("family f(k = 3) { phase = k * x + 2 }", /*stdlib=*/true);
    REQUIRE_FALSE(p.diags->hasErrors());
    CHECK(p.module.literals.empty());
    CHECK(p.module.decls[0]->params[0].defaultValue->literalSlot == -1);
}
