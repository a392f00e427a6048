#include "runtime/view/ParamValues.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lex/Lexer.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <numbers>

namespace moire::view {

namespace {

using ast::Type;

constexpr double kDegree = 180.0 / std::numbers::pi;

// A number trimmed to twelve significant digits: what snapping on a step computed in binary
// leaves as 0.30000000000000004 is meant as 0.3.
double trimmed(double v) {
    return std::stod(fmt::format("{:.12g}", v));
}

// On the step from `origin`, then in [lo, hi] (the ends as given, when present).
double onStep(double v, std::optional<double> step, std::optional<double> lo,
              std::optional<double> hi) {
    if (step && *step > 0) {
        const double origin = lo.value_or(0.0);
        v = trimmed(origin + std::round((v - origin) / *step) * *step);
    }
    if (lo) v = std::max(v, *lo);
    if (hi) v = std::min(v, *hi);
    return v;
}

} // namespace

ParamValue snapParamValue(const Parameter& p, ParamValue value) {
    ParamValue v = value;
    switch (p.type) {
    case Type::Bool:
        v = {value[0] >= 0.5 ? 1.0 : 0.0, 0, 0, 0};
        break;
    case Type::Color:
        for (double& c : v) c = std::clamp(std::isfinite(c) ? c : 0.0, 0.0, 1.0);
        break;
    case Type::Angle:
        if (p.unit == Unit::Deg) {
            // On the step in degrees, as the slider shows it and the file writes it.
            auto deg = [](std::optional<double> r) {
                return r ? std::optional<double>(trimmed(*r * kDegree)) : std::nullopt;
            };
            const double d =
                onStep(trimmed(value[0] * kDegree), deg(p.step), deg(p.min), deg(p.max));
            v[0] = d * (std::numbers::pi / 180.0); // as the lexer reads `{d}deg`
        } else {
            v[0] = onStep(value[0], p.step, p.min, p.max);
        }
        v[1] = v[2] = v[3] = 0;
        break;
    default:
        for (int i = 0; i < 4; ++i)
            v[i] = i < p.components ? onStep(value[i], p.step, p.min, p.max) : 0.0;
        break;
    }
    for (int i = 0; i < p.components; ++i)
        if (!std::isfinite(v[i])) v[i] = p.min.value_or(0.0);
    // What the file would say reads back as itself; a value next to a limit that the literal
    // rounds past the limit stays as it is (still in range).
    if (std::optional<ParamValue> back = readLiteral(p, literalText(p, v)))
        if (checkParameterValue(p, std::span<const double>(back->data(), p.components)).empty())
            return *back;
    return v;
}

std::string literalText(const Parameter& p, const ParamValue& value) {
    return formatParameterValue(p, std::span<const double>(value.data(), p.components));
}

std::string_view defaultText(const Parameter& p, std::string_view source) {
    const size_t at = p.valueRange.begin.offset, n = p.valueRange.length;
    if (!p.valueRange.begin.valid() || at > source.size() || n > source.size() - at) return {};
    return source.substr(at, n);
}

void applyParams(std::span<const Parameter> params, const ParamSet& set,
                 std::vector<double>& literals) {
    for (size_t i = 0; i < params.size() && i < set.size(); ++i)
        if (set[i])
            setParameterValue(
                params[i], std::span<const double>(set[i]->data(), params[i].components), literals);
}

ParamSet carryParams(std::span<const Parameter> from, const ParamSet& set,
                     std::string_view fromSource, std::span<const Parameter> to,
                     std::string_view toSource) {
    ParamSet out(to.size());
    for (size_t j = 0; j < to.size(); ++j)
        for (size_t i = 0; i < from.size() && i < set.size(); ++i) {
            const Parameter &a = from[i], &b = to[j];
            if (!set[i] || a.name != b.name) continue;
            if (a.type == b.type && a.components == b.components &&
                defaultText(a, fromSource) == defaultText(b, toSource) &&
                checkParameterValue(b, std::span<const double>(set[i]->data(), b.components))
                    .empty())
                out[j] = set[i];
            break;
        }
    return out;
}

} // namespace moire::view
