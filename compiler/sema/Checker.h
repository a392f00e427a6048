// The semantic checker's internals, shared by Sema.cpp (declarations, blocks, layers) and
// CheckExpr.cpp (expressions: names, types, units). Not part of the compiler's interface.
#pragma once

#include "compiler/sema/Sema.h"
#include "compiler/sema/Views.h"

#include <fmt/format.h>
#include <string>
#include <unordered_map>
#include <vector>

namespace moire::sema::detail {

using namespace ast;

inline std::string plural(int n, const char* word) {
    return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s");
}

// How tall an expression may grow once the fields and lets it names are filled in. Lowering
// inlines them and walks the result recursively; the parser already bounds each expression
// by itself (Parser::kMaxDepth), and this bounds chains of fields referring to fields. It is
// well above one expression's limit, so that a long expression split into fields fits.
constexpr int kMaxExpandedDepth = 1024;

inline bool isLiteralZero(const Expr& e) {
    if (e.kind == ExprKind::Number) return e.number == 0.0;
    if (e.kind == ExprKind::Unary) return isLiteralZero(*e.args[0]);
    return false;
}

struct DepthGuard {
    int& depth;
    explicit DepthGuard(int& d) : depth(d) { ++depth; }
    ~DepthGuard() { --depth; }
};

// Scope of names while checking one expression.
struct Scope {
    const Decl* family = nullptr; // inside a family body
    size_t visibleLets = 0;
    bool allowSpacing = false; // family bodies and anonymous phases
    bool easing = false;       // an easing's body: `u` is its variable
};

class Checker {
  public:
    explicit Checker(DiagEngine& diags) : diags_(diags) {}

    CheckedScene run(const std::vector<Module*>& modules);

  private:
    // ---- declarations -------------------------------------------------------------------
    bool reserved(const std::string& name, SourceRange at);
    void collect(const std::vector<Module*>& modules);

    std::vector<std::string> globalNames(DeclKind kind) const;

    enum class State { Unvisited, InProgress, Done };
    void checkField(Decl& f);
    void checkParam(Decl& p);        // CheckParam.cpp
    void checkDefinedValue(Decl& p); // CheckParam.cpp: a `-D` value against its default
    void checkFamily(Decl& f);
    void checkEasing(Decl& e);
    std::vector<Decl*>& declList(DeclKind k) {
        return k == DeclKind::Field || k == DeclKind::Param ? fields_
               : k == DeclKind::Family                      ? familyDecls_
               : k == DeclKind::Timing                      ? timings_
                                                            : easings_;
    }
    void checkTiming(Decl& t);
    // The morph of a layer: `family = morph(timing, f0, f1, ...)`; false when it is not one.
    bool checkMorph(const Property& fam, CheckedLayer& layer);
    // `arg` names a timing (for ramp, progress, morph); reported and false otherwise.
    bool timingArgument(Expr& arg, const std::string& fn);
    const PropertySpec* findSpec(const std::vector<PropertySpec>& specs, const std::string& name);
    void checkProperty(Property& p, const PropertySpec& spec, const Scope& scope);
    bool noDuplicates(Decl& d, const char* what);
    void checkBlock(Decl& d, const std::vector<PropertySpec>& specs, const char* what);
    void checkViewName(Property& p);   // `view = NAME`: one of sema/Views.h
    void checkSwitch(Property& p);     // `overlay = true` or `false`
    void checkFilterName(Property& p); // `filter = point` or `mean`
    void checkLayer(Decl& d);

    // ---- expressions ------------------------------------------------------------------
    void expectType(const Expr& e, Type want, const std::string& what);
    void inherit(Expr& e);
    void tooDeep(const Expr& e);

    // Checks `e` and leaves in lastHeight_ its height with fields and lets filled in.
    Type checkExpr(Expr& e, const Scope& scope);
    Type finishExpr(Expr& e, const Scope& scope, int height);

    bool anyError(const Expr& e) const;
    Type typeOf(Expr& e, const Scope& scope);
    Type binaryType(Expr& e);
    Type callType(Expr& e);
    Type resolveName(Expr& e, const Scope& scope);

    DiagEngine& diags_;
    CheckedScene out_;
    std::unordered_map<std::string, const Decl*> globals_;
    std::unordered_map<std::string, const Decl*> layerNames_;
    int userLayers_ = 0; // counted against kMaxLayers
    std::vector<Decl*> fields_, familyDecls_, timings_, easings_;
    std::unordered_map<const Decl*, State> fieldState_;
    std::vector<const Decl*> fieldStack_;
    // Heights with fields and lets filled in (see kMaxExpandedDepth).
    std::unordered_map<const Decl*, int> fieldHeight_;
    std::unordered_map<const Let*, int> letHeight_;
    int lastHeight_ = 0; // of the expression checkExpr last finished
    int exprDepth_ = 0;
    bool tooDeepReported_ = false; // checkExpr calls under way, through the fields they name
    int refHeight_ = 0;            // of what the name being resolved refers to
};

} // namespace moire::sema::detail
