// `moire export`: a scene as one self-contained HTML page that draws it live with WebGL2,
// its clock and parameters under the picture (runtime/export/PiecePage.h, docs/export.md).
#pragma once

#include "runtime/cli/Commands.h"

#include <CLI/CLI.hpp>
#include <string>

namespace moire::cli {

struct ExportArgs {
    std::string scene;  // empty: the embedded default scene
    std::string output; // empty: <scene stem>.html; "-": standard output
    std::string size;   // "WxH", empty: the scene's
    double time = 0.0;  // the clock when the page opens
    bool paused = false;
    Verbosity verbosity;
};

// Declares the subcommand and its options on `app`.
CLI::App* addExportCommand(CLI::App& app, ExportArgs& args);
int exportPiece(const ExportArgs& args);

} // namespace moire::cli
