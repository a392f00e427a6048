#include "compiler/format/TokenList.h"

#include "compiler/diag/Diagnostics.h"

#include <algorithm>

namespace moire::format {

namespace {
int countLines(std::string_view text, size_t from, size_t to) {
    return to > from ? static_cast<int>(std::count(text.begin() + from, text.begin() + to, '\n'))
                     : 0;
}

std::string normalise(std::string_view text, bool block) {
    std::string s;
    s.reserve(text.size());
    for (size_t i = 0; i < text.size(); ++i) // a CRLF file gives LF lines
        if (!(text[i] == '\r' && i + 1 < text.size() && text[i + 1] == '\n')) s += text[i];
    if (!block) s.erase(s.find_last_not_of(" \t\r\f\v") + 1);
    return s;
}
} // namespace

TokenList::TokenList(const SourceManager& sm, uint32_t fileId) {
    std::string_view text = sm.file(fileId).text();
    DiagEngine quiet(sm); // the parser has reported whatever is wrong already
    Lexer lexer(fileId, text, quiet);
    std::vector<Comment> raw;
    lexer.keepComments(&raw);
    size_t rawSeen = 0;
    size_t prevEnd = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;
    uint32_t line = 0;
    size_t lineCounted = 0; // the offset up to which `line` counts
    std::vector<size_t> open;
    for (;;) {
        Token t = lexer.next();
        FormatToken f;
        f.kind = t.kind;
        f.spelling = text.substr(t.offset, t.length);
        f.firstComment = comments_.size();
        size_t from = prevEnd;
        for (; rawSeen < raw.size(); ++rawSeen) {
            const Comment& c = raw[rawSeen];
            GapComment g;
            g.block = c.block;
            g.text = normalise(text.substr(c.offset, c.length), c.block);
            g.linesBefore = countLines(text, from, c.offset);
            from = c.offset + c.length;
            comments_.push_back(std::move(g));
        }
        f.endComment = comments_.size();
        f.linesBefore = countLines(text, from, t.offset);
        f.gapBreak = countLines(text, prevEnd, t.offset) > 0;
        f.match = tokens_.size();
        if (t.kind == Tok::LParen || t.kind == Tok::LBrace) {
            open.push_back(tokens_.size());
        } else if ((t.kind == Tok::RParen || t.kind == Tok::RBrace) && !open.empty()) {
            f.match = open.back();
            tokens_[open.back()].match = tokens_.size();
            open.pop_back();
        }
        line += countLines(text, lineCounted, t.offset);
        lineCounted = t.offset;
        lineOf_.push_back(line);
        tokens_.push_back(f);
        prevEnd = t.offset + t.length;
        if (t.kind == Tok::End) break;
    }
}

} // namespace moire::format
