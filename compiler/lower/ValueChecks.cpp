#include "compiler/lower/ValueChecks.h"

#include "compiler/sema/ConstantValue.h"

namespace moire::lower {

using namespace ast;

// Records `e` (each component of a vector) for the frame to check against `rule`.
void ValueChecks::check(const Expr& e, ValueCheck::Rule rule, const std::string& name) {
    // A morph gives one property to every family with that parameter: checked once.
    if (!checked_.insert({&e, rule}).second) return;
    Vals v = ctx_.exprs.lower(e, ctx_.world);
    for (size_t i = 0; i < v.size(); ++i) {
        // A component of a vector written out is located by itself.
        const bool written = e.kind == ExprKind::Vector && e.args.size() == v.size();
        const Expr& at = written ? *e.args[i] : e;
        checks_.push_back(
            {v[i], ValueCheck{rule, "'" + name + "'", at.range, e.type == Type::Angle, false}});
    }
}

// A layer's values that the float renderers could not draw (docs/language.md, "Limits").
void ValueChecks::layer(const sema::CheckedLayer& layer) {
    using R = ValueCheck::Rule;
    static const std::pair<const char*, R> rules[] = {
        {"spacing", R::Spacing},  {"phase", R::Finite},  {"stroke", R::Positive},
        {"opacity", R::Unit},     {"origin", R::Finite}, {"rotation", R::Finite},
        {"offset", R::Finite},    {"turn", R::Finite},   {"gain", R::Finite},
        {"morph_time", R::Finite}};
    for (const auto& [name, rule] : rules)
        if (const Expr* e = layer.prop(name)) check(*e, rule, name);
    std::vector<const sema::CheckedLayer::Member*> members;
    sema::CheckedLayer::Member single{layer.family, layer.args};
    if (layer.morph.empty() && layer.family) members.push_back(&single);
    for (const sema::CheckedLayer::Member& m : layer.morph) members.push_back(&m);
    for (const sema::CheckedLayer::Member* m : members) {
        const Decl& fam = *m->family->decl;
        for (size_t i = 0; i < fam.params.size(); ++i) {
            if (!m->args[i] || fam.params[i].type == Type::Color) continue;
            check(*m->args[i], R::Finite, fam.params[i].name);
        }
        // A polygon family's side count, when a parameter gives it (ngon's `sides`): a
        // fraction or fewer than 3 is no polygon (its phase would not close up).
        const Expr* facets = m->family->facets;
        if (facets && facets->kind == ExprKind::Name && facets->ref == RefKind::FamilyParam) {
            const int p = facets->refIndex;
            const Expr* value = m->args[p] ? m->args[p] : fam.params[p].defaultValue.get();
            if (value) check(*value, R::Sides, fam.params[p].name);
        }
    }
}

void ValueChecks::params(const sema::CheckedScene& scene) {
    for (const Decl* p : scene.params) {
        Vals v = ctx_.exprs.param(*p, ctx_.world);
        params_.push_back(v);
        if (!p->rangeLo) continue;
        std::optional<double> lo = sema::constantValue(*p->rangeLo);
        std::optional<double> hi = sema::constantValue(*p->rangeHi);
        if (!lo || !hi) continue; // reported by the checks
        const Expr& e = *p->value;
        for (size_t i = 0; i < v.size(); ++i) {
            const bool written = e.kind == ExprKind::Vector && e.args.size() == v.size();
            ValueCheck c{ValueCheck::Range, "param '" + p->name + "'",
                         written ? e.args[i]->range : e.range, e.type == Type::Angle, false};
            c.lo = *lo;
            c.hi = *hi;
            checks_.push_back({v[i], std::move(c)});
        }
    }
}

void ValueChecks::output(OutputLayout& layout) {
    for (auto& [value, check] : checks_) {
        ctx_.b.output(layout.numKernelOutputs + layout.numSettings(), value);
        layout.checks.push_back(std::move(check));
    }
    layout.numParameters = static_cast<int>(params_.size());
    for (size_t p = 0; p < params_.size(); ++p)
        for (int i = 0; i < OutputLayout::kParameterWidth; ++i) {
            const size_t c = static_cast<size_t>(i);
            ir::ValueId v = c < params_[p].size() ? params_[p][c] : ctx_.b.constF(0.0);
            ctx_.b.output(
                layout.numKernelOutputs + layout.parameterSetting(static_cast<int>(p)) + i, v);
        }
}

} // namespace moire::lower
