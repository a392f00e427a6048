// Source text and positions. Every AST node and IR instruction that came from user text
// carries a SourceLoc so that any later stage can point back at the line that caused it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace moire {

// A position in some source file: a file id (index into SourceManager) and a byte offset.
struct SourceLoc {
    uint32_t file = UINT32_MAX;
    uint32_t offset = 0;
    bool valid() const { return file != UINT32_MAX; }
};

// A span: a location plus a length in bytes (for the caret underline).
struct SourceRange {
    SourceLoc begin;
    uint32_t length = 1;
};

// The length in bytes (1 to 4) of the well-formed UTF-8 character at text[i], with its code
// point in `cp`; 0 when the bytes there are not UTF-8 (overlong, surrogate, cut short...).
size_t decodeUtf8(std::string_view text, size_t i, uint32_t& cp);

struct LineCol {
    uint32_t line = 0;   // 1-based
    uint32_t column = 0; // 1-based, counted in characters (a byte that is not UTF-8 counts as one)
};

class SourceFile {
  public:
    SourceFile(std::string path, std::string text, bool isStdlib);

    const std::string& path() const { return path_; }
    const std::string& text() const { return text_; }
    bool isStdlib() const { return isStdlib_; }

    LineCol lineCol(uint32_t offset) const;
    // The full text of the line holding `offset`, without its newline.
    std::string_view lineText(uint32_t offset) const;
    uint32_t lineStart(uint32_t offset) const;

  private:
    std::string path_;
    std::string text_;
    bool isStdlib_;
    std::vector<uint32_t> lineStarts_;
};

class SourceManager {
  public:
    uint32_t add(std::string path, std::string text, bool isStdlib = false);
    const SourceFile& file(uint32_t id) const { return *files_.at(id); }
    uint32_t size() const { return static_cast<uint32_t>(files_.size()); }

  private:
    std::vector<std::unique_ptr<SourceFile>> files_;
};

} // namespace moire
