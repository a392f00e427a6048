// The `-D name=value` option shared by render, clip, view, watch and serve.
#pragma once

#include "compiler/Defines.h"

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace moire::cli {

// Adds `-D,--define NAME=VALUE` (repeatable) to `cmd`, collecting the raw arguments in `raw`.
void addDefineOption(CLI::App* cmd, std::vector<std::string>& raw);

// The defines of the command line `argv`, with offsets into the joined command line that
// diagnostics show. An argument that is not NAME=VALUE is a user error: the rendered
// diagnostic goes to `diagnostics` and the function returns false.
bool collectDefines(int argc, const char* const* argv, Defines& out, std::string& diagnostics);

} // namespace moire::cli
