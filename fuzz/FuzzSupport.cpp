#include "fuzz/FuzzSupport.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/lower/LowerScene.h"
#include "compiler/parse/Parser.h"
#include "compiler/stdlib/Embedded.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace moire::fuzz {

void finding(const std::string& what) {
    std::fprintf(stderr, "moire fuzz finding: %s\n", what.c_str());
    std::fflush(stderr);
    std::abort();
}

// The same modules, in the same order, with the same shown names as compileScene: the
// library files of the embedded standard library, then the scene. The parser reads each file on
// its own, so the parse-only target leaves the library out (it would be most of its time).
std::unique_ptr<Front> runFront(std::string text, bool check) {
    auto f = std::make_unique<Front>();
    for (const embedded::File& file : check ? embedded::files() : std::vector<embedded::File>{}) {
        std::string_view path = file.path;
        if (!path.starts_with("stdlib/") || path.starts_with("stdlib/scenes/") ||
            !path.ends_with(".moire"))
            continue;
        uint32_t id = f->sources->add("<stdlib>/" + std::string(path.substr(7)),
                                      std::string(file.text), /*isStdlib=*/true);
        f->modules.push_back(
            std::make_unique<ast::Module>(Parser(*f->sources, id, *f->diags).parseModule()));
    }
    if (f->diags->hasErrors()) finding("the standard library does not parse");
    f->userFile = f->sources->add("fuzz.moire", std::move(text));
    f->modules.push_back(
        std::make_unique<ast::Module>(Parser(*f->sources, f->userFile, *f->diags).parseModule()));
    if (!check || f->diags->hasErrors()) return f;
    std::vector<ast::Module*> modules;
    for (auto& m : f->modules) modules.push_back(m.get());
    f->checked = sema::check(modules, *f->diags);
    f->checkedOk = !f->diags->hasErrors();
    return f;
}

void checkDiagnostics(const Front& f) {
    int errors = 0;
    for (const Diagnostic& d : f.diags->all()) {
        if (d.severity == Severity::Error) ++errors;
        if (d.text.empty()) finding("a diagnostic without text");
        if (!d.range.begin.valid()) continue;
        if (d.range.begin.file >= f.sources->size())
            finding("a diagnostic names file " + std::to_string(d.range.begin.file));
        const SourceFile& file = f.sources->file(d.range.begin.file);
        if (d.range.begin.offset > file.text().size())
            finding("a diagnostic points past the end of its file: " + d.text);
        if (f.diags->render(d).empty()) finding("a diagnostic renders as nothing");
    }
    // The engine keeps at most kMaxErrors errors (it counts the rest).
    if (errors > DiagEngine::kMaxErrors) finding("more errors kept than kMaxErrors");
    if (f.diags->hasErrors() && errors == 0) finding("errors reported but none kept");
    // The structured diagnostics (an editor's, `check --format=json`) say what the text says.
    std::string joined;
    for (const LocatedDiagnostic& d : f.diags->located()) joined += d.rendered;
    if (joined != f.diags->render()) finding("the located diagnostics differ from the text");
}

LowerSetup lowerSetup(const Front& f, const uint8_t* data, size_t size) {
    // A byte mixed from the whole input picks the options: one bit each.
    uint32_t h = 2166136261u;
    for (size_t i = 0; i < size; ++i) h = (h ^ data[i]) * 16777619u;
    LowerSetup s;
    s.literals = f.modules.back()->literals;
    s.options.layerFields = h & 1;
    s.options.tally = (h >> 1) & 1;
    if ((h >> 2) & 1) {
        s.options.probeSlot = static_cast<int>(s.literals.size());
        s.literals.push_back(0.25);
        s.literals.push_back(-0.5);
    }
    if ((h >> 3) & 1) {
        s.options.viewSlot = static_cast<int>(s.literals.size());
        s.literals.resize(s.literals.size() +
                              lower::ViewSlots::count(static_cast<int>(f.checked.layers.size())),
                          0.0);
        s.literals[s.options.viewSlot + lower::ViewSlots::kZoomFactor] = 1.0;
    }
    return s;
}

std::vector<double> interpret(const ir::Function& f, const std::vector<double>& params,
                              const std::vector<double>& uniforms, double px, double py, int w,
                              int h, double t) {
    return Interpreter(f).atPixel(uniforms, px, py, w, h, t, &params);
}

bool sameValue(double a, double b) {
    if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
    if (a == b) return true;
    return std::abs(a - b) <= 1e-9 * std::max(std::abs(a), std::abs(b));
}

void requireSame(const char* what, const std::vector<double>& a, const std::vector<double>& b,
                 size_t count) {
    if (a.size() < count || b.size() < count) finding(std::string(what) + ": too few outputs");
    for (size_t i = 0; i < count; ++i)
        if (!sameValue(a[i], b[i]))
            finding(std::string(what) + ": output " + std::to_string(i) + " is " +
                    std::to_string(a[i]) + " against " + std::to_string(b[i]));
}

} // namespace moire::fuzz
