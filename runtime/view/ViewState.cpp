#include "runtime/view/ViewState.h"

#include "compiler/Compile.h"
#include "runtime/FrameEval.h"
#include "runtime/output/ImageIO.h"
#include "runtime/output/OutputFile.h"
#include "runtime/TextFile.h"
#include "runtime/view/ParamWriteBack.h"
#include "runtime/view/Placement.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace moire::view {

namespace {

const std::string& sourceOf(const SceneProgram& program) {
    return program.sources->file(program.userModule().file).text();
}

// The frame with the panel's values: a parameter may move the camera or resize the scene.
bool frameAt(const LiveProgram* build, const ParamSet& params, double time, FrameValues& fv) {
    if (!build) return false;
    std::vector<double> literals = build->program->literals;
    applyParams(build->program->parameters, params, literals);
    FrameRequest req;
    req.time = time;
    req.literals = &literals;
    std::string diags;
    return evaluateFrame(*build->program, req, fv, diags);
}

} // namespace

// --- The build ------------------------------------------------------------------------------

void ViewState::adopt(std::shared_ptr<const LiveProgram> build) {
    std::vector<std::string> names;
    for (const sema::CheckedLayer& l : build->program->checked.layers)
        names.push_back(l.decl->name);
    ViewAdjust next = view_;
    next.layers.clear();
    int selected = -1;
    for (int j = 0; j < static_cast<int>(names.size()); ++j) {
        int from = -1;
        for (int i = 0; i < static_cast<int>(names_.size()) && from < 0; ++i)
            if (names[j].empty() ? (i == j && names_[i].empty()) : names_[i] == names[j]) from = i;
        if (from < 0) continue;
        if (!view_.layer(from).identity()) next.layerRef(j) = view_.layer(from);
        if (from == selected_) selected = j;
    }
    view_ = std::move(next);
    selected_ = selected;
    names_ = std::move(names);
    params_ = build_ ? carryParams(build_->program->parameters, params_, sourceOf(*build_->program),
                                   build->program->parameters, sourceOf(*build->program))
                     : ParamSet(build->program->parameters.size());
    build_ = std::move(build);
    pickWanted_ = 0; // an answer about the old build would name its layers
    changed(false);
}

void ViewState::reloaded(const BuildResult& result) {
    redraw_ = true;
    if (!result.good()) {
        buildError_ = result.diagnostics; // the last good build stays on screen under them
        return;
    }
    // The text `w` wrote holds the view's adjustments: they are the scene's now.
    if (placedText_ && sourceOf(*result.build->program) == *placedText_) view_.reset();
    placedText_.reset();
    adopt(result.build);
    buildError_.clear();
}

std::optional<std::pair<int, int>> ViewState::sceneSize(Clock::time_point now) const {
    FrameValues fv;
    if (!frameAt(build_.get(), params_, timeNow(now), fv)) return std::nullopt;
    return std::make_pair(fv.width, fv.height);
}

SceneCamera ViewState::sceneCamera(Clock::time_point now) {
    FrameValues fv;
    if (frameAt(build_.get(), params_, timeNow(now), fv)) camera_ = SceneCamera::from(fv);
    return camera_;
}

// --- The view -------------------------------------------------------------------------------

void ViewState::select(int layer) {
    selected_ = layer >= 0 && layer < numLayers() ? layer : -1;
    pickWanted_ = 0;
    redraw_ = true;
}

sema::ViewMode ViewState::shownView() const {
    return build_ ? build_->program->view : viewOverride_.value_or(sema::ViewMode::Pattern);
}

void ViewState::toggleEnvelope() {
    viewOverride_ = shownView() == sema::ViewMode::Envelope ? sema::ViewMode::Pattern
                                                            : sema::ViewMode::Envelope;
}

void ViewState::toggleRatio() {
    viewOverride_ =
        shownView() == sema::ViewMode::Ratio ? sema::ViewMode::Pattern : sema::ViewMode::Ratio;
}

bool ViewState::shownOverlay() const {
    return build_ ? build_->program->overlay : overlayOverride_.value_or(false);
}

void ViewState::toggleOverlay() {
    overlayOverride_ = !shownOverlay();
}

void ViewState::resetView() {
    view_.reset();
    changed(false);
}

void ViewState::resize(int width, int height) {
    if (width == width_ && height == height_) return;
    width_ = width, height_ = height;
    changed(true); // resizing by hand is a gesture: previews while it lasts
}

// --- Gestures -------------------------------------------------------------------------------

void ViewState::press(int button, Vec2 at) {
    if (drag_ >= 0) return;
    drag_ = button;
    pressAt_ = lastAt_ = at;
    moved_ = false;
}

void ViewState::cursorMoved(Vec2 at, bool turn, double pixelsPerUnit, Clock::time_point now) {
    if (drag_ < 0 || !build_) return;
    if (!moved_) {
        if (std::hypot(at.x - pressAt_.x, at.y - pressAt_.y) < kDragThreshold * pixelsPerUnit)
            return;
        moved_ = true;
    }
    const SceneCamera cam = sceneCamera(now);
    if (drag_ == kPrimaryButton && selected_ >= 0) {
        if (turn)
            turnLayer(cam, view_, width_, height_, selected_, lastAt_, at);
        else
            moveLayer(cam, view_, width_, height_, selected_, lastAt_, at);
    } else {
        panDrag(cam, view_, width_, height_, lastAt_, at);
    }
    lastAt_ = at;
    changed(true);
}

std::optional<PickRequest> ViewState::release(int button, Clock::time_point now) {
    if (button != drag_) return std::nullopt;
    drag_ = -1;
    // A click (a press that never became a drag) on a stroke selects its layer.
    if (moved_ || button != kPrimaryButton || !build_) return std::nullopt;
    PickRequest r;
    r.picture = job(now);
    r.at = pressAt_;
    r.tolerance = kPickTolerance;
    r.id = pickWanted_ = ++picks_;
    return r;
}

void ViewState::picked(const PickResult& result) {
    if (result.id == 0 || result.id != pickWanted_ || result.build != build_) return;
    pickWanted_ = 0;
    if (result.ok) select(result.layer);
}

void ViewState::scroll(double dy, Vec2 at, Clock::time_point now) {
    if (!build_ || dy == 0.0) return;
    zoomAbout(sceneCamera(now), view_, width_, height_, at, std::pow(kWheelZoom, dy));
    changed(true);
}

// --- The clock ------------------------------------------------------------------------------

void ViewState::togglePlay(Clock::time_point now) {
    if (clock_.playing())
        clock_.pause(now);
    else
        clock_.play(now);
    redraw_ = true; // the status line says so
}

void ViewState::stepFrames(int frames, Clock::time_point now) {
    clock_.step(frames * kFrameStep, now);
    redraw_ = true;
    changed(true);
}

void ViewState::skip(double dt, Clock::time_point now) {
    clock_.set(timeNow(now) + dt, now);
    changed(true);
}

// --- Frames ---------------------------------------------------------------------------------

void ViewState::changed(bool interactive) {
    ++version_;
    interactive_ = interactive_ || interactive;
}

RenderJob ViewState::job(Clock::time_point now) const {
    RenderJob j;
    j.build = build_;
    j.view = view_;
    j.time = timeNow(now);
    j.width = width_;
    j.height = height_;
    j.interactive = interactive_;
    j.version = version_;
    j.params = params_;
    return j;
}

void ViewState::submitted(const RenderJob& job) {
    clock_.asked(job.time);
    interactive_ = false;
}

std::string ViewState::statusLine(Clock::time_point now, const RenderedFrame* shown,
                                  double lastFullMs, const std::string& backend) const {
    std::string s = fmt::format("t={:.3f}", shown ? shown->time : timeNow(now));
    if (!clock_.playing()) s += "  paused";
    if (selected_ >= 0) {
        s += fmt::format("  layer {}", selected_ + 1);
        if (!names_[selected_].empty()) s += " " + names_[selected_];
    }
    if (shown && shown->divisor > 1) s += "  preview";
    return s + fmt::format("  {:.1f} ms  {}", lastFullMs, backend);
}

// --- The placement --------------------------------------------------------------------------

std::string ViewState::placementReport(Clock::time_point now) const {
    if (!build_) return {};
    return fmt::format("// placement at t = {:.3f} s: set these in the scene's blocks (w writes "
                       "them into the file)\n{}",
                       timeNow(now), placementText(*build_->program, view_));
}

std::string ViewState::unwritable(const std::string& path) const {
    // The file must still be the text on screen: a save with errors, or one not yet
    // reloaded, is the user's newer work, never to be replaced by an older text.
    if (!buildError_.empty()) return "the file has errors; fix them first";
    std::string now, why;
    if (!readWholeFile(path, now, why)) return why;
    if (now != sourceOf(*build_->program))
        return "the file has changed since it was loaded; try again";
    return {};
}

PlacementWrite ViewState::writePlacement(const std::string& path) {
    auto fail = [](std::string why) { return PlacementWrite{false, std::move(why)}; };
    if (!build_) return {}; // nothing on screen to place
    if (path.empty()) return fail("the default scene has no file (p prints the placement)");
    if (std::string why = unwritable(path); !why.empty()) return fail(why);
    const std::string& loaded = sourceOf(*build_->program);
    std::string why;
    std::string placed;
    if (!placedSource(*build_->program, view_, placed, why)) return fail(why);
    if (placed == loaded) return {true, "moire: the scene already has this placement"};
    try {
        writeFileAtomically(path, placed.data(), placed.size());
    } catch (const IoError& e) {
        return fail(e.what());
    }
    placedText_ = placed;
    return {true, fmt::format("moire: wrote the placement into {}", path)};
}

// --- The parameters -------------------------------------------------------------------------

void ViewState::setParam(int param, const ParamValue& value, bool interactive) {
    if (param < 0 || param >= static_cast<int>(params_.size())) return;
    if (params_[param] == value) return;
    params_[param] = value;
    changed(interactive);
}

void ViewState::resetParams() {
    if (std::none_of(params_.begin(), params_.end(), [](const auto& v) { return v.has_value(); }))
        return;
    params_.assign(params_.size(), std::nullopt);
    changed(false);
}

PlacementWrite ViewState::writeParams(const std::string& path) {
    auto fail = [](std::string why) { return PlacementWrite{false, std::move(why)}; };
    if (!build_) return {};
    if (path.empty()) return fail("the default scene has no file");
    if (std::string why = unwritable(path); !why.empty()) return fail(why);
    const SceneProgram& program = *build_->program;
    ParamWriteBack w = writeBackParameters(sourceOf(program), program.userModule().file,
                                           program.parameters, params_);
    std::string message;
    if (!w.written.empty()) {
        try {
            writeFileAtomically(path, w.text.data(), w.text.size());
        } catch (const IoError& e) {
            return fail(e.what());
        }
        message = fmt::format("moire: wrote {} into {}", fmt::join(w.written, ", "), path);
    } else {
        message = "moire: the file already has these values";
    }
    for (const std::string& s : w.skipped) message += fmt::format("\nmoire: kept {}", s);
    return {true, message};
}

} // namespace moire::view
