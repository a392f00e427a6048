#include "compiler/diag/Diagnostics.h"

#include <algorithm>

namespace moire {

namespace {
struct MsgInfo {
    const char* name;
    const char* text;
};
constexpr MsgInfo kMessages[] = {
#define MOIRE_MSG(id, text) {#id, text},
#include "compiler/diag/Messages.def"
#undef MOIRE_MSG
};
} // namespace

const char* messageTemplate(Msg m) {
    return kMessages[static_cast<int>(m)].text;
}
const char* messageName(Msg m) {
    return kMessages[static_cast<int>(m)].name;
}
int messageCount() {
    return static_cast<int>(sizeof(kMessages) / sizeof(kMessages[0]));
}

const char* severityName(Severity s) {
    return s == Severity::Error ? "error" : "note";
}

LocatedRange locate(const SourceManager& sm, SourceRange r) {
    const SourceFile& f = sm.file(r.begin.file);
    LocatedRange out;
    out.file = f.path();
    out.offset = r.begin.offset;
    // A range may run past the end of the text (a missing token after the last one).
    uint32_t size = static_cast<uint32_t>(f.text().size());
    uint32_t end = static_cast<uint32_t>(
        std::min<uint64_t>(uint64_t{r.begin.offset} + r.length, std::max(size, r.begin.offset)));
    out.length = end - r.begin.offset;
    out.start = f.lineCol(r.begin.offset);
    out.end = f.lineCol(end);
    return out;
}

void DiagEngine::report(Severity s, SourceRange at, Msg m, std::string text,
                        std::optional<Suggestion> suggestion) {
    if (s == Severity::Error) {
        droppedLastError_ = errorCount_ >= kMaxErrors;
        if (droppedLastError_) {
            ++droppedErrors_;
            return;
        }
        ++errorCount_;
    } else if (droppedLastError_) {
        // A note explains the error before it; without that error it would point at nothing.
        return;
    }
    diags_.push_back(Diagnostic{s, m, at, std::move(text), std::move(suggestion)});
}

std::string DiagEngine::render(const Diagnostic& d) const {
    const char* kind = severityName(d.severity);
    if (!d.range.begin.valid()) return fmt::format("moire: {}: {}\n", kind, d.text);
    const SourceFile& f = sm_.file(d.range.begin.file);
    LineCol lc = f.lineCol(d.range.begin.offset);
    std::string out = fmt::format("{}:{}:{}: {}: {}\n", f.path(), lc.line, lc.column, kind, d.text);

    std::string_view line = f.lineText(d.range.begin.offset);
    uint32_t lineStart = f.lineStart(d.range.begin.offset);
    uint32_t rangeBegin = d.range.begin.offset;
    uint32_t rangeEnd = static_cast<uint32_t>(std::min<uint64_t>(
        uint64_t{rangeBegin} + d.range.length, uint64_t{lineStart} + line.size()));
    // Walk the line one character at a time (as SourceFile::lineCol counts columns). The
    // shown line replaces control characters and bytes that are not UTF-8 with U+FFFD, so the
    // output stays readable text; the caret line keeps tabs so that it stays aligned under
    // any tab width, and marks the range with one '^' or '~' per character.
    std::string shown, marks;
    bool caret = false;
    for (size_t i = 0; i < line.size();) {
        uint32_t cp = 0;
        size_t n = decodeUtf8(line, i, cp);
        bool printable = n > 0 && (cp == '\t' || (cp >= 0x20 && cp != 0x7F));
        shown += printable ? line.substr(i, n) : std::string_view("\xEF\xBF\xBD");
        size_t step = n ? n : 1;
        uint32_t at = lineStart + static_cast<uint32_t>(i);
        if (at + step <= rangeBegin)
            marks += n == 1 && cp == '\t' ? '\t' : ' ';
        else if (!caret)
            marks += '^', caret = true;
        else if (at < rangeEnd)
            marks += '~';
        i += step;
    }
    // The range may begin at the end of the line (a missing ')' or '}').
    if (!caret) marks += '^';
    std::string gutter = fmt::format("{:>5}", lc.line);
    out += fmt::format("{} | {}\n", gutter, shown);
    out += fmt::format("{} | {}\n", std::string(gutter.size(), ' '), marks);
    return out;
}

std::string DiagEngine::render() const {
    std::string out;
    for (const Diagnostic& d : diags_) out += render(d);
    if (std::optional<Diagnostic> more = droppedNote()) out += render(*more);
    return out;
}

std::optional<Diagnostic> DiagEngine::droppedNote() const {
    // Later errors are usually echoes of the first ones; say how many were left out.
    if (droppedErrors_ == 0) return std::nullopt;
    return Diagnostic{Severity::Note, Msg::MoreErrors, SourceRange{},
                      format(Msg::MoreErrors, droppedErrors_, droppedErrors_ == 1 ? "" : "s"),
                      std::nullopt};
}

std::vector<LocatedDiagnostic> DiagEngine::located() const {
    std::vector<LocatedDiagnostic> out;
    auto add = [&](const Diagnostic& d) {
        LocatedDiagnostic l;
        l.severity = d.severity;
        l.id = messageName(d.msg);
        l.message = d.text;
        if (d.range.begin.valid()) l.range = locate(sm_, d.range);
        if (d.suggestion && d.suggestion->range.begin.valid())
            l.suggestion =
                LocatedDiagnostic::Fix{d.suggestion->replacement, locate(sm_, d.suggestion->range)};
        l.rendered = render(d);
        out.push_back(std::move(l));
    };
    for (const Diagnostic& d : diags_) add(d);
    if (std::optional<Diagnostic> more = droppedNote()) add(*more);
    return out;
}

void internalError(const char* file, int line, const std::string& what) {
    throw InternalError(fmt::format("internal compiler error at {}:{}: {}", file, line, what));
}

} // namespace moire
