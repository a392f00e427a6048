// The compiler's entry point: source text in, frame program and pixel kernel out.
// Compile.cpp reads as the ordered list of stages.
#pragma once

#include "compiler/Defines.h"
#include "compiler/diag/Diagnostics.h"
#include "compiler/ir/IR.h"
#include "compiler/lower/LowerScene.h"
#include "compiler/Parameters.h"
#include "compiler/parse/Ast.h"
#include "compiler/sema/Sema.h"
#include "compiler/sema/Symbols.h"

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace moire {

struct CompileOptions {
    // Where the camera's inputs come from: the scene (Render), a probe point in literal
    // slots (Probe: SceneProgram::probeSlot), or the viewer's pan, zoom and layer motions in
    // literal slots (Interactive: SceneProgram::viewSlot). See lower::LowerMode.
    using Mode = lower::LowerMode;
    Mode mode = Mode::Render;
    bool layerFields = false; // the kernel also outputs each layer's index, distance and gradient
    bool tally = false;       // count the walking solver's radius evaluations (interpreter)
    // The view and the envelope's settings, replacing the scene's when set (sema/Views.h).
    std::optional<sema::ViewMode> view = std::nullopt;
    std::optional<double> envelopeGain = std::nullopt, envelopeTaps = std::nullopt;
    std::optional<bool> overlay = std::nullopt;            // the fringe overlay
    std::optional<sema::FilterMode> filter = std::nullopt; // the stroke filter (docs/filtering.md)
    // `moire print`: only this layer, over a transparent paper (lower::LowerOptions::separate),
    // and the pixel's world size set by FrameRequest::pixelSize (SceneProgram::pixelSlot).
    std::optional<int> separateLayer = std::nullopt;
    bool pixelSize = false;
    // For the experiments only (experiments/, bench/): the walking solver's variant and the
    // stroke floor (lower::LowerOptions::walking, strokeFloor).
    lower::WalkingVariant walking = {};
    bool strokeFloor = true;
    // `-D` values: a param's default or a named layer's property replaced before checking.
    Defines defines = {};
    // When set, each stage appends its name and wall-clock seconds (bench/compile_bench).
    std::vector<std::pair<std::string, double>>* stageSeconds = nullptr;
};

// A compiled scene, with every intermediate stage kept for `moire compile --dump`.
struct SceneProgram {
    std::unique_ptr<SourceManager> sources;
    std::vector<std::unique_ptr<ast::Module>> modules; // standard library first, the scene last
    sema::CheckedScene checked;
    std::vector<double> literals;      // the scene's literal table (values of its numbers)
    std::vector<Parameter> parameters; // the scene's `param`s, in declaration order

    ir::Function lowered; // the scene function, simplified, before differentiation
    ir::Function derived; // after forward-mode AD and simplification
    ir::Function frame;   // per-frame program: literals and clock -> uniforms, settings
    ir::Function kernel;  // per-pixel program: uniforms, pixel -> outputs
    lower::OutputLayout layout;
    int numUniforms = 0;
    uint64_t kernelHash = 0; // structure only: unchanged when only numbers change
    int probeSlot = -1;      // in Mode::Probe: the literal slots of the probe point
    int viewSlot = -1;       // in Mode::Interactive: the first of lower::ViewSlots' slots
    int pixelSlot = -1;      // with CompileOptions::pixelSize: the pixel's world size
    sema::ViewMode view = sema::ViewMode::Pattern; // the view the kernel draws
    bool overlay = false;                          // and whether the fringe overlay is on it

    const ast::Module& userModule() const { return *modules.back(); }
};

struct CompileResult {
    std::unique_ptr<SceneProgram> program; // null when the scene has errors
    std::string diagnostics;               // rendered file:line:col diagnostics
    // The same diagnostics one by one (severity, place, message id, suggestion), for tools.
    std::vector<LocatedDiagnostic> diagnosticList;

    // For an editor, errors or not: the scene as far as the front end got. When the scene
    // has errors, `partial` holds its sources, its parsed modules and what the checks made
    // of them (annotated where they resolved names), and no IR; when it compiled, `program`.
    std::unique_ptr<SceneProgram> partial;
    const SceneProgram& frontEnd() const { return program ? *program : *partial; }
    // The user's declarations and the references to them (sema/Symbols.h), errors or not.
    sema::SymbolTable symbols;
};

// Compiles `text` (read from `path`, used in diagnostics). User errors come back as
// diagnostics; a bug in moire throws InternalError.
CompileResult compileScene(const std::string& path, std::string text,
                           const CompileOptions& options = {});

// The embedded default scene (path and text).
struct EmbeddedScene {
    std::string path;
    std::string text;
};
EmbeddedScene defaultScene();

} // namespace moire
