#include "compiler/sema/Symbols.h"

#include <algorithm>
#include <map>
#include <tuple>

namespace moire::sema {

using namespace ast;

const char* symbolKindName(SymbolKind k) {
    switch (k) {
    case SymbolKind::Field:
        return "field";
    case SymbolKind::Family:
        return "family";
    case SymbolKind::Timing:
        return "timing";
    case SymbolKind::Easing:
        return "easing";
    case SymbolKind::Layer:
        return "layer";
    case SymbolKind::Param:
        return "parameter";
    case SymbolKind::Let:
        return "let";
    case SymbolKind::SceneParam:
        return "param";
    }
    return "?";
}

namespace {

bool contains(SourceRange r, SourceLoc loc) {
    return r.begin.file == loc.file && loc.offset >= r.begin.offset &&
           loc.offset < r.begin.offset + std::max<uint32_t>(r.length, 1);
}

SymbolKind kindOf(DeclKind k) {
    switch (k) {
    case DeclKind::Field:
        return SymbolKind::Field;
    case DeclKind::Family:
        return SymbolKind::Family;
    case DeclKind::Timing:
        return SymbolKind::Timing;
    case DeclKind::Easing:
        return SymbolKind::Easing;
    case DeclKind::Param:
        return SymbolKind::SceneParam;
    default:
        return SymbolKind::Layer;
    }
}

class Collector {
  public:
    SymbolTable run(const Module& user) {
        for (const DeclPtr& d : user.decls) declare(*d);
        for (const DeclPtr& d : user.decls) {
            walk(d->value.get());
            for (const FamilyParam& p : d->params) walk(p.defaultValue.get());
            for (const Let& l : d->lets) walk(l.value.get());
            for (const Property& p : d->props) walk(p.value.get());
        }
        for (Symbol& s : table_.symbols)
            std::sort(s.references.begin(), s.references.end(),
                      [](SourceRange a, SourceRange b) { return a.begin.offset < b.begin.offset; });
        return std::move(table_);
    }

  private:
    using Key = std::tuple<const Decl*, SymbolKind, int>;

    size_t add(SymbolKind kind, const std::string& name, SourceRange at, const Decl* decl,
               int index) {
        Key key{decl, kind, index};
        auto it = index_.find(key);
        if (it != index_.end()) return it->second;
        table_.symbols.push_back(Symbol{kind, name, at, decl, index, {}});
        return index_[key] = table_.symbols.size() - 1;
    }

    void declare(const Decl& d) {
        if (d.kind == DeclKind::Scene || d.kind == DeclKind::Camera || d.name.empty()) return;
        add(kindOf(d.kind), d.name, d.nameRange, &d, -1);
        for (size_t i = 0; i < d.params.size(); ++i)
            add(SymbolKind::Param, d.params[i].name, d.params[i].nameRange, &d,
                static_cast<int>(i));
        for (size_t i = 0; i < d.lets.size(); ++i)
            add(SymbolKind::Let, d.lets[i].name, d.lets[i].nameRange, &d, static_cast<int>(i));
    }

    void reference(const Expr& e) {
        const Decl* d = e.refDecl;
        if (!d) return;
        size_t s;
        switch (e.ref) {
        case RefKind::Field:
        case RefKind::Param:
        case RefKind::Family:
        case RefKind::Timing:
        case RefKind::Easing:
            s = add(kindOf(d->kind), d->name, d->nameRange, d, -1);
            break;
        case RefKind::FamilyParam:
            s = add(SymbolKind::Param, d->params.at(e.refIndex).name,
                    d->params.at(e.refIndex).nameRange, d, e.refIndex);
            break;
        case RefKind::Let:
            s = add(SymbolKind::Let, d->lets.at(e.refIndex).name, d->lets.at(e.refIndex).nameRange,
                    d, e.refIndex);
            break;
        default:
            return;
        }
        table_.symbols[s].references.push_back(e.opRange); // the name, without parentheses
    }

    // A loop, not recursion: a chain `a + b + c + ...` is as deep as it is long.
    void walk(const Expr* root) {
        std::vector<const Expr*> stack;
        if (root) stack.push_back(root);
        while (!stack.empty()) {
            const Expr* e = stack.back();
            stack.pop_back();
            if (e->kind == ExprKind::Name) reference(*e);
            for (const ExprPtr& a : e->args)
                if (a) stack.push_back(a.get());
        }
    }

    SymbolTable table_;
    std::map<Key, size_t> index_;
};

} // namespace

SymbolTable collectSymbols(const std::vector<const Module*>& modules) {
    if (modules.empty()) return {};
    return Collector().run(*modules.back());
}

const Symbol* SymbolTable::at(SourceLoc loc) const {
    for (const Symbol& s : symbols) {
        if (contains(s.declaration, loc)) return &s;
        for (SourceRange r : s.references)
            if (contains(r, loc)) return &s;
    }
    return nullptr;
}

const Symbol* SymbolTable::find(SymbolKind kind, std::string_view name) const {
    for (const Symbol& s : symbols)
        if (s.kind == kind && s.name == name) return &s;
    return nullptr;
}

} // namespace moire::sema
