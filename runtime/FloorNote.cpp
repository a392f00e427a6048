#include "runtime/FloorNote.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lower/LayerPipeline.h"
#include "compiler/lower/LowerScene.h"

#include <fmt/format.h>

namespace moire {

std::string strokeFloorNotes(const SceneProgram& program,
                             const std::optional<sema::FilterMode>& filter, double pixelSize) {
    if (!(pixelSize > 0.0) || lower::filterOf(program.checked, filter) != sema::FilterMode::Point)
        return {};
    // The floor's width: twice the thinnest half-width drawn, in world units.
    const double floorWidth = 2.0 * lower::kStrokeFloorPixels * pixelSize;
    DiagEngine diags(*program.sources);
    std::string out;
    for (const sema::CheckedLayer& layer : program.checked.layers) {
        const ast::Expr* stroke = layer.prop("stroke");
        if (!stroke || stroke->kind != ast::ExprKind::Number) continue;
        const double t = stroke->number;
        if (!(t > 0.0 && t < floorWidth)) continue;
        const std::string name =
            layer.decl->name.empty() ? "this layer" : "layer '" + layer.decl->name + "'";
        Diagnostic note;
        note.severity = Severity::Note;
        note.range = stroke->range;
        note.text = fmt::format(
            "the stroke of {}, {:g} wide, is {:.2g} pixels at this size, under the stroke "
            "floor: it is drawn {:.2g} pixels ({:.3g} units) wide, darker than written; "
            "filter = mean keeps the stroke's tone",
            name, t, t / pixelSize, 2.0 * lower::kStrokeFloorPixels, floorWidth);
        out += diags.render(note);
    }
    return out;
}

} // namespace moire
