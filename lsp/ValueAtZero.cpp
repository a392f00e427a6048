#include "lsp/ValueAtZero.h"

#include "compiler/backend/interp/Interpreter.h"
#include "compiler/ir/Builder.h"
#include "compiler/lower/LowerExpr.h"
#include "compiler/lower/Timings.h"

namespace moire::lsp {

std::optional<std::vector<double>> valueAtZero(const SceneProgram& program, const ast::Expr& e) {
    if (e.dependsOnPosition || e.type == ast::Type::Error) return std::nullopt;
    bool local = false; // names of a family's or an easing's own
    std::vector<const ast::Expr*> stack{&e};
    while (!stack.empty()) {
        const ast::Expr* x = stack.back();
        stack.pop_back();
        if (x->ref == ast::RefKind::FamilyParam || x->ref == ast::RefKind::Let ||
            x->ref == ast::RefKind::Spacing || x->ref == ast::RefKind::EasingVar ||
            (x->ref == ast::RefKind::Unresolved && x->kind == ast::ExprKind::Name))
            local = true;
        for (const ast::ExprPtr& a : x->args)
            if (a) stack.push_back(a.get());
    }
    if (local) return std::nullopt;
    try {
        ir::Function f;
        f.name = "hover";
        ir::Builder b(f);
        lower::ExprLowering exprs(b);
        lower::TimingLowering timings(b, exprs, program.checked);
        exprs.setTimings([&](const ast::Decl* t) { return timings.progress(t); });
        lower::Frame frame;
        frame.x = b.constF(0);
        frame.y = b.constF(0);
        lower::Vals v = exprs.lower(e, frame);
        for (size_t i = 0; i < v.size(); ++i) b.output(static_cast<int>(i), v[i]);
        f.numOutputs = static_cast<int>(v.size());
        Interpreter interp(f);
        return interp.atPixel({}, 0, 0, 1, 1, 0.0, &program.literals);
    } catch (const std::exception&) {
        return std::nullopt; // the hover goes without the value
    }
}

} // namespace moire::lsp
