#include "compiler/ApplyDefines.h"

#include "compiler/diag/Suggest.h"
#include "compiler/parse/Parser.h"

#include <string>

namespace moire {

using namespace ast;

namespace {
SourceRange at(uint32_t file, size_t offset, size_t length) {
    SourceRange r;
    r.begin.file = file;
    r.begin.offset = static_cast<uint32_t>(offset);
    r.length = static_cast<uint32_t>(std::max<size_t>(length, 1));
    return r;
}

std::vector<std::string> namesOf(const Module& m, DeclKind kind) {
    std::vector<std::string> out;
    for (const DeclPtr& d : m.decls)
        if (d->kind == kind && !d->name.empty()) out.push_back(d->name);
    return out;
}

Decl* find(Module& m, DeclKind kind, const std::string& name) {
    for (DeclPtr& d : m.decls)
        if (d->kind == kind && d->name == name) return d.get();
    return nullptr;
}
} // namespace

void applyDefines(const Defines& defines, SourceManager& sm, Module& scene,
                  std::vector<double>& literals, DiagEngine& diags) {
    for (const Define& def : defines.list) {
        // One source per value, cut where the value ends: the lexer reads to the end of its
        // text, and the next argument is not part of this value.
        const size_t end = def.valueOffset + def.value.size();
        const uint32_t file = sm.add("<command line>", defines.commandLine.substr(0, end));
        const size_t dot = def.target.find('.');
        const std::string name = def.target.substr(0, dot);
        Decl* target = nullptr;
        if (dot == std::string::npos) {
            target = find(scene, DeclKind::Param, name);
            if (!target) {
                diags.error(at(file, def.targetOffset, name.size()), Msg::UnknownDefine, "param",
                            name, didYouMean(name, namesOf(scene, DeclKind::Param)));
                continue;
            }
        } else {
            target = find(scene, DeclKind::Layer, name);
            if (!target) {
                diags.error(at(file, def.targetOffset, name.size()), Msg::UnknownDefine, "layer",
                            name, didYouMean(name, namesOf(scene, DeclKind::Layer)));
                continue;
            }
        }
        Parser parser(sm, file, diags, def.valueOffset, static_cast<int>(literals.size()));
        ExprPtr value = parser.parseStandaloneExpr();
        literals.insert(literals.end(), parser.literals().begin(), parser.literals().end());
        if (dot == std::string::npos) {
            if (!target->sceneDefault) target->sceneDefault = std::move(target->value);
            target->value = std::move(value);
            continue;
        }
        // `layer.property`: replaces the property, or adds it; the checks then hold it to the
        // property's rules like one written in the scene (an unknown name included).
        const std::string prop = def.target.substr(dot + 1);
        Property* existing = nullptr;
        for (Property& p : target->props)
            if (p.name == prop) existing = &p;
        if (existing) {
            existing->value = std::move(value);
            continue;
        }
        Property p;
        p.name = prop;
        p.nameRange = at(file, def.targetOffset + dot + 1, prop.size());
        p.value = std::move(value);
        target->props.push_back(std::move(p));
    }
}

} // namespace moire
