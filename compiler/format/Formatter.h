// `moire fmt`: the canonical layout of a .moire file (docs/formatting.md).
//
// The formatter reads a file with the compiler's own lexer and parser, so that it can never
// accept what `moire check` refuses, and lays out the same tokens again: every comment stays
// where it was, and the formatted file parses to the same tree and the same literal table
// (the same kernel), which formatSource checks before it answers.
#pragma once

#include <string>
#include <string_view>

namespace moire::format {

struct FormatResult {
    bool ok = false;
    std::string text;        // the formatted file, when ok
    std::string diagnostics; // when not ok: rendered as `moire check` renders them
};

// Formats one file. `fileName` names it in diagnostics; a file directly in a folder named
// stdlib is read as a standard-library module, which may declare
// builtin families. A file that does not parse is not formatted: ok is false and
// `diagnostics` holds the errors `moire check` prints for it.
FormatResult formatSource(std::string_view fileName, std::string_view text);

} // namespace moire::format
