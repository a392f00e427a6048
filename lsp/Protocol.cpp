#include "lsp/Protocol.h"

#include "compiler/diag/Source.h"
#include "compiler/stdlib/Embedded.h"

#include <algorithm>
#include <cctype>

namespace moire::lsp {

namespace {

// UTF-16 code units of the text between two offsets. A byte that is not UTF-8 counts as one
// unit, as the compiler counts it as one character.
uint32_t utf16Units(std::string_view text, size_t from, size_t to) {
    uint32_t units = 0;
    for (size_t i = from; i < to;) {
        uint32_t cp = 0;
        size_t n = decodeUtf8(text, i, cp);
        if (n == 0) n = 1;
        units += cp >= 0x10000 && n == 4 ? 2 : 1;
        i += n;
    }
    return units;
}

int hexValue(char c) {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    if (c >= 'A' && c <= 'F') return c - 'A' + 10;
    return -1;
}

} // namespace

LineIndex::LineIndex(std::string_view text) : text_(text) {
    starts_.push_back(0);
    for (size_t i = 0; i < text.size(); ++i)
        if (text[i] == '\n') starts_.push_back(static_cast<uint32_t>(i + 1));
}

Position LineIndex::position(uint32_t offset) const {
    offset = std::min<uint32_t>(offset, static_cast<uint32_t>(text_.size()));
    auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
    uint32_t line = static_cast<uint32_t>(it - starts_.begin()) - 1;
    return {line, utf16Units(text_, starts_[line], offset)};
}

uint32_t LineIndex::offset(Position p) const {
    if (p.line >= starts_.size()) return static_cast<uint32_t>(text_.size());
    size_t i = starts_[p.line];
    size_t end = p.line + 1 < starts_.size() ? starts_[p.line + 1] - 1 : text_.size();
    uint32_t units = 0;
    while (i < end && units < p.character) {
        uint32_t cp = 0;
        size_t n = decodeUtf8(text_, i, cp);
        if (n == 0) n = 1;
        units += cp >= 0x10000 && n == 4 ? 2 : 1;
        i += n;
    }
    return static_cast<uint32_t>(i);
}

Json toJson(Position p) {
    return Json{{"line", p.line}, {"character", p.character}};
}

Json rangeJson(const LineIndex& index, uint32_t begin, uint32_t end) {
    return Json{{"start", toJson(index.position(begin))}, {"end", toJson(index.position(end))}};
}

Position positionFrom(const Json& j) {
    return {j.at("line").get<uint32_t>(), j.at("character").get<uint32_t>()};
}

std::string uriToPath(std::string_view uri) {
    constexpr std::string_view file = "file://";
    if (!uri.starts_with(file)) return std::string(uri);
    std::string_view rest = uri.substr(file.size());
    // file://host/path: a host other than localhost is kept in the name.
    if (rest.starts_with("localhost/")) rest.remove_prefix(9);
    std::string out;
    for (size_t i = 0; i < rest.size(); ++i) {
        if (rest[i] == '%' && i + 2 < rest.size() && hexValue(rest[i + 1]) >= 0 &&
            hexValue(rest[i + 2]) >= 0) {
            out += static_cast<char>(hexValue(rest[i + 1]) * 16 + hexValue(rest[i + 2]));
            i += 2;
        } else {
            out += rest[i];
        }
    }
    return out;
}

std::string pathToUri(std::string_view path) {
    if (!path.starts_with("/")) return std::string(path);
    static const char* hex = "0123456789ABCDEF";
    std::string out = "file://";
    for (unsigned char c : path) {
        if (std::isalnum(c) ||
            std::string_view("/-._~").find(static_cast<char>(c)) != std::string_view::npos) {
            out += static_cast<char>(c);
        } else {
            out += '%';
            out += hex[c >> 4];
            out += hex[c & 15];
        }
    }
    return out;
}

std::string stdlibUri(std::string_view shownPath) {
    constexpr std::string_view prefix = "<stdlib>/";
    if (shownPath.starts_with(prefix)) shownPath.remove_prefix(prefix.size());
    return std::string(kStdlibScheme) + std::string(shownPath);
}

const std::string_view* stdlibText(std::string_view uri) {
    if (!uri.starts_with(kStdlibScheme)) return nullptr;
    std::string path = "stdlib/" + std::string(uri.substr(kStdlibScheme.size()));
    for (const embedded::File& f : embedded::files())
        if (path == f.path) return &f.text;
    return nullptr;
}

} // namespace moire::lsp
