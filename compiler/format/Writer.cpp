#include "compiler/format/Writer.h"

namespace moire::format {

int Writer::width(std::string_view s) {
    int n = 0;
    for (char c : s)
        if ((static_cast<unsigned char>(c) & 0xC0) != 0x80) ++n;
    return n;
}

void Writer::put(std::string_view s, bool space) {
    if (breakPending_) newline();
    if (!lineOpen_) {
        out_.append(static_cast<size_t>(indent), ' ');
        column_ = lineIndent_ = indent;
        lineOpen_ = true;
    } else if (space) {
        out_ += ' ';
        ++column_;
    }
    out_ += s;
    afterOpen_ = s == "{";
    size_t nl = s.rfind('\n');
    if (nl == std::string_view::npos) {
        column_ += width(s);
    } else {
        for (char c : s) lines_ += c == '\n';
        column_ = width(s.substr(nl + 1));
    }
}

void Writer::newline() {
    breakPending_ = false;
    if (!lineOpen_) return;
    out_.erase(out_.find_last_not_of(' ') + 1);
    out_ += '\n';
    ++lines_;
    lineOpen_ = false;
    column_ = 0;
}

void Writer::blank() {
    newline();
    if (out_.empty() || out_.ends_with("\n\n") || afterOpen_) return;
    out_ += '\n';
    ++lines_;
}

void Writer::reset(const Mark& m) {
    out_.resize(m.size);
    lines_ = m.lines;
    column_ = m.column;
    lineIndent_ = m.lineIndent;
    lineOpen_ = m.lineOpen;
    breakPending_ = m.breakPending;
    afterOpen_ = m.afterOpen;
}

std::string Writer::finish() {
    newline();
    return std::move(out_);
}

} // namespace moire::format
