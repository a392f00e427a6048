// What the fuzz targets share: the front end run the way compileScene runs it, the rule that
// turns an internal error into a finding, and the interpreter runs that check one IR function
// against another.
//
// A fuzz target (one per stage, `<stage>_fuzz.cpp`) defines LLVMFuzzerTestOneInput. Bad input
// is expected and must come back as diagnostics; a finding is a crash, a sanitizer report, an
// InternalError (MOIRE_ICE, MOIRE_CHECK, the IR verifier) or a broken invariant (finding()),
// all of which end the process so that libFuzzer (or the replay driver) reports the input.
#pragma once

#include "compiler/Compile.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/IR.h"
#include "compiler/parse/Ast.h"
#include "compiler/sema/Sema.h"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace moire::fuzz {

// Inputs longer than this are skipped. Large inputs only slow the search down: every stage's
// cost that matters grows with the number of layers and the depth of expressions, which a few
// kilobytes reach. The bounded runs and scripts/fuzz.sh pass the same figure as -max_len.
constexpr size_t kMaxInput = 4096;

// Reports a broken invariant with the input's stage and ends the process (abort, so libFuzzer
// and the sanitizers report it with the input).
[[noreturn]] void finding(const std::string& what);

// Runs `body`; an InternalError (or any other exception) escaping it is a finding.
template <class F>
void guarded(const char* stage, F&& body);

// The standard library and one user file, parsed and checked as compileScene does.
struct Front {
    std::unique_ptr<SourceManager> sources = std::make_unique<SourceManager>();
    std::unique_ptr<DiagEngine> diags = std::make_unique<DiagEngine>(*sources);
    std::vector<std::unique_ptr<ast::Module>> modules; // standard library first
    uint32_t userFile = 0;
    sema::CheckedScene checked;
    bool checkedOk = false; // parsed and checked without errors
};
// Parses `text` as the scene file "fuzz.moire"; with `check`, parses the standard library
// before it and checks them together.
std::unique_ptr<Front> runFront(std::string text, bool check);

// Every diagnostic points into a file that exists, within its text, and renders.
void checkDiagnostics(const Front& f);

// The user module's literal table (lowering appends the slots of probe and interactive
// modes to it) and the lowering options.
struct LowerSetup {
    lower::LowerOptions options;
    std::vector<double> literals;
};
// Lowering options chosen from the input's bytes, so the same input always lowers the same way.
LowerSetup lowerSetup(const Front& f, const uint8_t* data, size_t size);
// Lowers the checked scene with `setup`, then moves a probe point off the origin.
lower::LoweredScene lowerWith(const Front& f, LowerSetup& setup);

// Evaluates `f` once on the interpreter at pixel centre (px, py) of a w x h image at time t.
std::vector<double> interpret(const ir::Function& f, const std::vector<double>& params,
                              const std::vector<double>& uniforms, double px, double py, int w,
                              int h, double t);

// Two evaluations of the same quantity by two IR functions agree: equal, both NaN, or within
// a relative 1e-9 (folding may evaluate a constant through another but equivalent libm path).
bool sameValue(double a, double b);

// Fails with a description naming `what` and the first output that differs.
void requireSame(const char* what, const std::vector<double>& a, const std::vector<double>& b,
                 size_t count);

template <class F>
void guarded(const char* stage, F&& body) {
    try {
        body();
    } catch (const InternalError& e) {
        finding(std::string(stage) + ": internal error: " + e.what());
    } catch (const std::exception& e) {
        finding(std::string(stage) + ": uncaught exception: " + e.what());
    }
}

} // namespace moire::fuzz
