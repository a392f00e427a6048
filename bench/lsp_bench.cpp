// The language server's latency on the largest example (and on a scene of 200 layers, to see
// it grow): hover and completion (each right after a change, so the scene is analysed again
// first, as when the user types and then looks), and the diagnostics of a change (analysis
// and publishing, to which the server's debounce adds its wait). Goals: hover and completion
// within 50 ms, diagnostics within 100 ms of the change (docs/editors.md).
//
//   build/bin/moire_lsp_bench [--repeat 30]
//
// The server runs in this process (lsp::Server), fed the frames a client would send, so the
// figures are the server's own work without the pipe.
#include "lsp/Server.h"

#include <algorithm>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace moire;
using namespace moire::lsp;

namespace {

const std::string kUri = "file:///bench/scene.moire";

std::vector<std::string> call(Server& s, const Json& m) {
    return s.receive({Frame::Kind::Message, m.dump(), {}});
}

Json request(int id, const std::string& method, Json params) {
    return {{"jsonrpc", "2.0"}, {"id", id}, {"method", method}, {"params", std::move(params)}};
}

// A change that keeps the scene as it was: a comment line inserted at the top (odd versions)
// or taken out again (even ones).
Json change(int version) {
    bool insert = version % 2 == 1;
    Json range{{"start", {{"line", 0}, {"character", 0}}},
               {"end", {{"line", insert ? 0 : 1}, {"character", 0}}}};
    Json edit{{"range", range}, {"text", insert ? "// edit\n" : ""}};
    Json params{{"textDocument", {{"uri", kUri}, {"version", version}}},
                {"contentChanges", Json::array({edit})}};
    return {{"jsonrpc", "2.0"}, {"method", "textDocument/didChange"}, {"params", params}};
}

struct Stats {
    double min, median;
};
Stats stats(std::vector<double> ms) {
    std::sort(ms.begin(), ms.end());
    return {ms.front(), ms[ms.size() / 2]};
}

double msSince(Clock::time_point t0) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

// The place of the first occurrence of `word` in `text`, as a position.
Json where(const std::string& text, const std::string& word) {
    size_t at = text.find(word);
    LineIndex index(text);
    Position p = index.position(static_cast<uint32_t>(at == std::string::npos ? 0 : at + 1));
    return {{"line", p.line}, {"character", p.character}};
}

void measure(const std::string& name, const std::string& text, int repeat) {
    // Diagnostics wait (debounced) until the bench asks for them, so that a request right
    // after a change finds the analysis stale and makes it.
    Server s(std::chrono::hours(1));
    call(s, request(1, "initialize", Json::object()));
    Json doc{{"uri", kUri}, {"languageId", "moire"}, {"version", 1}, {"text", text}};
    Json open{{"jsonrpc", "2.0"},
              {"method", "textDocument/didOpen"},
              {"params", {{"textDocument", doc}}}};
    call(s, open);
    std::vector<double> hover, complete, diagnose, hoverWarm;
    int version = 1, id = 10;
    Json hoverAt = where(text, "spacing"), completeAt = where(text, "stroke");
    for (int i = 0; i < repeat; ++i) {
        // The line shifts down by one with every other change: keep to the same word.
        std::string shown = s.documents().find(kUri)->text;
        hoverAt = where(shown, "spacing");
        completeAt = where(shown, "stroke");
        call(s, change(++version));
        auto t0 = Clock::now();
        call(s, request(++id, "textDocument/hover",
                        {{"textDocument", {{"uri", kUri}}}, {"position", hoverAt}}));
        hover.push_back(msSince(t0));
        t0 = Clock::now();
        call(s, request(++id, "textDocument/hover",
                        {{"textDocument", {{"uri", kUri}}}, {"position", hoverAt}}));
        hoverWarm.push_back(msSince(t0));
        call(s, change(++version));
        t0 = Clock::now();
        call(s, request(++id, "textDocument/completion",
                        {{"textDocument", {{"uri", kUri}}}, {"position", completeAt}}));
        complete.push_back(msSince(t0));
        // Diagnostics: the change and the publishing that follows it, the debounce left out.
        t0 = Clock::now();
        std::vector<std::string> out = call(s, change(++version));
        std::vector<std::string> due = s.due(Clock::now() + std::chrono::hours(2));
        diagnose.push_back(msSince(t0));
        if (due.size() + out.size() != 1) fmt::print("unexpected: {} messages\n", due.size());
    }
    auto row = [&](const char* what, const std::vector<double>& ms, double goal) {
        Stats st = stats(ms);
        fmt::print(
            "  {:<44} min {:7.2f} ms  median {:7.2f} ms  goal {:4.0f} ms  median/goal {:.3f}\n",
            what, st.min, st.median, goal, st.median / goal);
    };
    fmt::print("{} ({} bytes, {} repeats)\n", name, text.size(), repeat);
    row("hover after a change (analysis included)", hover, 50);
    row("hover, analysis fresh", hoverWarm, 50);
    row("completion after a change (analysis incl.)", complete, 50);
    // The server waits 40 ms of quiet before analysing (Server's debounce).
    std::vector<double> withDebounce = diagnose;
    for (double& d : withDebounce) d += 40;
    row("diagnostics of a change (analysis, publish)", diagnose, 100);
    row("  + the 40 ms debounce", withDebounce, 100);
}

} // namespace

int main(int argc, char** argv) {
    int repeat = 30;
    for (int i = 1; i + 1 < argc; ++i)
        if (std::string(argv[i]) == "--repeat") repeat = std::max(1, std::atoi(argv[i + 1]));
    // The largest example.
    std::filesystem::path largest;
    for (const auto& e : std::filesystem::directory_iterator(MOIRE_SOURCE_DIR "/examples"))
        if (e.path().extension() == ".moire" &&
            (largest.empty() || e.file_size() > std::filesystem::file_size(largest)))
            largest = e.path();
    std::ifstream in(largest);
    std::stringstream text;
    text << in.rdbuf();
    measure(largest.filename().string(), text.str(), repeat);
    std::string big = "scene { size = (800, 600) }\n";
    for (int i = 0; i < 200; ++i)
        big += fmt::format("layer l{} {{\n    family = circles\n    origin = ({}, 0)\n    spacing "
                           "= 6 + sin(t)\n    stroke = 1.5\n}}\n",
                           i, i);
    measure("200 layers", big, std::max(1, repeat / 3));
    return 0;
}
