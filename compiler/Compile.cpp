#include "compiler/Compile.h"

#include "compiler/ApplyDefines.h"
#include "compiler/lower/LowerScene.h"
#include "compiler/parse/Parser.h"
#include "compiler/passes/AutoDiff.h"
#include "compiler/passes/Simplify.h"
#include "compiler/passes/SplitFrame.h"
#include "compiler/stdlib/Embedded.h"

#include <chrono>

namespace moire {

namespace {
// Times the stages for CompileOptions::stageSeconds; free when that is not set.
class StageClock {
  public:
    explicit StageClock(std::vector<std::pair<std::string, double>>* out) : out_(out) {}
    void lap(const char* stage) {
        if (!out_) return;
        auto now = std::chrono::steady_clock::now();
        out_->emplace_back(stage, std::chrono::duration<double>(now - last_).count());
        last_ = now;
    }

  private:
    std::vector<std::pair<std::string, double>>* out_;
    std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

bool isLibraryModule(std::string_view path) {
    return path.starts_with("stdlib/") && path.ends_with(".moire");
}
} // namespace

EmbeddedScene defaultScene() {
    for (const embedded::File& f : embedded::files())
        if (std::string_view(f.path) == "examples/drifting_walks.moire")
            return {"<default scene>", std::string(f.text)};
    MOIRE_ICE("the default scene is not embedded");
}

CompileResult compileScene(const std::string& path, std::string text,
                           const CompileOptions& options) {
    auto program = std::make_unique<SceneProgram>();
    program->sources = std::make_unique<SourceManager>();
    SourceManager& sm = *program->sources;
    DiagEngine diags(sm);
    CompileResult result;
    StageClock clock(options.stageSeconds);

    // 1. Parse the standard library, then the scene.
    for (const embedded::File& f : embedded::files()) {
        if (!isLibraryModule(f.path)) continue;
        std::string shown = "<stdlib>/" + std::string(std::string_view(f.path).substr(7));
        uint32_t id = sm.add(shown, std::string(f.text), /*isStdlib=*/true);
        program->modules.push_back(
            std::make_unique<ast::Module>(Parser(sm, id, diags).parseModule()));
    }
    uint32_t userId = sm.add(path, std::move(text));
    program->modules.push_back(
        std::make_unique<ast::Module>(Parser(sm, userId, diags).parseModule()));
    program->literals = program->modules.back()->literals;
    // `-D` values, read from the command line into the scene's module.
    if (!options.defines.empty() && !diags.hasErrors())
        applyDefines(options.defines, sm, *program->modules.back(), program->literals, diags);
    clock.lap("parse");

    // 2. Semantic checks: names, arity, types, units, constness. The symbol table (for an
    // editor) is taken from what the checks resolved, errors or not.
    if (!diags.hasErrors()) {
        std::vector<ast::Module*> modules;
        for (auto& m : program->modules) modules.push_back(m.get());
        program->checked = sema::check(modules, diags);
        clock.lap("check");
    }
    {
        std::vector<const ast::Module*> modules;
        for (auto& m : program->modules) modules.push_back(m.get());
        result.symbols = sema::collectSymbols(modules);
    }
    result.diagnosticList = diags.located();
    if (diags.hasErrors()) {
        result.diagnostics = diags.render();
        result.partial = std::move(program);
        return result;
    }

    // 3. Lower to the scene function, then the ordered IR passes.
    const lower::LowerOptions lowerOptions{.mode = options.mode,
                                           .layerFields = options.layerFields,
                                           .tally = options.tally,
                                           .view = options.view,
                                           .envelopeGain = options.envelopeGain,
                                           .envelopeTaps = options.envelopeTaps,
                                           .overlay = options.overlay,
                                           .filter = options.filter,
                                           .separate = options.separateLayer,
                                           .pixelSlot = options.pixelSize,
                                           .walking = options.walking,
                                           .strokeFloor = options.strokeFloor};
    lower::LoweredScene lowered =
        lower::lowerScene(program->checked, lowerOptions, program->literals);
    // A view that sweeps every layer's index needs each family's phase sample.
    for (int i : lowered.unsweepable) {
        const sema::CheckedLayer& layer = program->checked.layers.at(i);
        const ast::Property* fam = layer.decl->prop("family");
        // The family without a sample: in a morph, the member given by its distance.
        const sema::CheckedFamily* family = layer.family;
        for (const sema::CheckedLayer::Member& m : layer.morph)
            if (m.family && m.family->kind == sema::FamilyKind::Distance) family = m.family;
        std::string what =
            family ? fmt::format("the {} family", family->decl->name) : std::string("this layer");
        diags.error(fam ? fam->value->range : layer.decl->range, Msg::ViewCannotSweep,
                    sema::viewName(lowered.view), what);
    }
    if (diags.hasErrors()) {
        result.diagnostics = diags.render();
        result.diagnosticList = diags.located();
        result.partial = std::move(program);
        return result;
    }
    program->parameters = collectParameters(program->checked);
    program->view = lowered.view;
    program->overlay = lowered.overlay;
    program->layout = std::move(lowered.layout);
    program->probeSlot = lowered.probeSlot;
    program->viewSlot = lowered.viewSlot;
    program->pixelSlot = lowered.pixelSlot;
    clock.lap("lower");
    program->lowered = passes::simplify(lowered.function); // fold, CSE, DCE
    clock.lap("simplify");
    ir::Function derived = passes::autoDiff(program->lowered); // forward-mode AD
    clock.lap("autodiff");
    program->derived = passes::simplify(derived);
    clock.lap("simplify derived");
    passes::FrameSplit split = passes::splitFrame(
        program->derived, program->layout.numKernelOutputs, program->layout.firstCheckSetting());
    // A checked value that depends on the pixel cannot be checked per frame.
    // (A param's value never depends on the pixel: the checks refuse that.)
    for (int s : split.perPixelSettings)
        program->layout.checks.at(s - program->layout.firstCheckSetting()).perPixel = true;
    clock.lap("split frame");
    program->frame = std::move(split.frame);          // per-frame uniforms
    program->kernel = passes::simplify(split.kernel); // per-pixel kernel
    clock.lap("simplify kernel");
    program->numUniforms = split.numUniforms;
    program->kernelHash = ir::structuralHash(program->kernel);
    clock.lap("hash");

    result.diagnostics = diags.render(); // notes, if any
    result.diagnosticList = diags.located();
    result.program = std::move(program);
    return result;
}

} // namespace moire
