// The checks of a `param`: a value that a tool may replace (compiler/Parameters.h), so one
// that never depends on the position, with a range and step that a slider can read without
// running anything.
#include "compiler/sema/Checker.h"
#include "compiler/sema/ConstantValue.h"

#include <fmt/format.h>
#include <numbers>

namespace moire::sema::detail {

using namespace ast;

namespace {
std::string number(double v) {
    return fmt::format("{:g}", v);
}
} // namespace

void Checker::checkDefinedValue(Decl& p) {
    // A `-D` value has the type of the default it replaces: the scene was written for that.
    // (A bare 0 serves for an angle, as everywhere.)
    checkExpr(*p.sceneDefault, Scope{});
    const Type want = p.sceneDefault->type, type = p.value->type;
    if (want == Type::Error || type == Type::Error || type == want ||
        (want == Type::Angle && isLiteralZero(*p.value)))
        return;
    diags_.error(p.value->range, Msg::TypeMismatch, fmt::format("param '{}'", p.name),
                 typeName(want), typeName(type));
    // The scene's own default stands in, so that the param's uses are not reported as well.
    std::swap(p.value, p.sceneDefault);
    p.sceneDefault.reset();
}

void Checker::checkParam(Decl& p) {
    // The default itself was checked with the fields (checkField): its type, and cycles
    // through other params and fields.
    const std::string what = fmt::format("param '{}'", p.name);
    if (p.sceneDefault && p.sceneDefault->type == Type::Error) return;
    // A `-D` value has its default's type (checkDefinedValue); a bare 0 for an angle included.
    const Type type = p.sceneDefault ? p.sceneDefault->type : p.value->type;
    const Expr& value = *p.value;
    if (value.type != Type::Error && value.dependsOnPosition) {
        diags_.error(value.range, Msg::MustBeConstant, what, "the position (x, y, r or theta)");
        return;
    }
    out_.params.push_back(&p);
    if (!p.rangeLo && !p.step) return;
    if (type == Type::Error) return;
    if (type != Type::Num && type != Type::Angle && type != Type::Vec2) {
        const Expr& at = p.rangeLo ? *p.rangeLo : *p.step;
        diags_.error(at.range, Msg::ParamNoRange, p.name, typeName(type));
        return;
    }
    // The ends and the step have the type of one component: an angle for an angle (a bare
    // 0 too, as everywhere), a number for a number or a vector.
    const Type component = type == Type::Angle ? Type::Angle : Type::Num;
    auto read = [&](Expr& e, const char* role) -> std::optional<double> {
        checkExpr(e, Scope{});
        if (e.type == Type::Error) return std::nullopt;
        if (e.type != component && !(component == Type::Angle && isLiteralZero(e))) {
            diags_.error(e.range, Msg::TypeMismatch, fmt::format("the {} of {}", role, what),
                         typeName(component), typeName(e.type));
            return std::nullopt;
        }
        std::optional<double> v = constantValue(e);
        if (!v) diags_.error(e.range, Msg::ParamNotConstant, role, p.name);
        return v;
    };
    std::optional<double> lo, hi;
    if (p.rangeLo) {
        lo = read(*p.rangeLo, "range");
        hi = read(*p.rangeHi, "range");
        if (lo && hi && !(*lo < *hi)) {
            diags_.error(p.rangeLo->range, Msg::ParamEmptyRange, p.name, number(*lo), number(*hi));
            return;
        }
    }
    if (p.step) {
        std::optional<double> s = read(*p.step, "step");
        if (s && !(*s > 0)) diags_.error(p.step->range, Msg::ParamBadStep, p.name, number(*s));
    }
    // A default of numbers alone is checked against the range now; one that is an expression
    // is checked on every frame (lower/ValueChecks), where it has a value.
    if (!lo || !hi) return;
    // Angles are shown in degrees when the range was written in them.
    const bool degrees = p.rangeHi->kind == ExprKind::Number && p.rangeHi->unit == Unit::Deg;
    auto shown = [&](double v) {
        return degrees ? number(v * 180.0 / std::numbers::pi) + "deg" : number(v);
    };
    auto inRange = [&](const Expr& e) {
        std::optional<double> v = constantValue(e);
        if (!v || (*v >= *lo && *v <= *hi)) return;
        diags_.error(e.range, Msg::ValueOutOfRange, what,
                     fmt::format("from {} to {}", shown(*lo), shown(*hi)), shown(*v));
    };
    if (type == Type::Vec2 && value.kind == ExprKind::Vector) {
        for (const ExprPtr& c : value.args) inRange(*c);
    } else if (type != Type::Vec2) {
        inRange(value);
    }
}

} // namespace moire::sema::detail
