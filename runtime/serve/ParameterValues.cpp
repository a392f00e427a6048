#include "runtime/serve/ParameterValues.h"

#include "runtime/serve/Session.h"

#include <cmath>
#include <fmt/format.h>

namespace moire::serve {

namespace {

using json = nlohmann::json;

json optionalNumber(const std::optional<double>& v) {
    return v ? json(*v) : json(nullptr);
}

} // namespace

json parameterJson(const Parameter& p, const std::vector<double>& value, bool set) {
    json j;
    j["name"] = p.name;
    j["type"] = parameterKind(p.type);
    j["components"] = p.components;
    j["min"] = optionalNumber(p.min);
    j["max"] = optionalNumber(p.max);
    j["step"] = optionalNumber(p.step);
    j["unit"] = p.unit == Unit::Deg   ? json("deg")
                : p.unit == Unit::Rad ? json("rad")
                                      : json(nullptr);
    json v = json::array();
    // A non-finite value (a default that divides by zero) is no JSON number: null.
    for (double c : value) v.push_back(std::isfinite(c) ? json(c) : json(nullptr));
    j["value"] = v;
    j["set"] = set;
    return j;
}

std::vector<double> parameterValueFromJson(const Parameter& p, const json& value) {
    std::vector<double> out;
    const std::string what = fmt::format("'{}' ({})", p.name, parameterKind(p.type));
    if (value.is_boolean()) {
        if (p.type != ast::Type::Bool)
            throw RequestError(fmt::format("{} takes no true or false", what));
        out = {value.get<bool>() ? 1.0 : 0.0};
    } else if (value.is_number()) {
        out = {value.get<double>()};
    } else if (value.is_string()) {
        if (p.type != ast::Type::Color) throw RequestError(fmt::format("{} takes no text", what));
        // A colour as the language writes it (#rrggbb or #rrggbbaa), read by the same rules.
        if (std::optional<std::array<double, 4>> c =
                readParameterValue(p, value.get<std::string>()))
            out.assign(c->begin(), c->end());
        if (out.empty())
            throw RequestError(fmt::format("{} takes a colour as #rrggbb or #rrggbbaa, not '{}'",
                                           what, value.get<std::string>()));
    } else if (value.is_array()) {
        for (const json& c : value) {
            if (!c.is_number())
                throw RequestError(fmt::format("the components of {} must be numbers", what));
            out.push_back(c.get<double>());
        }
        // A colour without alpha is opaque.
        if (p.type == ast::Type::Color && out.size() == 3) out.push_back(1.0);
    } else {
        throw RequestError(fmt::format("{} takes a number, true or false, a list of numbers or "
                                       "a colour's #rrggbb",
                                       what));
    }
    if (static_cast<int>(out.size()) != p.components)
        throw RequestError(fmt::format("{} has {} component{}, not {}", what, p.components,
                                       p.components == 1 ? "" : "s", out.size()));
    if (std::string why = checkParameterValue(p, out); !why.empty())
        throw RequestError(why); // it names the parameter
    return out;
}

} // namespace moire::serve
