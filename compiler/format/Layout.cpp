#include "compiler/format/Layout.h"

#include <vector>

namespace moire::format {

namespace {
bool endsOperand(Tok k) {
    return k == Tok::Number || k == Tok::Color || k == Tok::Ident || k == Tok::RParen;
}
bool isBinaryOperator(Tok k) {
    return k == Tok::Plus || k == Tok::Minus || k == Tok::Star || k == Tok::Slash ||
           k == Tok::Caret;
}
} // namespace

std::string Layout::format() {
    size_t k = 0;
    while (t_[k].kind != Tok::End) k = decl(k);
    gap(k, 0); // comments after the last declaration
    return w_.finish();
}

bool Layout::gap(size_t k, int indent) {
    bool ownLine = false;
    const std::vector<GapComment>& comments = t_.comments();
    for (size_t c = t_[k].firstComment; c < t_[k].endComment; ++c) {
        const GapComment& g = comments[c];
        if (g.linesBefore == 0 && w_.lineOpen()) {
            w_.put(g.text, true); // a comment after code stays at the end of its line
        } else {
            w_.newline();
            if (g.linesBefore >= 2) w_.blank();
            w_.indent = indent;
            w_.put(g.text, false);
            ownLine = true;
        }
        if (!g.block) w_.requireBreak();
    }
    return ownLine;
}

void Layout::startItem(size_t k, int indent) {
    gap(k, indent);
    w_.newline();
    if (t_[k].linesBefore >= 2) w_.blank();
    w_.indent = indent;
}

void Layout::dropSeparator(size_t k, int indent) {
    gap(k, indent);
}

size_t Layout::decl(size_t k) {
    size_t j = k;
    if (t_.isWord(j, "builtin")) ++j;
    std::string_view keyword = t_[j].spelling;
    ++j;
    bool named = keyword == "field" || keyword == "family" || keyword == "timing" ||
                 keyword == "easing" || keyword == "param" ||
                 (keyword == "layer" && t_[j].kind == Tok::Ident);
    if (named) ++j;
    if (keyword == "family" && t_[j].kind == Tok::LParen) j = t_[j].match + 1;
    startItem(k, 0);
    if (t_[j].kind == Tok::Assign) { // field, easing, param, family name(...) = phase
        size_t e = exprEnd(j + 1);
        if (keyword == "param") e = paramTail(e);
        run(k, e, 0, false);
        if (t_[e].kind == Tok::Semi) dropSeparator(e++, 0);
        return e;
    }
    run(k, j, 0, false);
    if (t_[j].kind != Tok::LBrace) return j; // builtin family: no body
    block(j, 0);
    return t_[j].match + 1;
}

size_t Layout::exprEnd(size_t k) const {
    // The grammar's expression, read only as far as where it ends (the file parses).
    for (;;) {
        while (t_[k].kind == Tok::Plus || t_[k].kind == Tok::Minus) ++k;
        if (t_[k].kind == Tok::Ident && t_[k + 1].kind == Tok::LParen)
            k = t_[k + 1].match + 1;
        else if (t_[k].kind == Tok::LParen)
            k = t_[k].match + 1;
        else if (t_[k].kind != Tok::End)
            ++k;
        if (!isBinaryOperator(t_[k].kind)) return k;
        ++k;
    }
}

size_t Layout::paramTail(size_t k) {
    if (t_.isWord(k, "in")) {
        tailWords_.insert(k);
        k = exprEnd(k + 1);
        if (t_[k].kind == Tok::DotDot) k = exprEnd(k + 1);
    }
    if (t_.isWord(k, "step")) {
        tailWords_.insert(k);
        k = exprEnd(k + 1);
    }
    if (t_.isWord(k, "unit")) k += 2;
    return k;
}

size_t Layout::itemEnd(size_t k) const {
    if (t_.isWord(k, "let") && t_[k + 1].kind == Tok::Ident) ++k;
    return exprEnd(k + 2); // past the name and '='
}

bool Layout::blockOnOneLine(size_t open, int indent) {
    size_t close = t_[open].match;
    // Kept on one line when written on one line (an empty block always), without comments.
    if (t_.commentsBetween(open, close) || (open + 1 < close && !t_.sameLine(open, close)))
        return false;
    Writer::Mark m = w_.mark();
    w_.indent = indent + kIndent;
    w_.put("{", true);
    for (size_t k = open + 1; k < close;) {
        size_t e = itemEnd(k);
        run(k, e, indent + kIndent, true);
        if (t_[e].kind == Tok::Semi || t_[e].kind == Tok::Comma) ++e;
        if (e < close) w_.put(";", false);
        k = e;
    }
    w_.put("}", open + 1 < close);
    if (w_.linesEnded() == m.lines && w_.column() <= Writer::kWidth) return true;
    w_.reset(m);
    return false;
}

void Layout::block(size_t open, int indent) {
    size_t close = t_[open].match;
    int inner = indent + kIndent;
    w_.indent = inner;
    gap(open, inner);
    if (blockOnOneLine(open, indent)) return;
    w_.put("{", true);
    for (size_t k = open + 1; k < close;) {
        startItem(k, inner);
        size_t e = itemEnd(k);
        run(k, e, inner, false);
        if (t_[e].kind == Tok::Semi || t_[e].kind == Tok::Comma) dropSeparator(e++, inner);
        k = e;
    }
    gap(close, inner);
    w_.newline();
    w_.indent = indent;
    w_.put("}", false);
}

bool Layout::isSign(size_t k) const {
    return (t_[k].kind == Tok::Plus || t_[k].kind == Tok::Minus) && k > 0 &&
           (!endsOperand(t_[k - 1].kind) || tailWords_.count(k - 1));
}

bool Layout::spaceBefore(size_t k) const {
    Tok prev = t_[k - 1].kind, cur = t_[k].kind;
    if (cur == Tok::RParen || cur == Tok::Comma || prev == Tok::LParen) return false;
    if (cur == Tok::Caret || prev == Tok::Caret) return false;  // x^2, as on paper
    if (isSign(k - 1)) return false;                            // -x
    if (cur == Tok::LParen && prev == Tok::Ident) return false; // a call: f(x)
    return true;
}

void Layout::run(size_t b, size_t e, int indent, bool spaceFirst) {
    // An open parenthesis: where a line broken inside it continues, and the indentation of
    // the line it is on (for a ')' that begins a line).
    struct Open {
        int align, lineIndent;
    };
    std::vector<Open> opens;
    int base = indent + kIndent; // where a line broken outside parentheses continues
    bool inValue = false, valueStarts = false;
    for (size_t k = b; k < e; ++k) {
        Tok kind = t_[k].kind;
        if (k > b) {
            int cont = opens.empty()         ? base
                       : kind == Tok::RParen ? opens.back().lineIndent
                                             : opens.back().align;
            gap(k, cont);
            // A line that begins with an operator begins that much to the left, so that the
            // operands line up: the standard library's long fields read as columns.
            w_.indent = cont;
            if (isBinaryOperator(kind) && !isSign(k) && cont >= 2) w_.indent = cont - 2;
            // Line breaks are the writer's inside parentheses and values: kept as written.
            if ((inValue || !opens.empty()) && t_[k].linesBefore > 0) w_.newline();
        }
        w_.put(t_[k].spelling, k > b ? spaceBefore(k) : spaceFirst);
        if (valueStarts) {
            base = w_.column() - Writer::width(t_[k].spelling);
            valueStarts = false;
        }
        if (kind == Tok::Assign && opens.empty() && !inValue) {
            inValue = valueStarts = true;
        } else if (kind == Tok::LParen) {
            bool broken = t_[k + 1].gapBreak;
            opens.push_back({broken ? w_.lineIndent() + kIndent : w_.column(), w_.lineIndent()});
        } else if (kind == Tok::RParen && !opens.empty()) {
            opens.pop_back();
        }
    }
}

} // namespace moire::format
