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

// "#rrggbb" or "#rrggbbaa" as straight sRGB components in 0..1; empty when it is not one.
std::vector<double> hexColour(const std::string& s) {
    if ((s.size() != 7 && s.size() != 9) || s[0] != '#') return {};
    std::vector<double> out;
    for (size_t i = 1; i < s.size(); i += 2) {
        int v = 0;
        for (size_t k = i; k < i + 2; ++k) {
            const char c = s[k];
            const int d = c >= '0' && c <= '9'   ? c - '0'
                          : c >= 'a' && c <= 'f' ? c - 'a' + 10
                          : c >= 'A' && c <= 'F' ? c - 'A' + 10
                                                 : -1;
            if (d < 0) return {};
            v = v * 16 + d;
        }
        out.push_back(v / 255.0);
    }
    if (out.size() == 3) out.push_back(1.0);
    return out;
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
        out = hexColour(value.get<std::string>());
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
