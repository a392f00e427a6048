// The protocol's types as the server uses them, and the conversions between the compiler's
// places (byte offsets into a file) and LSP's (0-based line, and a character counted in UTF-16
// code units, the encoding every client supports), and between URIs and the paths the
// compiler names files by.
#pragma once

#include "lsp/JsonRpc.h"

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace moire::lsp {

struct Position {
    uint32_t line = 0, character = 0;
};

// The starts of a text's lines, to turn offsets into positions and back. A line ends at
// "\n" ("\r\n" is a line end whose "\r" is the line's last character, as LSP counts it).
class LineIndex {
  public:
    explicit LineIndex(std::string_view text);
    Position position(uint32_t offset) const;
    // The offset of a position; one past the end of its line (or the text) is clamped to it.
    uint32_t offset(Position p) const;
    uint32_t lineCount() const { return static_cast<uint32_t>(starts_.size()); }

  private:
    std::string_view text_;
    std::vector<uint32_t> starts_;
};

Json toJson(Position p);
Json rangeJson(const LineIndex& index, uint32_t begin, uint32_t end);
Position positionFrom(const Json& j); // {"line", "character"}; throws on a wrong shape

// The stdlib's files, read-only, under this scheme: moire-stdlib:///families.moire.
constexpr std::string_view kStdlibScheme = "moire-stdlib:///";

// file:///a%20b/c.moire -> /a b/c.moire; any other URI is kept whole as the name the
// diagnostics give the document.
std::string uriToPath(std::string_view uri);
std::string pathToUri(std::string_view path);
// The URI of a stdlib file named as diagnostics name it ("<stdlib>/families.moire").
std::string stdlibUri(std::string_view shownPath);
// The embedded text of a stdlib URI, or null when there is no such file.
const std::string_view* stdlibText(std::string_view uri);

} // namespace moire::lsp
