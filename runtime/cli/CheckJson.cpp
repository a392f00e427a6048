// `moire check --format=json`: the diagnostics of each scene as one JSON document on standard
// output, for editors and other tools. The fields are those of LocatedDiagnostic
// (compiler/diag/Diagnostics.h); docs/cli.md describes the document.
#include "runtime/cli/Commands.h"
#include "runtime/cli/Shared.h"
#include "runtime/FrameEval.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

namespace moire::cli {

namespace {

using Json = nlohmann::ordered_json;

Json toJson(const LocatedRange& r) {
    return Json{{"file", r.file},
                {"start", {{"line", r.start.line}, {"column", r.start.column}}},
                {"end", {{"line", r.end.line}, {"column", r.end.column}}},
                {"offset", r.offset},
                {"length", r.length}};
}

Json toJson(const LocatedDiagnostic& d) {
    Json j{{"severity", severityName(d.severity)}, {"id", d.id}, {"message", d.message}};
    j["range"] = d.range ? toJson(*d.range) : Json(nullptr);
    j["suggestion"] = d.suggestion ? Json{{"replacement", d.suggestion->replacement},
                                          {"range", toJson(d.suggestion->range)}}
                                   : Json(nullptr);
    j["rendered"] = d.rendered;
    return j;
}

} // namespace

int checkJson(const std::vector<std::string>& scenes) {
    int status = kExitOk;
    Json list = Json::array();
    for (const std::string& path : scenes) {
        Json entry{{"scene", path}, {"read", true}, {"ok", false}};
        Json diagnostics = Json::array();
        Source src;
        // An unreadable scene is said on standard error, as in text mode: it has no source
        // for a diagnostic to point into.
        if (!readScene(path, src)) {
            entry["read"] = false;
        } else {
            CompileResult r = compileScene(src.path, src.text);
            std::vector<LocatedDiagnostic> all = std::move(r.diagnosticList);
            bool ok = r.program != nullptr;
            if (ok) {
                FrameValues frame;
                std::string rendered;
                std::vector<LocatedDiagnostic> frameDiags;
                ok = evaluateFrame(*r.program, FrameRequest{}, frame, rendered, &frameDiags);
                all.insert(all.end(), frameDiags.begin(), frameDiags.end());
            }
            for (const LocatedDiagnostic& d : all) diagnostics.push_back(toJson(d));
            entry["ok"] = ok;
        }
        // The first failing scene's status, as in text mode.
        if (status == kExitOk && !entry["ok"].get<bool>())
            status = entry["read"].get<bool>() ? kExitScene : kExitIo;
        entry["diagnostics"] = std::move(diagnostics);
        list.push_back(std::move(entry));
    }
    fmt::print("{}\n", Json{{"scenes", std::move(list)}}.dump(2));
    return status;
}

} // namespace moire::cli
