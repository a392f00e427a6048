// The values of each layer the frame checks before drawing them (ValueCheck): those the float
// renderers could not draw (docs/language.md, "Limits"), each output as one frame setting.
#pragma once

#include "compiler/lower/SceneContext.h"

#include <set>
#include <utility>
#include <vector>

namespace moire::lower {

class ValueChecks {
  public:
    explicit ValueChecks(SceneContext& ctx) : ctx_(ctx) {}

    // Records the values of `layer` to check: its properties and its families' arguments.
    void layer(const sema::CheckedLayer& layer);
    // Records the scene's params: each one's value, and its range when it has one.
    void params(const sema::CheckedScene& scene);
    // Outputs every recorded value as a setting after the layout's others, in order, then the
    // params' values.
    void output(OutputLayout& layout);

  private:
    // Records `e` (each component of a vector) for the frame to check against `rule`.
    void check(const ast::Expr& e, ValueCheck::Rule rule, const std::string& name);

    SceneContext& ctx_;
    std::vector<std::pair<ir::ValueId, ValueCheck>> checks_;
    std::set<std::pair<const ast::Expr*, ValueCheck::Rule>> checked_;
    std::vector<Vals> params_;
};

} // namespace moire::lower
