// User diagnostics and internal errors, kept apart (as Halide does):
//  - a UserError is the user's input being wrong; it carries file:line:col diagnostics and
//    makes the command exit with status 1;
//  - an InternalError is a bug in moire itself (MOIRE_ICE / MOIRE_CHECK); it is never
//    expected, and exits with status 70.
#pragma once

#include "compiler/diag/Source.h"
#include "compiler/diag/Suggest.h"

#include <fmt/format.h>
#include <optional>
#include <stdexcept>
#include <string>
#include <type_traits>
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

const char* severityName(Severity s); // "error", "note"

// What a "did you mean" hint proposes: `replacement` written in place of `range`.
struct Suggestion {
    std::string replacement;
    SourceRange range;
};

struct Diagnostic {
    Severity severity = Severity::Error;
    Msg msg{};
    SourceRange range;
    std::string text;
    std::optional<Suggestion> suggestion; // from a Hint argument that proposes a replacement
};

// A range as an editor shows it: the file's name as diagnostics print it, and the 1-based
// line and column (in characters, as the caret line counts them) of its first character and
// of the character just after it.
struct LocatedRange {
    std::string file;
    LineCol start, end;
    uint32_t offset = 0, length = 0; // in bytes, in the file's text
};
LocatedRange locate(const SourceManager& sm, SourceRange r);

// One diagnostic with everything resolved, for tools (`moire check --format=json`, an
// editor): it no longer needs the SourceManager.
struct LocatedDiagnostic {
    Severity severity = Severity::Error;
    std::string id;                    // the message's name in Messages.def: "UnknownName"
    std::string message;               // the text after "error: "
    std::optional<LocatedRange> range; // none: about no place in the source
    struct Fix {
        std::string replacement;
        LocatedRange range;
    };
    std::optional<Fix> suggestion;
    std::string rendered; // exactly as DiagEngine::render prints it
};

class DiagEngine {
  public:
    explicit DiagEngine(const SourceManager& sm) : sm_(sm) {}

    template <class... Args>
    void error(SourceRange at, Msg m, Args&&... args) {
        report(Severity::Error, at, m, format(m, args...), suggestionOf(at, args...));
    }
    template <class... Args>
    void note(SourceRange at, Msg m, Args&&... args) {
        report(Severity::Note, at, m, format(m, args...), suggestionOf(at, args...));
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

    // The same diagnostics one by one, in order, each with its rendered text; the note on
    // errors left out (kMaxErrors) comes last, as render() prints it.
    std::vector<LocatedDiagnostic> located() const;

    // Stop collecting after this many errors; later stages would only repeat the cause.
    static constexpr int kMaxErrors = 20;

  private:
    template <class... Args>
    static std::string format(Msg m, const Args&... args) {
        return fmt::format(fmt::runtime(messageTemplate(m)), args...);
    }
    // The replacement proposed by the message's Hint argument, if it has one.
    template <class... Args>
    static std::optional<Suggestion> suggestionOf(SourceRange at, const Args&... args) {
        std::optional<Suggestion> out;
        auto take = [&](const auto& a) {
            if constexpr (std::is_same_v<std::decay_t<decltype(a)>, Hint>)
                if (!a.replacement.empty())
                    out = Suggestion{a.replacement, a.range.begin.valid() ? a.range : at};
        };
        (take(args), ...);
        (void)take; // a message with no arguments
        return out;
    }
    void report(Severity s, SourceRange at, Msg m, std::string text,
                std::optional<Suggestion> suggestion);
    // The note render() ends with when errors were left out.
    std::optional<Diagnostic> droppedNote() const;

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
