// User diagnostics and internal errors, kept apart (as Halide does):
//  - a UserError is the user's input being wrong; it carries file:line:col diagnostics and
//    makes the command exit with status 1;
//  - an InternalError is a bug in moire itself (MOIRE_ICE / MOIRE_CHECK); it is never
//    expected, and exits with status 70.
#pragma once

#include "compiler/diag/Source.h"

#include <fmt/format.h>
#include <stdexcept>
#include <string>
#include <vector>

namespace moire {

enum class Msg {
#define MOIRE_MSG(id, text) id,
#include "compiler/diag/Messages.def"
#undef MOIRE_MSG
};

// The template text of a message (for tests that check every message has a case).
const char* messageTemplate(Msg m);
const char* messageName(Msg m);
int messageCount();

enum class Severity { Error, Note };

struct Diagnostic {
    Severity severity = Severity::Error;
    Msg msg{};
    SourceRange range;
    std::string text;
};

class DiagEngine {
  public:
    explicit DiagEngine(const SourceManager& sm) : sm_(sm) {}

    template <class... Args>
    void error(SourceRange at, Msg m, Args&&... args) {
        report(Severity::Error, at, m, format(m, std::forward<Args>(args)...));
    }
    template <class... Args>
    void note(SourceRange at, Msg m, Args&&... args) {
        report(Severity::Note, at, m, format(m, std::forward<Args>(args)...));
    }

    bool hasErrors() const { return errorCount_ > 0; }
    int errorCount() const { return errorCount_; }
    const std::vector<Diagnostic>& all() const { return diags_; }

    // Renders every diagnostic as
    //   path:line:col: error: message
    //      3 |   source line
    //        |   ^~~~
    std::string render() const;
    std::string render(const Diagnostic& d) const;

    // Stop collecting after this many errors; later stages would only repeat the cause.
    static constexpr int kMaxErrors = 20;

  private:
    template <class... Args>
    static std::string format(Msg m, Args&&... args) {
        return fmt::format(fmt::runtime(messageTemplate(m)), std::forward<Args>(args)...);
    }
    void report(Severity s, SourceRange at, Msg m, std::string text);

    const SourceManager& sm_;
    std::vector<Diagnostic> diags_;
    int errorCount_ = 0;
    int droppedErrors_ = 0;         // errors over kMaxErrors, counted but not kept
    bool droppedLastError_ = false; // the last error was over kMaxErrors: drop its notes too
};

// Thrown when a stage finished with errors; the DiagEngine holds them.
class UserError : public std::runtime_error {
  public:
    UserError() : std::runtime_error("the scene has errors") {}
};

// A bug in moire. Never the user's fault.
class InternalError : public std::logic_error {
  public:
    using std::logic_error::logic_error;
};

[[noreturn]] void internalError(const char* file, int line, const std::string& what);

} // namespace moire

#define MOIRE_ICE(...) ::moire::internalError(__FILE__, __LINE__, fmt::format(__VA_ARGS__))
#define MOIRE_CHECK(cond, ...)                                                                     \
    do {                                                                                           \
        if (!(cond)) MOIRE_ICE("check failed: " #cond " " __VA_ARGS__);                            \
    } while (0)
