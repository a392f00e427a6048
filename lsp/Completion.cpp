// Completion in context, read from the tokens before the cursor (the text being typed seldom
// parses): declaration keywords at the top level; inside a block the properties that block
// takes (a layer's also its family's parameters); after `family =` the families, after
// `easing =` the easings, after `mode =` the modes; elsewhere in a value the functions, the
// built-in names and the scene's and library's fields, params and timings (in a family's body
// also its parameters and lets, in an easing `u`); after a param's value the words `in`, `step`
// and `unit` that may still follow.
#include "compiler/lex/Keywords.h"
#include "compiler/sema/Views.h"
#include "lsp/Describe.h"
#include "lsp/Features.h"
#include "lsp/Syntax.h"

#include <optional>
#include <set>

namespace moire::lsp {

namespace {

// CompletionItemKind
constexpr int kFunction = 3, kField = 5, kVariable = 6, kClass = 7, kProperty = 10, kValue = 12,
              kKeyword = 14, kEnumMember = 20, kConstant = 21, kEvent = 23, kTypeParameter = 25;

struct Context {
    // ParamClause: after a param's whole value (or range, or step), where `in`, `step` and
    // `unit` may follow.
    enum class Kind { None, TopLevel, PropertyName, Value, ParamClause } kind = Kind::None;
    std::optional<ast::DeclKind> block; // the block or declaration the cursor is in
    std::string property;               // Value: the property (or declaration) it is the value of
    std::string callee;                 // the function whose argument list the cursor is in
    size_t blockOpen = 0;               // index of the block's `{` token
    std::string lastClause;             // a param's last `in`, `step` or `unit` before the cursor
};

// The words after a param's value, in the order the parser reads them.
const char* const kClauseWords[] = {"in", "step", "unit"};

std::optional<ast::DeclKind> declKind(std::string_view w) {
    using K = ast::DeclKind;
    static const std::pair<const char*, K> kinds[] = {
        {"scene", K::Scene},   {"camera", K::Camera}, {"layer", K::Layer},   {"field", K::Field},
        {"family", K::Family}, {"timing", K::Timing}, {"easing", K::Easing}, {"param", K::Param}};
    for (auto [name, k] : kinds)
        if (w == name) return k;
    return std::nullopt;
}

bool endsValue(Tok t) {
    return t == Tok::Number || t == Tok::Color || t == Tok::Ident || t == Tok::RParen;
}

Context contextAt(std::string_view text, const std::vector<Token>& toks, uint32_t at) {
    Context c;
    int depth = 0;
    std::vector<std::string> calls; // callee per open paren ("" for a grouping)
    bool stmtStart = true, inValue = false, afterKeyword = false, afterClause = false,
         rangeClosed = false; // a param's `in lo` has its `..`
    std::optional<ast::DeclKind> pending;
    auto spell = [&](const Token& t) { return text.substr(t.offset, t.length); };
    auto gapHasNewline = [&](uint32_t from, uint32_t to) {
        return text.substr(from, to - from).find('\n') != std::string_view::npos;
    };
    const Token* prev = nullptr;
    for (size_t i = 0; i < toks.size() && toks[i].offset < at; ++i) {
        const Token& t = toks[i];
        // A value ends at a line's end (the separators are optional).
        if (prev && inValue && calls.empty() && endsValue(prev->kind) &&
            gapHasNewline(prev->offset + prev->length, t.offset)) {
            stmtStart = true;
            inValue = false;
        }
        const bool wasStart = stmtStart;
        stmtStart = false;
        afterKeyword = false;
        afterClause = false;
        switch (t.kind) {
        case Tok::Ident:
            if (depth == 0 && calls.empty() && wasStart && declKind(spell(t))) {
                pending = declKind(spell(t));
                c.block = pending;
                c.lastClause.clear();
                afterKeyword = true;
            } else if (pending == ast::DeclKind::Param && depth == 0 && calls.empty() && inValue &&
                       prev && endsValue(prev->kind) && isParamClauseWord(spell(t))) {
                c.lastClause = spell(t); // `in`, `step` or `unit` after a whole value
                afterClause = true;
                rangeClosed = false;
            }
            break;
        case Tok::LBrace:
            if (++depth == 1) {
                c.block = pending;
                c.blockOpen = i;
            }
            stmtStart = true;
            inValue = false;
            break;
        case Tok::RBrace:
            if (depth > 0 && --depth == 0) c.block.reset();
            stmtStart = true;
            inValue = false;
            calls.clear();
            break;
        case Tok::LParen:
            calls.push_back(prev && prev->kind == Tok::Ident ? std::string(spell(*prev)) : "");
            break;
        case Tok::RParen:
            if (!calls.empty()) calls.pop_back();
            break;
        case Tok::Semi:
        case Tok::Comma:
            if (calls.empty()) {
                stmtStart = true;
                inValue = false;
            }
            break;
        case Tok::DotDot:
            rangeClosed = true;
            break;
        case Tok::Assign:
            if (prev && prev->kind == Tok::Ident && calls.empty()) c.property = spell(*prev);
            inValue = true;
            break;
        default:
            break;
        }
        prev = &t;
    }
    if (prev && inValue && calls.empty() && endsValue(prev->kind) &&
        gapHasNewline(prev->offset + prev->length, at)) {
        stmtStart = true;
        inValue = false;
    }
    if (!calls.empty()) c.callee = calls.back();
    if (afterKeyword) return c; // naming a new declaration: nothing to offer
    if (c.block == ast::DeclKind::Param && depth == 0 && calls.empty() && inValue && prev) {
        // After `unit` comes its label, any word, and then nothing; after `in 4`, `..`.
        if (c.lastClause == "unit") return c;
        if (!afterClause && endsValue(prev->kind)) {
            if (c.lastClause != "in" || rangeClosed) c.kind = Context::Kind::ParamClause;
            return c;
        }
    }
    if (depth == 0) {
        if (inValue || !calls.empty())
            c.kind = Context::Kind::Value;
        else if (stmtStart)
            c.kind = Context::Kind::TopLevel;
        if (c.kind == Context::Kind::TopLevel) c.block.reset();
        return c;
    }
    if (stmtStart)
        c.kind = Context::Kind::PropertyName;
    else if (inValue)
        c.kind = Context::Kind::Value;
    return c;
}

struct Items {
    Json list = Json::array();
    std::set<std::string> seen;
    void add(const std::string& label, int kind, const std::string& detail = "",
             const std::string& doc = "") {
        if (!seen.insert(label).second) return;
        Json item{{"label", label}, {"kind", kind}};
        if (!detail.empty()) item["detail"] = detail;
        if (!doc.empty()) item["documentation"] = {{"kind", "markdown"}, {"value", doc}};
        list.push_back(std::move(item));
    }
};

// Every declaration of that kind, the scene's first, then the library's.
std::vector<const ast::Decl*> declsOf(const SceneProgram& fe, ast::DeclKind kind) {
    std::vector<const ast::Decl*> out;
    for (auto it = fe.modules.rbegin(); it != fe.modules.rend(); ++it)
        for (const ast::DeclPtr& d : (*it)->decls)
            if (d->kind == kind && !d->name.empty()) out.push_back(d.get());
    return out;
}

void addDecls(Items& items, const SceneProgram& fe, ast::DeclKind kind, int itemKind) {
    for (const ast::Decl* d : declsOf(fe, kind)) {
        Description desc = describeDecl(fe, *d);
        items.add(d->name, itemKind, desc.signature, desc.meaning);
    }
}

// The family a layer block names (`family = name`, or a morph's first), from its tokens.
const ast::Decl* blockFamily(const SceneProgram& fe, std::string_view text,
                             const std::vector<Token>& toks, size_t open) {
    for (size_t i = open + 1; i + 2 < toks.size() && toks[i].kind != Tok::RBrace; ++i) {
        auto spell = [&](size_t k) { return text.substr(toks[k].offset, toks[k].length); };
        if (toks[i].kind != Tok::Ident || spell(i) != "family" || toks[i + 1].kind != Tok::Assign)
            continue;
        size_t n = i + 2;
        if (spell(n) == "morph" && n + 4 < toks.size()) n += 4; // morph ( timing , family
        for (const ast::Decl* d : declsOf(fe, ast::DeclKind::Family))
            if (d->name == spell(n)) return d;
    }
    return nullptr;
}

void addExpressionNames(Items& items, const SceneProgram& fe, const Context& c,
                        const ast::Decl* decl) {
    // In a family's body: its parameters, lets and the layer's spacing; in an easing: u.
    if (decl && decl->kind == ast::DeclKind::Family && c.block == ast::DeclKind::Family) {
        for (size_t i = 0; i < decl->params.size(); ++i) {
            Description d = describeParam(fe, *decl, int(i));
            items.add(decl->params[i].name, kTypeParameter, d.signature, d.meaning);
        }
        for (const ast::Let& l : decl->lets) items.add(l.name, kVariable, "let " + l.name);
        items.add("spacing", kProperty, "spacing: number", "the layer's spacing");
    }
    if (c.block == ast::DeclKind::Easing)
        items.add("u", kVariable, "u: number", "the progress the easing shapes, 0 to 1");
    if (c.callee == "ramp" || c.callee == "progress" || c.callee == "morph")
        addDecls(items, fe, ast::DeclKind::Timing, kEvent);
    for (const std::string& name : sema::builtinFunctions())
        if (auto fn = sema::lookupFn(name)) {
            Description d = describeFunction(sema::fnInfo(*fn));
            items.add(name, kFunction, d.signature, d.meaning);
        }
    for (const std::string& name : sema::builtinNames())
        if (auto n = sema::lookupName(name)) {
            Description d = describeBuiltinName(sema::nameInfo(*n));
            items.add(name, kConstant, d.signature, d.meaning);
        }
    addDecls(items, fe, ast::DeclKind::Field, kField);
    addDecls(items, fe, ast::DeclKind::Param, kConstant);
    addDecls(items, fe, ast::DeclKind::Timing, kEvent);
}

} // namespace

Json completion(const DocView& doc, uint32_t offset) {
    const SceneProgram* fe = doc.analysis.frontEnd();
    if (!fe) return Json::array();
    std::string_view text = doc.text();
    uint32_t at = wordAt(text, offset).first;
    std::vector<Token> toks = lexTokens(text);
    Context c = contextAt(text, toks, at);
    const ast::Decl* decl = declAt(fe->userModule(), at);
    Items items;
    switch (c.kind) {
    case Context::Kind::None:
        break;
    case Context::Kind::TopLevel:
        for (const std::string& k : declarationKeywords()) items.add(k, kKeyword);
        break;
    case Context::Kind::PropertyName: {
        // What the block has already written is not offered again.
        std::set<std::string> written;
        if (decl && c.block && decl->kind == *c.block)
            for (const ast::Property& p : decl->props)
                if (p.nameRange.begin.offset != at) written.insert(p.name);
        if (const auto* table = c.block ? propertyTable(*c.block) : nullptr)
            for (const sema::PropertySpec& s : *table)
                if (!written.count(s.name)) {
                    Description d = describeProperty(s, ast::declKindName(*c.block));
                    items.add(s.name, kProperty, d.signature, d.meaning);
                }
        if (c.block == ast::DeclKind::Layer)
            if (const ast::Decl* fam = blockFamily(*fe, text, toks, c.blockOpen))
                for (size_t i = 0; i < fam->params.size(); ++i)
                    if (!written.count(fam->params[i].name)) {
                        Description d = describeParam(*fe, *fam, int(i));
                        items.add(fam->params[i].name, kProperty, d.signature, d.meaning);
                    }
        if (c.block == ast::DeclKind::Family)
            items.add("let", kKeyword, "let name = value", "a value named in the family's body");
        break;
    }
    case Context::Kind::ParamClause: {
        // The words not yet written, in their order: after `step` only `unit` may come.
        bool open = c.lastClause.empty();
        for (const char* w : kClauseWords) {
            if (open) {
                Description d = describeParamClause(w);
                items.add(w, kKeyword, d.signature, d.meaning);
            }
            if (w == c.lastClause) open = true;
        }
        break;
    }
    case Context::Kind::Value:
        if (c.block == ast::DeclKind::Layer && c.property == "family" && c.callee.empty()) {
            addDecls(items, *fe, ast::DeclKind::Family, kClass);
            items.add("morph", kFunction, "morph(timing, family, family, ...)",
                      "one stroke that changes from each family into the next as the timing runs");
        } else if (c.block == ast::DeclKind::Layer && c.callee == "morph") {
            addDecls(items, *fe, ast::DeclKind::Timing, kEvent);
            addDecls(items, *fe, ast::DeclKind::Family, kClass);
        } else if (c.block == ast::DeclKind::Layer && c.property == "field") {
            addDecls(items, *fe, ast::DeclKind::Field, kField);
        } else if (c.block == ast::DeclKind::Timing && c.property == "easing") {
            addDecls(items, *fe, ast::DeclKind::Easing, kFunction);
        } else if (c.block == ast::DeclKind::Timing && c.property == "mode") {
            const auto& spec = sema::propertySpec(sema::timingProperties(), "mode");
            for (const char* m : {"once", "loop", "pingpong"})
                items.add(m, kEnumMember, "", spec.doc);
        } else if (c.block == ast::DeclKind::Scene && c.property == "view") {
            for (const sema::ViewName& v : sema::viewNames())
                items.add(v.name, kEnumMember, "", v.doc);
        } else if (c.block == ast::DeclKind::Scene && c.property == "overlay") {
            items.add("true", kValue);
            items.add("false", kValue);
        } else if (c.block == ast::DeclKind::Scene && c.property == "filter") {
            const auto& spec = sema::propertySpec(sema::sceneProperties(), "filter");
            for (const char* f : sema::kFilterNames) items.add(f, kEnumMember, "", spec.doc);
        } else {
            addExpressionNames(items, *fe, c, decl);
        }
        break;
    }
    return Json{{"isIncomplete", false}, {"items", std::move(items.list)}};
}

} // namespace moire::lsp
