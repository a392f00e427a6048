// `moire print`: a scene at physical size on a sheet of paper, with bleed and printer's marks
// when asked, or with --separate one sheet a layer on a transparent ground (docs/print.md).
#pragma once

#include "compiler/Defines.h"
#include "runtime/cli/Commands.h"

#include <CLI/CLI.hpp>
#include <optional>
#include <string>
#include <vector>

namespace moire::cli {

struct PrintArgs {
    std::string scene;  // empty: the embedded default scene
    std::string output; // empty: <scene stem>.tif
    std::string paper;  // A0..A6, letter, legal, tabloid, or WxH with mm, cm or in
    bool landscape = false, portrait = false;
    double dpi = 0.0;
    double bleed = 0.0; // millimetres
    bool marks = false;
    std::optional<double> scale; // world units per millimetre; unset: fitted to the trim
    bool separate = false;
    double time = 0.0;
    std::string backend = "jit";
    int device = -1;
    std::string depth;
    int threads = 0;
    std::string filter; // --filter point|mean (docs/filtering.md); empty: the scene's
    Verbosity verbosity;
    Defines defines; // -D NAME=VALUE
};

// Declares the subcommand and its options on `app` (-D is added here, into `rawDefines`).
CLI::App* addPrintCommand(CLI::App& app, PrintArgs& args, std::vector<std::string>& rawDefines);
int print(const PrintArgs& args);

// The file of layer `layer`'s separation: OUTPUT's stem, '-', the layer's name, OUTPUT's
// extension, in OUTPUT's directory ("out/sheet.tif", "ink" -> "out/sheet-ink.tif").
std::string separationPath(const std::string& output, const std::string& layer);

} // namespace moire::cli
