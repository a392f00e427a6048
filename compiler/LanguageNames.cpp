#include "compiler/LanguageNames.h"

#include "compiler/Compile.h"
#include "compiler/lex/Keywords.h"
#include "compiler/sema/Builtins.h"
#include "compiler/sema/Properties.h"
#include "compiler/sema/Views.h"

#include <algorithm>
#include <iterator>

namespace moire {

namespace {

void addOnce(std::vector<std::string>& to, const std::vector<std::string>& names) {
    for (const std::string& n : names)
        if (std::find(to.begin(), to.end(), n) == to.end()) to.push_back(n);
}

} // namespace

LanguageNames languageNames() {
    LanguageNames out;
    out.keywords = declarationKeywords();
    out.keywords.push_back(kLetKeyword);

    out.blocks = {{"scene", sema::propertyNames(sema::sceneProperties())},
                  {"camera", sema::propertyNames(sema::cameraProperties())},
                  {"layer", sema::propertyNames(sema::layerProperties())},
                  {"family", sema::familyBodyPropertyNames()},
                  {"timing", sema::timingPropertyNames()}};
    for (const BlockNames& b : out.blocks) addOnce(out.properties, b.properties);

    // The library as the compiler reads it: an empty scene compiled beside it. What the
    // front end parsed is there whether or not the empty scene itself is complete.
    CompileResult r = compileScene("<names>", "");
    const SceneProgram& front = r.frontEnd();
    for (size_t m = 0; m + 1 < front.modules.size(); ++m)
        for (const ast::DeclPtr& d : front.modules[m]->decls) {
            if (d->kind == ast::DeclKind::Family) {
                FamilyNames f{d->name, {}, d->builtin};
                for (const ast::FamilyParam& p : d->params) f.params.push_back(p.name);
                out.families.push_back(std::move(f));
            } else if (d->kind == ast::DeclKind::Field) {
                out.fields.push_back(d->name);
            } else if (d->kind == ast::DeclKind::Easing) {
                out.easings.push_back(d->name);
            }
        }

    out.functions = sema::builtinFunctions();
    out.functions.push_back(sema::kMorphName);
    for (const std::string& n : sema::builtinNames()) {
        const sema::NameInfo& info = sema::nameInfo(*sema::lookupName(n));
        (info.position || info.time ? out.variables : out.constants).push_back(n);
    }
    out.variables.push_back(sema::kEasingProgressName);
    out.variables.push_back(sema::kSpacingName);

    out.words = sema::timingModeNames();
    for (const sema::ViewName& v : sema::viewNames()) out.words.push_back(v.name);
    for (const char* s : sema::kSwitchNames) out.words.push_back(s);
    for (const char* f : sema::kFilterNames) out.words.push_back(f);
    out.units.assign(std::begin(kUnitNames), std::end(kUnitNames));
    return out;
}

} // namespace moire
