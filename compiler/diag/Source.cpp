#include "compiler/diag/Source.h"

#include <algorithm>

namespace moire {

SourceFile::SourceFile(std::string path, std::string text, bool isStdlib)
    : path_(std::move(path)), text_(std::move(text)), isStdlib_(isStdlib) {
    lineStarts_.push_back(0);
    for (uint32_t i = 0; i < text_.size(); ++i)
        if (text_[i] == '\n') lineStarts_.push_back(i + 1);
}

uint32_t SourceFile::lineStart(uint32_t offset) const {
    auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset);
    return *(it - 1);
}

size_t decodeUtf8(std::string_view s, size_t i, uint32_t& cp) {
    auto b = [&](size_t k) { return static_cast<unsigned char>(s[i + k]); };
    if (i >= s.size()) return 0;
    unsigned char c = b(0);
    if (c < 0x80) {
        cp = c;
        return 1;
    }
    size_t n = c >= 0xF0 && c <= 0xF4  ? 4
               : c >= 0xE0 && c < 0xF0 ? 3
               : c >= 0xC2 && c < 0xE0 ? 2
                                       : 0;
    if (n == 0 || i + n > s.size()) return 0;
    uint32_t v = c & (0x7F >> n);
    for (size_t k = 1; k < n; ++k) {
        if ((b(k) & 0xC0) != 0x80) return 0;
        v = (v << 6) | (b(k) & 0x3F);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not UTF-8.
    static constexpr uint32_t kMin[] = {0, 0, 0x80, 0x800, 0x10000};
    if (v < kMin[n] || (v >= 0xD800 && v <= 0xDFFF) || v > 0x10FFFF) return 0;
    cp = v;
    return n;
}

LineCol SourceFile::lineCol(uint32_t offset) const {
    offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text_.size()));
    auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset);
    uint32_t line = static_cast<uint32_t>(it - lineStarts_.begin());
    uint32_t start = *(it - 1);
    // Columns count characters, not bytes; the diagnostic renderer walks lines the same way,
    // so the caret sits under the column reported.
    uint32_t column = 1;
    for (uint32_t i = start; i < offset; ++column) {
        uint32_t cp = 0;
        size_t n = decodeUtf8(text_, i, cp);
        i += static_cast<uint32_t>(n ? n : 1);
    }
    return {line, column};
}

std::string_view SourceFile::lineText(uint32_t offset) const {
    uint32_t start = lineStart(std::min<uint32_t>(offset, static_cast<uint32_t>(text_.size())));
    uint32_t end = start;
    while (end < text_.size() && text_[end] != '\n' && text_[end] != '\r') ++end;
    return std::string_view(text_).substr(start, end - start);
}

uint32_t SourceManager::add(std::string path, std::string text, bool isStdlib) {
    files_.push_back(std::make_unique<SourceFile>(std::move(path), std::move(text), isStdlib));
    return static_cast<uint32_t>(files_.size() - 1);
}

} // namespace moire
