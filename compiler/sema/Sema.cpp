#include "compiler/sema/Sema.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include "compiler/sema/Builtins.h"
#include "compiler/sema/Suggest.h"

namespace moire::sema {

using namespace ast;

const std::vector<PropertySpec>& sceneProperties() {
    static const std::vector<PropertySpec> props = {
        {"size", Type::Vec2, true, true, "image size in pixels, (width, height); default (1200, 800)"},
        {"background", Type::Color, true, false, "paper colour; default #ffffff"},
    };
    return props;
}

const std::vector<PropertySpec>& cameraProperties() {
    static const std::vector<PropertySpec> props = {
        {"center", Type::Vec2, true, false, "world point at the middle of the image; default (0, 0)"},
        {"zoom", Type::Num, true, false, "pixels per world unit; default 1"},
        {"rotation", Type::Angle, true, false, "turn of the view; default 0deg"},
    };
    return props;
}

const std::vector<PropertySpec>& layerProperties() {
    static const std::vector<PropertySpec> props = {
        {"family", Type::Error, false, false, "a family name, or a phase expression in x and y"},
        {"spacing", Type::Num, false, false, "distance between members (s); default 10"},
        {"phase", Type::Num, false, false, "offset of the members, in phase units; default 0"},
        {"stroke", Type::Num, false, false, "stroke thickness in world units; default 1"},
        {"color", Type::Color, false, false, "ink colour; default #000000"},
        {"opacity", Type::Num, false, false, "0..1; default 1"},
        {"origin", Type::Vec2, false, false, "where the family's (0, 0) sits; default (0, 0)"},
        {"rotation", Type::Angle, false, false, "turn of the family about its origin; default 0deg"},
    };
    return props;
}

namespace {

const std::vector<std::string> kKeywords = {"scene", "camera", "layer", "field", "family", "let"};

std::string plural(int n, const char* word) { return fmt::format("{} {}{}", n, word, n == 1 ? "" : "s"); }

// How tall an expression may grow once the fields and lets it names are filled in. Lowering
// inlines them and walks the result recursively; the parser already bounds each expression
// by itself (Parser::kMaxDepth), and this bounds chains of fields referring to fields. It is
// well above one expression's limit, so that a long expression split into fields fits.
constexpr int kMaxExpandedDepth = 1024;

bool isLiteralZero(const Expr& e) {
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
    bool allowSpacing = false;    // family bodies and anonymous phases
};

class Checker {
public:
    explicit Checker(DiagEngine& diags) : diags_(diags) {}

    CheckedScene run(const std::vector<Module*>& modules) {
        collect(modules);
        for (Decl* f : fields_) checkField(*f);
        for (Decl* f : familyDecls_) checkFamily(*f);
        for (Module* m : modules)
            for (DeclPtr& d : m->decls) {
                if (d->kind == DeclKind::Scene) checkBlock(*d, sceneProperties(), "scene");
                if (d->kind == DeclKind::Camera) checkBlock(*d, cameraProperties(), "camera");
                if (d->kind == DeclKind::Layer) checkLayer(*d);
            }
        return std::move(out_);
    }

private:
    // ---- declarations -------------------------------------------------------------------
    bool reserved(const std::string& name, SourceRange at) {
        auto is = [&](const std::vector<std::string>& v) {
            return std::find(v.begin(), v.end(), name) != v.end();
        };
        if (is(builtinNames()) || is(builtinFunctions()) || is(kKeywords) || name == "spacing") {
            diags_.error(at, Msg::ReservedName, name);
            return true;
        }
        return false;
    }

    void collect(const std::vector<Module*>& modules) {
        for (Module* m : modules) {
            for (DeclPtr& dp : m->decls) {
                Decl& d = *dp;
                switch (d.kind) {
                case DeclKind::Scene:
                case DeclKind::Camera: {
                    const Decl*& slot = d.kind == DeclKind::Scene ? out_.scene : out_.camera;
                    if (slot) {
                        diags_.error(d.range, Msg::DuplicateBlock, declKindName(d.kind));
                        diags_.note(slot->range, Msg::FirstDefinedHere);
                    } else {
                        slot = &d;
                    }
                    break;
                }
                case DeclKind::Field:
                case DeclKind::Family: {
                    if (reserved(d.name, d.nameRange)) break;
                    auto known = globals_.find(d.name);
                    if (known != globals_.end()) {
                        diags_.error(d.nameRange, Msg::DuplicateDecl, declKindName(known->second->kind), d.name);
                        diags_.note(known->second->nameRange, Msg::FirstDefinedHere);
                        break;
                    }
                    globals_[d.name] = &d;
                    (d.kind == DeclKind::Field ? fields_ : familyDecls_).push_back(&d);
                    break;
                }
                case DeclKind::Layer:
                    if (!d.name.empty()) {
                        auto known = layerNames_.find(d.name);
                        if (known != layerNames_.end()) {
                            diags_.error(d.nameRange, Msg::DuplicateDecl, "layer", d.name);
                            diags_.note(known->second->nameRange, Msg::FirstDefinedHere);
                        } else {
                            layerNames_[d.name] = &d;
                        }
                    }
                    break;
                }
            }
        }
    }

    std::vector<std::string> globalNames(DeclKind kind) const {
        std::vector<std::string> v;
        for (auto& [name, d] : globals_)
            if (d->kind == kind) v.push_back(name);
        return v;
    }

    enum class State { Unvisited, InProgress, Done };

    void checkField(Decl& f) {
        State& st = fieldState_[&f];
        if (st != State::Unvisited) return;
        st = State::InProgress;
        fieldStack_.push_back(&f);
        checkExpr(*f.value, Scope{});
        fieldHeight_[&f] = lastHeight_;
        fieldStack_.pop_back();
        fieldState_[&f] = State::Done;
    }

    void checkFamily(Decl& f) {
        CheckedFamily& cf = out_.families[&f];
        cf.decl = &f;
        out_.familyByName[f.name] = &f;
        // Parameters and lets share one namespace: a let named like a parameter would hide it.
        std::unordered_map<std::string, std::pair<const char*, SourceRange>> seen;
        auto duplicate = [&](const std::string& name, SourceRange at) {
            auto it = seen.find(name);
            if (it == seen.end()) return false;
            diags_.error(at, Msg::DuplicateDecl, it->second.first, name);
            diags_.note(it->second.second, Msg::FirstDefinedHere);
            return true;
        };
        for (FamilyParam& p : f.params) {
            if (reserved(p.name, p.nameRange)) continue;
            // A layer's `stroke = 2` sets the layer's stroke, so a parameter of that name
            // could never be set.
            bool layerProp = false;
            for (const PropertySpec& spec : layerProperties()) layerProp |= p.name == spec.name;
            if (layerProp) {
                diags_.error(p.nameRange, Msg::ParamIsLayerProperty, p.name);
                continue;
            }
            if (duplicate(p.name, p.nameRange)) continue;
            seen[p.name] = {"parameter", p.nameRange};
            if (p.defaultValue) {
                checkExpr(*p.defaultValue, Scope{});
                p.type = p.defaultValue->type == Type::Error ? Type::Num : p.defaultValue->type;
            }
        }
        Scope scope;
        scope.family = &f;
        scope.allowSpacing = true;
        for (size_t i = 0; i < f.lets.size(); ++i) {
            Let& l = f.lets[i];
            if (!reserved(l.name, l.nameRange) && !duplicate(l.name, l.nameRange))
                seen[l.name] = {"let", l.nameRange};
            scope.visibleLets = i;
            checkExpr(*l.value, scope);
            letHeight_[&l] = lastHeight_;
        }
        scope.visibleLets = f.lets.size();
        std::unordered_map<std::string, const Property*> props;
        for (Property& p : f.props) {
            if (props.count(p.name)) {
                diags_.error(p.nameRange, Msg::DuplicateProperty, p.name, "family");
                diags_.note(props[p.name]->nameRange, Msg::FirstSeenHere);
                continue;
            }
            props[p.name] = &p;
            if (p.name == "phase") {
                checkExpr(*p.value, scope);
                expectType(*p.value, Type::Num, "the phase");
                cf.phase = p.value.get();
            } else if (p.name == "first") {
                checkExpr(*p.value, scope);
                const Expr* e = p.value.get();
                bool negative = false;
                while (e->kind == ExprKind::Unary) {
                    negative ^= e->un == UnOp::Neg;
                    e = e->args[0].get();
                }
                if (e->kind != ExprKind::Number || e->unit != Unit::None || std::floor(e->number) != e->number ||
                    std::fabs(e->number) > 1e6) {
                    diags_.error(p.value->range, Msg::FirstNotInteger);
                } else {
                    cf.first = static_cast<int>(negative ? -e->number : e->number);
                }
            } else {
                // `w = 2` in a family body is most likely a value meant to be named.
                std::string hint = didYouMean(p.name, {"phase", "first"});
                if (hint.empty()) hint = fmt::format("; to name a value, write: let {} = ...", p.name);
                diags_.error(p.nameRange, Msg::UnknownProperty, p.name, "a family (its properties are phase and first)",
                             hint);
            }
        }
        if (!cf.phase) diags_.error(f.nameRange, Msg::FamilyNeedsPhase, f.name);
    }

    const PropertySpec* findSpec(const std::vector<PropertySpec>& specs, const std::string& name) {
        for (const PropertySpec& s : specs)
            if (name == s.name) return &s;
        return nullptr;
    }

    void checkProperty(Property& p, const PropertySpec& spec, const Scope& scope) {
        checkExpr(*p.value, scope);
        expectType(*p.value, spec.type, fmt::format("'{}'", p.name));
        if (spec.positionFree && p.value->dependsOnPosition)
            diags_.error(p.value->range, Msg::MustBeConstant, fmt::format("'{}'", p.name),
                         "the position (x, y, r or theta)");
        if (spec.timeFree && p.value->dependsOnTime)
            diags_.error(p.value->range, Msg::MustBeConstant, fmt::format("'{}'", p.name), "the clock t");
    }

    bool noDuplicates(Decl& d, const char* what) {
        std::unordered_map<std::string, const Property*> seen;
        bool ok = true;
        for (Property& p : d.props) {
            auto it = seen.find(p.name);
            if (it != seen.end()) {
                diags_.error(p.nameRange, Msg::DuplicateProperty, p.name, what);
                diags_.note(it->second->nameRange, Msg::FirstSeenHere);
                ok = false;
                continue;
            }
            seen[p.name] = &p;
        }
        return ok;
    }

    void checkBlock(Decl& d, const std::vector<PropertySpec>& specs, const char* what) {
        noDuplicates(d, what);
        std::vector<std::string> names;
        for (const PropertySpec& s : specs) names.push_back(s.name);
        for (Property& p : d.props) {
            const PropertySpec* spec = findSpec(specs, p.name);
            if (!spec) {
                diags_.error(p.nameRange, Msg::UnknownProperty, p.name, fmt::format("the {}", what),
                             didYouMean(p.name, names));
                continue;
            }
            checkProperty(p, *spec, Scope{});
        }
    }

    void checkLayer(Decl& d) {
        noDuplicates(d, "layer");
        CheckedLayer layer;
        layer.decl = &d;
        const Property* fam = d.prop("family");
        const Decl* familyDecl = nullptr;
        if (!fam) {
            diags_.error(d.range, Msg::MissingFamily);
        } else if (fam->value->kind == ExprKind::Name && !lookupName(fam->value->name) &&
                   fam->value->name != "spacing" && // a (constant) phase, like any built-in name
                   !(globals_.count(fam->value->name) && globals_[fam->value->name]->kind == DeclKind::Field)) {
            auto it = globals_.find(fam->value->name);
            if (it != globals_.end() && it->second->kind == DeclKind::Family) {
                familyDecl = it->second;
                layer.family = &out_.families[familyDecl];
            } else {
                diags_.error(fam->value->range, Msg::UnknownFamily, fam->value->name,
                             didYouMean(fam->value->name, globalNames(DeclKind::Family)));
            }
        } else {
            Scope scope;
            scope.allowSpacing = true;
            checkExpr(*fam->value, scope);
            // Said in the layer's terms: `family` takes a family's name or a phase.
            Type t = fam->value->type;
            if (t != Type::Num && t != Type::Error)
                diags_.error(fam->value->range, Msg::TypeMismatch, "'family'", "a family name or a number (a phase)",
                             typeName(t));
            layer.anonymousPhase = fam->value.get();
        }
        std::vector<std::string> allowed;
        for (const PropertySpec& s : layerProperties()) allowed.push_back(s.name);
        if (familyDecl) {
            layer.args.assign(familyDecl->params.size(), nullptr);
            for (const FamilyParam& p : familyDecl->params) allowed.push_back(p.name);
        }
        for (Property& p : d.props) {
            if (p.name == "family") continue;
            if (const PropertySpec* spec = findSpec(layerProperties(), p.name)) {
                checkProperty(p, *spec, Scope{});
                continue;
            }
            bool matched = false;
            if (familyDecl) {
                for (size_t i = 0; i < familyDecl->params.size(); ++i) {
                    const FamilyParam& fp = familyDecl->params[i];
                    if (fp.name != p.name) continue;
                    PropertySpec spec{fp.name.c_str(), fp.type, false, false, ""};
                    checkProperty(p, spec, Scope{});
                    layer.args[i] = p.value.get();
                    matched = true;
                }
            }
            if (!matched) {
                std::string owner = familyDecl ? fmt::format("a layer of family '{}'", familyDecl->name)
                                               : std::string("a layer");
                diags_.error(p.nameRange, Msg::UnknownProperty, p.name, owner, didYouMean(p.name, allowed));
            }
        }
        if (familyDecl) {
            for (size_t i = 0; i < familyDecl->params.size(); ++i)
                if (!layer.args[i] && !familyDecl->params[i].defaultValue)
                    diags_.error(fam->value->range, Msg::MissingParam, familyDecl->name, familyDecl->params[i].name,
                                 familyDecl->params[i].name);
        }
        out_.layers.push_back(std::move(layer));
    }

    // ---- expressions ------------------------------------------------------------------
    void expectType(const Expr& e, Type want, const std::string& what) {
        if (e.type == Type::Error || want == Type::Error || e.type == want) return;
        if (want == Type::Angle && e.type == Type::Num) {
            if (isLiteralZero(e)) return;
            // The example repeats the number written, sign included (`-30` -> -30deg).
            const Expr* lit = &e;
            bool negative = false;
            while (lit->kind == ExprKind::Unary) {
                negative ^= lit->un == UnOp::Neg;
                lit = lit->args[0].get();
            }
            std::string example = lit->kind == ExprKind::Number
                                      ? fmt::format("{}{}", negative ? "-" : "", lit->number)
                                      : "30";
            diags_.error(e.range, Msg::AngleNeedsUnit, what, example, example);
            return;
        }
        diags_.error(e.range, Msg::TypeMismatch, what, typeName(want), typeName(e.type));
    }

    void inherit(Expr& e) {
        for (const ExprPtr& a : e.args) {
            e.dependsOnPosition |= a->dependsOnPosition;
            e.dependsOnTime |= a->dependsOnTime;
        }
    }

    void tooDeep(const Expr& e) {
        // Once is enough: the rest of a long chain would report it again every
        // kMaxExpandedDepth links.
        if (!tooDeepReported_) diags_.error(e.opRange, Msg::FieldsTooDeep, e.name, kMaxExpandedDepth);
        tooDeepReported_ = true;
    }

    // Checks `e` and leaves in lastHeight_ its height with fields and lets filled in.
    Type checkExpr(Expr& e, const Scope& scope) {
        DepthGuard guard(exprDepth_);
        int height = 0;
        for (ExprPtr& a : e.args) {
            checkExpr(*a, scope);
            height = std::max(height, lastHeight_);
        }
        inherit(e);
        refHeight_ = 0;
        e.type = typeOf(e, scope); // a name sets refHeight_ to the height of what it names
        // (A name whose value is already in error was reported where that error is.)
        if (refHeight_ >= kMaxExpandedDepth && e.type != Type::Error) {
            tooDeep(e);
            // Reported once, here: whatever uses this expression counts it as a leaf.
            refHeight_ = 0;
            e.type = Type::Error;
        }
        lastHeight_ = 1 + std::max(height, refHeight_);
        return e.type;
    }

    bool anyError(const Expr& e) const {
        for (const ExprPtr& a : e.args)
            if (a->type == Type::Error) return true;
        return false;
    }

    Type typeOf(Expr& e, const Scope& scope) {
        switch (e.kind) {
        case ExprKind::Error: return Type::Error;
        case ExprKind::Number: return e.unit == Unit::None ? Type::Num : Type::Angle;
        case ExprKind::Color: return Type::Color;
        case ExprKind::Name: return resolveName(e, scope);
        case ExprKind::Vector: {
            if (e.args.size() != 2) {
                diags_.error(e.range, Msg::VectorSize, e.args.size());
                return Type::Error;
            }
            for (const ExprPtr& a : e.args)
                if (a->type != Type::Num && a->type != Type::Error) {
                    diags_.error(a->range, Msg::TypeMismatch, "a vector component", typeName(Type::Num),
                                 typeName(a->type));
                    return Type::Error;
                }
            return anyError(e) ? Type::Error : Type::Vec2;
        }
        case ExprKind::Unary: {
            Type t = e.args[0]->type;
            if (t == Type::Error) return t;
            if (t == Type::Color) {
                diags_.error(e.opRange, Msg::UnaryType, e.un == UnOp::Neg ? "-" : "+", typeName(t));
                return Type::Error;
            }
            return t;
        }
        case ExprKind::Binary: return binaryType(e);
        case ExprKind::Call: return callType(e);
        }
        return Type::Error;
    }

    Type binaryType(Expr& e) {
        Type a = e.args[0]->type, b = e.args[1]->type;
        if (a == Type::Error || b == Type::Error) return Type::Error;
        auto fail = [&] {
            // Adding a bare number to an angle is the usual slip: the number wants a unit.
            bool angleAndNumber = (a == Type::Angle && b == Type::Num) || (a == Type::Num && b == Type::Angle);
            const char* hint = (e.bin == BinOp::Add || e.bin == BinOp::Sub) && angleAndNumber
                                   ? "; give the number a unit, as in 30deg"
                                   : "";
            diags_.error(e.opRange, Msg::BinaryTypes, binOpSpelling(e.bin), typeName(a), typeName(b), hint);
            return Type::Error;
        };
        switch (e.bin) {
        case BinOp::Add:
        case BinOp::Sub:
            if (a == b && a != Type::Color) return a;
            // 0 is zero in every unit: `rotation + 0` is harmless.
            if (a == Type::Angle && b == Type::Num && isLiteralZero(*e.args[1])) return a;
            if (b == Type::Angle && a == Type::Num && isLiteralZero(*e.args[0])) return b;
            return fail();
        case BinOp::Mul:
            if (a == Type::Num && b == Type::Num) return Type::Num;
            if (a == Type::Num && (b == Type::Angle || b == Type::Vec2)) return b;
            if (b == Type::Num && (a == Type::Angle || a == Type::Vec2)) return a;
            return fail();
        case BinOp::Div:
            if (b == Type::Num && (a == Type::Num || a == Type::Angle || a == Type::Vec2)) return a;
            if (a == Type::Angle && b == Type::Angle) return Type::Num;
            return fail();
        case BinOp::Pow:
            if (a == Type::Num && b == Type::Num) return Type::Num;
            return fail();
        }
        return Type::Error;
    }

    Type callType(Expr& e) {
        auto fn = lookupFn(e.name);
        if (!fn) {
            if (lookupName(e.name)) diags_.error(e.opRange, Msg::NotAFunction, e.name, "a built-in value");
            else if (globals_.count(e.name))
                diags_.error(e.opRange, Msg::NotAFunction, e.name,
                             globals_[e.name]->kind == DeclKind::Field ? "a field" : "a family");
            else
                diags_.error(e.opRange, Msg::UnknownFunction, e.name, didYouMean(e.name, builtinFunctions()));
            return Type::Error;
        }
        e.refIndex = static_cast<int>(*fn);
        const FnInfo& info = fnInfo(*fn);
        int given = static_cast<int>(e.args.size());
        if (given != info.numArgs) {
            diags_.error(e.range, Msg::Arity, e.name, plural(info.numArgs, "argument"),
                         fmt::format("{} {}", given, given == 1 ? "was" : "were"));
            return Type::Error;
        }
        if (anyError(e)) return Type::Error;
        auto argFail = [&](int i, const char* want) {
            diags_.error(e.args[i]->range, Msg::ArgumentType, i + 1, e.name, want, typeName(e.args[i]->type));
            return Type::Error;
        };
        switch (info.sig) {
        case Signature::Trig:
            if (e.args[0]->type != Type::Num && e.args[0]->type != Type::Angle) return argFail(0, "a number or an angle");
            return Type::Num;
        case Signature::NumToNum:
            for (int i = 0; i < given; ++i)
                if (e.args[i]->type != Type::Num) return argFail(i, "a number");
            return Type::Num;
        case Signature::SameUnit:
        case Signature::SameToNum: {
            Type t = e.args[0]->type;
            if (t != Type::Num && t != Type::Angle) return argFail(0, "a number or an angle");
            for (int i = 1; i < given; ++i) {
                Type u = e.args[i]->type;
                if (u == t) continue;
                if (u == Type::Num && isLiteralZero(*e.args[i])) continue;
                if (u != Type::Num && u != Type::Angle) return argFail(i, "a number or an angle");
                diags_.error(e.args[i]->range, Msg::SameTypeArgs, e.name, typeName(t), typeName(u));
                return Type::Error;
            }
            return info.sig == Signature::SameUnit ? t : Type::Num;
        }
        case Signature::Mix:
            if (e.args[0]->type != e.args[1]->type) {
                diags_.error(e.args[1]->range, Msg::SameTypeArgs, e.name, typeName(e.args[0]->type),
                             typeName(e.args[1]->type));
                return Type::Error;
            }
            if (e.args[2]->type != Type::Num) return argFail(2, "a number");
            return e.args[0]->type;
        case Signature::Length:
            if (e.args[0]->type != Type::Vec2) return argFail(0, "a 2-vector");
            return Type::Num;
        case Signature::Color:
            for (int i = 0; i < given; ++i)
                if (e.args[i]->type != Type::Num) return argFail(i, "a number");
            return Type::Color;
        }
        return Type::Error;
    }

    Type resolveName(Expr& e, const Scope& scope) {
        const std::string& n = e.name;
        if (scope.family) {
            for (size_t i = scope.visibleLets; i-- > 0;) {
                const Let& l = scope.family->lets[i];
                if (l.name != n) continue;
                e.ref = RefKind::Let;
                e.refDecl = scope.family;
                e.refIndex = static_cast<int>(i);
                e.dependsOnPosition = l.value->dependsOnPosition;
                e.dependsOnTime = l.value->dependsOnTime;
                refHeight_ = letHeight_[&l];
                return l.value->type;
            }
            for (size_t i = 0; i < scope.family->params.size(); ++i) {
                const FamilyParam& p = scope.family->params[i];
                if (p.name != n) continue;
                e.ref = RefKind::FamilyParam;
                e.refDecl = scope.family;
                e.refIndex = static_cast<int>(i);
                // A parameter is whatever the layer sets it to, which may vary.
                e.dependsOnPosition = true;
                e.dependsOnTime = true;
                return p.type;
            }
        }
        if (n == "spacing") {
            if (!scope.allowSpacing) {
                diags_.error(e.opRange, Msg::NameNotHere, n, "in a family's phase");
                return Type::Error;
            }
            e.ref = RefKind::Spacing;
            e.dependsOnPosition = e.dependsOnTime = true;
            return Type::Num;
        }
        if (auto b = lookupName(n)) {
            e.ref = RefKind::Builtin;
            e.refIndex = static_cast<int>(*b);
            e.dependsOnPosition = nameInfo(*b).position;
            e.dependsOnTime = nameInfo(*b).time;
            return Type::Num;
        }
        auto g = globals_.find(n);
        if (g != globals_.end() && g->second->kind == DeclKind::Field) {
            Decl* f = const_cast<Decl*>(g->second);
            if (fieldState_[f] == State::InProgress) {
                std::string path;
                bool on = false;
                for (const Decl* d : fieldStack_) {
                    if (d == f) on = true;
                    if (on) path += (path.empty() ? "" : " -> ") + d->name;
                }
                path += " -> " + f->name;
                diags_.error(e.opRange, Msg::FieldCycle, f->name, path);
                return Type::Error;
            }
            if (fieldState_[f] == State::Unvisited && exprDepth_ >= kMaxExpandedDepth) {
                // Checking `f` now would recurse once more per field in a chain of fields
                // each defined by the next; past the limit the chain is too deep anyway.
                tooDeep(e);
                return Type::Error;
            }
            checkField(*f);
            refHeight_ = fieldHeight_[f];
            e.ref = RefKind::Field;
            e.refDecl = f;
            e.dependsOnPosition = f->value->dependsOnPosition;
            e.dependsOnTime = f->value->dependsOnTime;
            return f->value->type;
        }
        if (g != globals_.end() && g->second->kind == DeclKind::Family) {
            diags_.error(e.opRange, Msg::FamilyAsValue, n, n);
            return Type::Error;
        }
        if (lookupFn(n)) {
            diags_.error(e.opRange, Msg::FunctionAsValue, n, n);
            return Type::Error;
        }
        if (scope.family) {
            // A let below this point (or this very let) is not defined yet.
            for (size_t i = scope.visibleLets; i < scope.family->lets.size(); ++i)
                if (scope.family->lets[i].name == n) {
                    diags_.error(e.opRange, Msg::NameNotHere, n, fmt::format("after 'let {} = ...' defines it", n));
                    return Type::Error;
                }
        }
        std::vector<std::string> candidates = builtinNames();
        for (auto& [name, d] : globals_)
            if (d->kind == DeclKind::Field) candidates.push_back(name);
        if (scope.family) {
            for (size_t i = 0; i < scope.visibleLets; ++i) candidates.push_back(scope.family->lets[i].name);
            for (const FamilyParam& p : scope.family->params) candidates.push_back(p.name);
        }
        if (scope.allowSpacing) candidates.push_back("spacing");
        diags_.error(e.opRange, Msg::UnknownName, n, didYouMean(n, candidates));
        return Type::Error;
    }

    DiagEngine& diags_;
    CheckedScene out_;
    std::unordered_map<std::string, const Decl*> globals_;
    std::unordered_map<std::string, const Decl*> layerNames_;
    std::vector<Decl*> fields_, familyDecls_;
    std::unordered_map<const Decl*, State> fieldState_;
    std::vector<const Decl*> fieldStack_;
    // Heights with fields and lets filled in (see kMaxExpandedDepth).
    std::unordered_map<const Decl*, int> fieldHeight_;
    std::unordered_map<const Let*, int> letHeight_;
    int lastHeight_ = 0; // of the expression checkExpr last finished
    int exprDepth_ = 0;
    bool tooDeepReported_ = false;  // checkExpr calls under way, through the fields they name
    int refHeight_ = 0;  // of what the name being resolved refers to
};

} // namespace

CheckedScene check(const std::vector<Module*>& modules, DiagEngine& diags) {
    return Checker(diags).run(modules);
}

} // namespace moire::sema
