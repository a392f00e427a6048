#include "compiler/diag/Diagnostics.h"

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

const char* messageTemplate(Msg m) { return kMessages[static_cast<int>(m)].text; }
const char* messageName(Msg m) { return kMessages[static_cast<int>(m)].name; }
int messageCount() { return static_cast<int>(sizeof(kMessages) / sizeof(kMessages[0])); }

void DiagEngine::report(Severity s, SourceRange at, Msg m, std::string text) {
    if (s == Severity::Error) {
        if (errorCount_ >= kMaxErrors) return;
        ++errorCount_;
    }
    diags_.push_back(Diagnostic{s, m, at, std::move(text)});
}

std::string DiagEngine::render(const Diagnostic& d) const {
    const char* kind = d.severity == Severity::Error ? "error" : "note";
    if (!d.range.begin.valid()) return fmt::format("moire: {}: {}\n", kind, d.text);
    const SourceFile& f = sm_.file(d.range.begin.file);
    LineCol lc = f.lineCol(d.range.begin.offset);
    std::string out = fmt::format("{}:{}:{}: {}: {}\n", f.path(), lc.line, lc.column, kind, d.text);

    std::string_view line = f.lineText(d.range.begin.offset);
    std::string gutter = fmt::format("{:>5}", lc.line);
    out += fmt::format("{} | {}\n", gutter, line);
    // The caret line copies tabs from the source so it stays aligned under any tab width.
    std::string marks;
    uint32_t lineStart = f.lineStart(d.range.begin.offset);
    for (uint32_t i = lineStart; i < d.range.begin.offset && i - lineStart < line.size(); ++i) {
        unsigned char c = static_cast<unsigned char>(f.text()[i]);
        if ((c & 0xC0) == 0x80) continue;
        marks += c == '\t' ? '\t' : ' ';
    }
    marks += '^';
    uint32_t avail = static_cast<uint32_t>(line.size()) -
                     std::min<uint32_t>(static_cast<uint32_t>(line.size()),
                                        d.range.begin.offset - lineStart + 1);
    uint32_t tildes = std::min(d.range.length > 0 ? d.range.length - 1 : 0, avail);
    marks.append(tildes, '~');
    out += fmt::format("{} | {}\n", std::string(gutter.size(), ' '), marks);
    return out;
}

std::string DiagEngine::render() const {
    std::string out;
    for (const Diagnostic& d : diags_) out += render(d);
    return out;
}

void internalError(const char* file, int line, const std::string& what) {
    throw InternalError(fmt::format("internal compiler error at {}:{}: {}", file, line, what));
}

} // namespace moire
