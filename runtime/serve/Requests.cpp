#include "runtime/serve/Requests.h"

#include "runtime/FrameEval.h"
#include "runtime/serve/ParameterValues.h"

#include <cmath>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <optional>

namespace moire::serve {

namespace {

using json = nlohmann::json;

json parseObject(const std::string& body) {
    json j = json::parse(body, nullptr, false);
    if (j.is_discarded()) throw RequestError("the message is not JSON");
    if (!j.is_object()) throw RequestError("the message must be a JSON object");
    return j;
}

double number(const json& j, const std::string& what) {
    if (!j.is_number()) throw RequestError(fmt::format("'{}' must be a number", what));
    return j.get<double>();
}

std::pair<double, double> point(const json& j, const std::string& what) {
    if (!j.is_array() || j.size() != 2)
        throw RequestError(fmt::format("'{}' must be a pair of numbers [x, y]", what));
    return {number(j[0], what + "[0]"), number(j[1], what + "[1]")};
}

int side(const json& j, const std::string& what) {
    const double v = number(j, what);
    if (v != std::floor(v) || v < 1 || v > kMaxFrameSide)
        throw RequestError(
            fmt::format("'{}' must be a whole number of pixels from 1 to {}", what, kMaxFrameSide));
    return static_cast<int>(v);
}

void onlyKnown(const json& j, std::initializer_list<const char*> known) {
    for (auto it = j.begin(); it != j.end(); ++it) {
        bool ok = false;
        for (const char* k : known) ok = ok || it.key() == k;
        if (!ok) throw RequestError(fmt::format("unknown field '{}'", it.key()));
    }
    if (j.empty()) throw RequestError("the message asks for nothing");
}

} // namespace

uint64_t applyViewMessage(Session& session, const std::string& body) {
    json j = parseObject(body);
    onlyKnown(j, {"size", "view", "overlay", "zoom", "pan", "reset"});
    uint64_t version = session.version();
    if (j.contains("size")) {
        const json& s = j["size"];
        if (!s.is_array() || s.size() != 2)
            throw RequestError("'size' must be [width, height] in pixels");
        version = session.resize(side(s[0], "size[0]"), side(s[1], "size[1]"));
    }
    if (j.contains("view")) {
        if (!j["view"].is_string()) throw RequestError("'view' must be a view's name");
        version = session.setView(j["view"].get<std::string>());
    }
    if (j.contains("overlay")) {
        const json& o = j["overlay"];
        if (!o.is_boolean() && !o.is_null())
            throw RequestError("'overlay' must be true, false or null (the scene's own)");
        version =
            session.setOverlay(o.is_null() ? std::nullopt : std::optional<bool>(o.get<bool>()));
    }
    if (j.contains("zoom")) {
        const json& z = j["zoom"];
        if (!z.is_object() || !z.contains("x") || !z.contains("y") || !z.contains("factor"))
            throw RequestError("'zoom' must be {\"x\": .., \"y\": .., \"factor\": ..}");
        version = session.zoom(number(z["x"], "zoom.x"), number(z["y"], "zoom.y"),
                               number(z["factor"], "zoom.factor"));
    }
    if (j.contains("pan")) {
        const json& p = j["pan"];
        if (!p.is_object() || !p.contains("from") || !p.contains("to"))
            throw RequestError("'pan' must be {\"from\": [x, y], \"to\": [x, y]}");
        auto [fx, fy] = point(p["from"], "pan.from");
        auto [tx, ty] = point(p["to"], "pan.to");
        version = session.pan(fx, fy, tx, ty);
    }
    if (j.contains("reset")) {
        if (!j["reset"].is_boolean()) throw RequestError("'reset' must be true or false");
        if (j["reset"].get<bool>()) version = session.resetView();
    }
    return version;
}

uint64_t applyParameterMessage(Session& session, const std::string& body) {
    json j = parseObject(body);
    onlyKnown(j, {"name", "value"});
    if (!j.contains("name") || !j["name"].is_string())
        throw RequestError("'name' must be the parameter's name");
    if (!j.contains("value"))
        throw RequestError("'value' is missing (null gives the parameter its default)");
    const std::string name = j["name"].get<std::string>();
    if (j["value"].is_null()) return session.setParameter(name, std::nullopt);
    std::optional<Parameter> p = session.parameter(name);
    // An unknown name: setParameter says which names there are.
    if (!p) return session.setParameter(name, std::nullopt);
    return session.setParameter(name, parameterValueFromJson(*p, j["value"]));
}

uint64_t applyClockMessage(Session& session, const std::string& body) {
    json j = parseObject(body);
    onlyKnown(j, {"play", "time"});
    uint64_t version = session.version();
    std::optional<bool> play;
    if (j.contains("play")) {
        if (!j["play"].is_boolean()) throw RequestError("'play' must be true or false");
        play = j["play"].get<bool>();
    }
    std::optional<double> time;
    if (j.contains("time")) time = number(j["time"], "time");
    // Stopped first, then moved: a stopped clock shows exactly the time asked for.
    if (play == false) version = session.pause();
    if (time) version = session.seek(*time);
    if (play == true) version = session.play();
    return version;
}

} // namespace moire::serve
