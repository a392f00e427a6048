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

LineCol SourceFile::lineCol(uint32_t offset) const {
    offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text_.size()));
    auto it = std::upper_bound(lineStarts_.begin(), lineStarts_.end(), offset);
    uint32_t line = static_cast<uint32_t>(it - lineStarts_.begin());
    uint32_t start = *(it - 1);
    // Columns count code points, not bytes: UTF-8 continuation bytes (10xxxxxx) are skipped.
    uint32_t column = 1;
    for (uint32_t i = start; i < offset; ++i)
        if ((static_cast<unsigned char>(text_[i]) & 0xC0) != 0x80) ++column;
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
