// `moire export`: a scene as one self-contained HTML page that draws it live with WebGL2,
// its clock and parameters under the picture (runtime/export/PiecePage.h, docs/export.md).
#pragma once

#include "compiler/Defines.h"
#include "runtime/cli/Commands.h"

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace moire::cli {

struct ExportArgs {
    std::string scene;  // empty: the embedded default scene
    std::string output; // empty: <scene stem>.html; "-": standard output
    std::string size;   // "WxH", empty: the scene's
    double time = 0.0;  // the clock when the page opens
    bool paused = false;
    std::string filter; // --filter point|mean (docs/filtering.md); empty: the scene's
    Defines defines;    // -D: the params' values (and layers' properties) the page starts from
    Verbosity verbosity;
};

// Declares the subcommand and its options on `app` (-D is added by the caller, with the other
// commands', into `rawDefines`).
CLI::App* addExportCommand(CLI::App& app, ExportArgs& args, std::vector<std::string>& rawDefines);
int exportPiece(const ExportArgs& args);

} // namespace moire::cli
