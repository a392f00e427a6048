#include "compiler/sema/Sema.h"

#include "compiler/diag/Suggest.h"
#include "compiler/lex/Keywords.h"
#include "compiler/sema/Builtins.h"
#include "compiler/sema/Checker.h"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <functional>
#include <unordered_set>

namespace moire::sema {

using namespace ast;

namespace detail {

namespace {
// A hint for a word that is not a timing's mode: the mode meant by a word other tools use
// for it, or a near spelling of one (at most one edit: 'bounce' is no misspelling of 'once').
Hint modeHint(const std::string& word) {
    static const std::pair<const char*, const char*> synonyms[] = {
        {"bounce", "pingpong"},  {"yoyo", "pingpong"},   {"alternate", "pingpong"},
        {"reverse", "pingpong"}, {"mirror", "pingpong"}, {"repeat", "loop"},
        {"cycle", "loop"},       {"forever", "loop"},    {"infinite", "loop"},
        {"single", "once"},      {"one", "once"},        {"hold", "once"}};
    for (const auto& [other, mode] : synonyms)
        if (word == other) return suggest(mode);
    std::string near = nearestName(word, timingModeNames(), 1);
    return near.empty() ? Hint() : suggest(near);
}

// `#rrggbb` for a colour's common name, as an example of how to write it.
std::string colorExample(const std::string& name) {
    static const std::pair<const char*, const char*> named[] = {
        {"black", "#000000"}, {"white", "#ffffff"},  {"red", "#ff0000"},    {"green", "#00a000"},
        {"blue", "#0000ff"},  {"yellow", "#ffff00"}, {"orange", "#ff8000"}, {"purple", "#800080"},
        {"gray", "#808080"},  {"grey", "#808080"},   {"cyan", "#00ffff"},   {"magenta", "#ff00ff"},
        {"pink", "#ffc0cb"},  {"brown", "#8b4513"}};
    for (const auto& [n, hex] : named)
        if (name == n) return fmt::format("{} for {}", hex, n);
    return "#1a2b3c";
}
} // namespace

CheckedScene Checker::run(const std::vector<Module*>& modules) {
    collect(modules);
    for (Decl* e : easings_) checkEasing(*e);
    for (Decl* t : timings_) checkTiming(*t);
    for (Decl* f : fields_) checkField(*f);
    for (Decl* f : fields_)
        if (f->kind == DeclKind::Param) checkParam(*f);
    for (Decl* f : familyDecls_) checkFamily(*f);
    for (Module* m : modules)
        for (DeclPtr& d : m->decls) {
            if (d->kind == DeclKind::Scene) checkBlock(*d, sceneProperties(), "scene");
            if (d->kind == DeclKind::Camera) checkBlock(*d, cameraProperties(), "camera");
            if (d->kind == DeclKind::Layer) checkLayer(*d);
        }
    return std::move(out_);
}

bool Checker::reserved(const std::string& name, SourceRange at) {
    auto is = [&](const std::vector<std::string>& v) {
        return std::find(v.begin(), v.end(), name) != v.end();
    };
    if (is(builtinNames()) || is(builtinFunctions()) || isKeyword(name) || name == kSpacingName ||
        name == "true" || name == "false") {
        diags_.error(at, Msg::ReservedName, name);
        return true;
    }
    return false;
}

void Checker::collect(const std::vector<Module*>& modules) {
    // The scene's own module comes last; the standard library's before it.
    std::unordered_set<const Decl*> library;
    for (size_t mi = 0; mi < modules.size(); ++mi) {
        const bool user = mi + 1 == modules.size();
        for (DeclPtr& dp : modules[mi]->decls) {
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
            case DeclKind::Family:
            case DeclKind::Timing:
            case DeclKind::Easing:
            case DeclKind::Param: {
                if (reserved(d.name, d.nameRange)) break;
                auto known = globals_.find(d.name);
                // A scene may reuse a library name (its own `field ripple`): its declaration
                // hides the library's wherever the scene names it.
                if (known != globals_.end() && user && library.count(known->second)) {
                    globals_[d.name] = &d;
                    declList(d.kind).push_back(&d);
                    break;
                }
                if (known != globals_.end()) {
                    diags_.error(d.nameRange, Msg::DuplicateDecl, declKindName(known->second->kind),
                                 d.name);
                    diags_.note(known->second->nameRange, Msg::FirstDefinedHere);
                    break;
                }
                globals_[d.name] = &d;
                if (!user) library.insert(&d);
                declList(d.kind).push_back(&d);
                break;
            }
            case DeclKind::Layer:
                if (++userLayers_ == kMaxLayers + 1)
                    diags_.error(d.range, Msg::TooManyLayers, kMaxLayers);
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

std::vector<std::string> Checker::globalNames(DeclKind kind) const {
    std::vector<std::string> v;
    for (auto& [name, d] : globals_)
        if (d->kind == kind) v.push_back(name);
    return v;
}

void Checker::checkField(Decl& f) {
    State& st = fieldState_[&f];
    if (st != State::Unvisited) return;
    st = State::InProgress;
    fieldStack_.push_back(&f);
    checkExpr(*f.value, Scope{});
    if (f.kind == DeclKind::Param && f.sceneDefault) checkDefinedValue(f);
    fieldHeight_[&f] = lastHeight_;
    fieldStack_.pop_back();
    fieldState_[&f] = State::Done;
}

void Checker::checkEasing(Decl& e) {
    // An easing maps progress u in [0, 1] to [0, 1]; it may use u and constants only.
    // The first declaration of a name wins, and the standard library's are checked first:
    // the compiler looks easings up here for its own use (a morph's cubic_in_out, §8.3),
    // which a scene's easing of the same name must not reshape. The scene's timings find
    // its own easing through the names in scope.
    out_.easingByName.emplace(e.name, &e);
    Scope scope;
    scope.easing = true;
    checkExpr(*e.value, scope);
    expectType(*e.value, Type::Num, fmt::format("easing '{}'", e.name));
    if (e.value->dependsOnPosition)
        diags_.error(e.value->range, Msg::MustBeConstant, fmt::format("easing '{}'", e.name),
                     "the position (x, y, r or theta)");
    if (e.value->dependsOnTime)
        diags_.error(e.value->range, Msg::MustBeConstant, fmt::format("easing '{}'", e.name),
                     "the clock t");
}

void Checker::checkTiming(Decl& t) {
    noDuplicates(t, "timing");
    CheckedTiming& ct = out_.timings[&t];
    ct.decl = &t;
    out_.timingOrder.push_back(&t);
    for (Property& p : t.props) {
        if (p.name == "period" || p.name == "delay") {
            // Both set the clip's loop length, so neither may change with the clock.
            PropertySpec spec{p.name.c_str(), Type::Num, true, true, ""};
            checkProperty(p, spec, Scope{});
            (p.name == "period" ? ct.period : ct.delay) = p.value.get();
        } else if (p.name == "mode") {
            const std::string word = p.value->kind == ExprKind::Name ? p.value->name : "";
            if (word == "once")
                ct.mode = TimingMode::Once;
            else if (word == "loop")
                ct.mode = TimingMode::Loop;
            else if (word == "pingpong")
                ct.mode = TimingMode::PingPong;
            else if (word.empty())
                diags_.error(p.value->range, Msg::BadMode, "this");
            else {
                Hint hint = modeHint(word);
                hint.text = fmt::format("'{}'{}", word, hint.text);
                diags_.error(p.value->range, Msg::BadMode, hint);
            }
        } else if (p.name == "easing") {
            auto it =
                p.value->kind == ExprKind::Name ? globals_.find(p.value->name) : globals_.end();
            if (it != globals_.end() && it->second->kind == DeclKind::Easing) {
                ct.easing = it->second;
                p.value->ref = RefKind::Easing; // for the symbol table
                p.value->refDecl = it->second;
            } else {
                std::vector<std::string> names;
                for (const Decl* e : easings_) names.push_back(e->name);
                std::string what =
                    p.value->kind == ExprKind::Name ? fmt::format("'{}'", p.value->name) : "this";
                Hint hint =
                    p.value->kind == ExprKind::Name ? didYouMean(p.value->name, names) : Hint();
                // With nothing near, say what there is, and how to make one's own.
                if (hint.text.empty()) {
                    std::sort(names.begin(), names.end());
                    names.erase(std::unique(names.begin(), names.end()), names.end());
                    std::string list;
                    for (size_t i = 0; i < names.size(); ++i)
                        list += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
                    hint = fmt::format("; the easings are {}, or declare one, as in: easing {} = "
                                       "u * u",
                                       list,
                                       p.value->kind == ExprKind::Name &&
                                               !globals_.count(p.value->name)
                                           ? p.value->name
                                           : "mine");
                }
                diags_.error(p.value->range, Msg::NotAnEasing, what, hint);
            }
        } else {
            diags_.error(p.nameRange, Msg::UnknownProperty, p.name,
                         "a timing (its properties are period, delay, mode and easing)",
                         didYouMean(p.name, timingPropertyNames()));
        }
    }
    if (!ct.period)
        diags_.error(t.nameRange, Msg::MissingProperty, "timing", t.name, "period", "period = 4");
}

bool Checker::timingArgument(Expr& arg, const std::string& fn) {
    auto it = arg.kind == ExprKind::Name ? globals_.find(arg.name) : globals_.end();
    if (it == globals_.end() || it->second->kind != DeclKind::Timing) {
        const char* example = fn == "ramp"       ? "ramp(drift, 0, 1)"
                              : fn == "progress" ? "progress(drift)"
                                                 : "morph(drift, circles, hexagons)";
        diags_.error(arg.range, Msg::NotATiming, fmt::format("'{}'", fn), example,
                     arg.kind == ExprKind::Name
                         ? didYouMean(arg.name, globalNames(DeclKind::Timing))
                         : Hint());
        return false;
    }
    arg.ref = RefKind::Timing;
    arg.refDecl = it->second;
    arg.type = Type::Num;
    arg.dependsOnTime = true;
    return true;
}

bool Checker::checkMorph(const Property& fam, CheckedLayer& layer) {
    Expr& call = *fam.value;
    if (call.kind != ExprKind::Call || call.name != kMorphName) return false;
    if (call.args.size() < 3) {
        diags_.error(call.range, Msg::MorphArgs);
        return true;
    }
    call.type = Type::Num;
    if (timingArgument(*call.args[0], kMorphName)) layer.morphTiming = call.args[0]->refDecl;
    for (size_t i = 1; i < call.args.size(); ++i) {
        Expr& a = *call.args[i];
        auto it = a.kind == ExprKind::Name ? globals_.find(a.name) : globals_.end();
        if (it == globals_.end() || it->second->kind != DeclKind::Family) {
            diags_.error(a.range, Msg::UnknownFamily, a.kind == ExprKind::Name ? a.name : "?",
                         a.kind == ExprKind::Name
                             ? didYouMean(a.name, globalNames(DeclKind::Family))
                             : Hint());
            continue;
        }
        a.ref = RefKind::Family; // for the symbol table
        a.refDecl = it->second;
        CheckedLayer::Member m;
        m.family = &out_.families[it->second];
        m.args.assign(it->second->params.size(), nullptr);
        layer.morph.push_back(std::move(m));
    }
    return true;
}

void Checker::checkFamily(Decl& f) {
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
        if (p.name == "phase" || p.name == "distance" || p.name == "index") {
            checkExpr(*p.value, scope);
            expectType(*p.value, Type::Num, p.name == "phase" ? "the phase" : "the " + p.name);
            (p.name == "phase"      ? cf.phase
             : p.name == "distance" ? cf.distance
                                    : cf.index) = p.value.get();
        } else if (p.name == "facets") {
            // Usually a whole number from the family's parameters; the walking solver copes
            // with any value (fractional counts fall through to its scan).
            checkExpr(*p.value, scope);
            expectType(*p.value, Type::Num, "'facets'");
            cf.facets = p.value.get();
        } else if (p.name == "first") {
            checkExpr(*p.value, scope);
            const Expr* e = p.value.get();
            bool negative = false;
            while (e->kind == ExprKind::Unary) {
                negative ^= e->un == UnOp::Neg;
                e = e->args[0].get();
            }
            if (e->kind != ExprKind::Number || e->unit != Unit::None ||
                std::floor(e->number) != e->number || std::fabs(e->number) > 1e6) {
                diags_.error(p.value->range, Msg::FirstNotInteger);
            } else {
                cf.first = static_cast<int>(negative ? -e->number : e->number);
            }
        } else {
            // `w = 2` in a family body is most likely a value meant to be named.
            Hint hint = didYouMean(p.name, familyBodyPropertyNames());
            if (hint.text.empty())
                hint = fmt::format("; to name a value, write: let {} = ...", p.name);
            diags_.error(p.nameRange, Msg::UnknownProperty, p.name,
                         "a family (its properties are phase, first, facets, distance and index)",
                         hint);
        }
    }
    if (f.builtin) {
        cf.kind = FamilyKind::Builtin;
        return;
    }
    if (cf.phase && cf.distance) {
        diags_.error(props["distance"]->nameRange, Msg::FamilyPhaseAndDistance);
        diags_.note(props["phase"]->nameRange, Msg::FirstSeenHere);
    } else if (cf.distance) {
        cf.kind = FamilyKind::Distance;
        for (const char* phaseOnly : {"first", "facets"})
            if (props.count(phaseOnly))
                diags_.error(props[phaseOnly]->nameRange, Msg::PropertyNeedsKind, phaseOnly,
                             "phase");
    } else if (cf.phase) {
        if (props.count("index"))
            diags_.error(props["index"]->nameRange, Msg::PropertyNeedsKind, "index", "distance");
    } else {
        diags_.error(f.nameRange, Msg::FamilyNeedsPhase, f.name);
    }
}

const PropertySpec* Checker::findSpec(const std::vector<PropertySpec>& specs,
                                      const std::string& name) {
    for (const PropertySpec& s : specs)
        if (name == s.name) return &s;
    return nullptr;
}

void Checker::checkProperty(Property& p, const PropertySpec& spec, const Scope& scope) {
    // `color = red`: a name where a colour is expected is most likely a colour's name, which
    // the language does not have; say how colours are written.
    if (spec.type == Type::Color && p.value->kind == ExprKind::Name && !lookupName(p.value->name) &&
        !globals_.count(p.value->name)) {
        diags_.error(p.value->range, Msg::ColorName, p.value->name, colorExample(p.value->name));
        p.value->type = Type::Error;
        return;
    }
    checkExpr(*p.value, scope);
    expectType(*p.value, spec.type, fmt::format("'{}'", p.name));
    if (spec.positionFree && p.value->dependsOnPosition)
        diags_.error(p.value->range, Msg::MustBeConstant, fmt::format("'{}'", p.name),
                     "the position (x, y, r or theta)");
    if (spec.timeFree && p.value->dependsOnTime)
        diags_.error(p.value->range, Msg::MustBeConstant, fmt::format("'{}'", p.name),
                     "the clock t");
}

bool Checker::noDuplicates(Decl& d, const char* what) {
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

void Checker::checkBlock(Decl& d, const std::vector<PropertySpec>& specs, const char* what) {
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
        if (spec->type == Type::Error) { // a name from a fixed list: the view, a switch
            if (p.name == "overlay")
                checkSwitch(p);
            else if (p.name == "filter")
                checkFilterName(p);
            else
                checkViewName(p);
            continue;
        }
        checkProperty(p, *spec, Scope{});
    }
}

void Checker::checkViewName(Property& p) {
    std::vector<std::string> names;
    for (const ViewName& v : viewNames()) names.push_back(v.name);
    if (p.value->kind == ExprKind::Name && viewNamed(p.value->name)) return;
    std::string shown = p.value->kind == ExprKind::Name ? "'" + p.value->name + "'" : "this";
    diags_.error(p.value->range, Msg::UnknownView, shown, viewList(),
                 p.value->kind == ExprKind::Name ? didYouMean(p.value->name, names) : Hint());
}

void Checker::checkFilterName(Property& p) {
    if (p.value->kind == ExprKind::Name && filterNamed(p.value->name)) return;
    std::string shown = p.value->kind == ExprKind::Name ? "'" + p.value->name + "'" : "this";
    diags_.error(p.value->range, Msg::UnknownFilter, shown, filterList(),
                 p.value->kind == ExprKind::Name
                     ? didYouMean(p.value->name, {kFilterNames[0], kFilterNames[1]})
                     : Hint());
}

void Checker::checkSwitch(Property& p) {
    if (p.value->kind == ExprKind::Name && switchNamed(p.value->name)) return;
    std::string shown = p.value->kind == ExprKind::Name ? "'" + p.value->name + "'" : "this";
    diags_.error(p.value->range, Msg::NotASwitch, p.name, shown,
                 p.value->kind == ExprKind::Name ? didYouMean(p.value->name, {"true", "false"})
                                                 : Hint());
}

void Checker::checkLayer(Decl& d) {
    noDuplicates(d, "layer");
    CheckedLayer layer;
    layer.decl = &d;
    const Property* fam = d.prop("family");
    // The layer's families: one, or the members of a morph. A phase written in the layer
    // has none.
    std::vector<CheckedLayer::Member> members;
    const int errorsBefore = diags_.errorCount();
    if (!fam) {
        diags_.error(d.range, Msg::MissingFamily);
    } else if (checkMorph(*fam, layer)) {
        members = layer.morph;
    } else if (fam->value->kind == ExprKind::Name && !lookupName(fam->value->name) &&
               fam->value->name != kSpacingName && // a (constant) phase, like any built-in name
               !(globals_.count(fam->value->name) &&
                 globals_[fam->value->name]->kind == DeclKind::Field)) {
        auto it = globals_.find(fam->value->name);
        if (it != globals_.end() && it->second->kind == DeclKind::Family) {
            fam->value->ref = RefKind::Family; // for the symbol table
            fam->value->refDecl = it->second;
            CheckedLayer::Member m;
            m.family = &out_.families[it->second];
            m.args.assign(it->second->params.size(), nullptr);
            members.push_back(std::move(m));
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
            diags_.error(fam->value->range, Msg::TypeMismatch, "'family'",
                         "a family name or a number (a phase)", typeName(t));
        layer.anonymousPhase = fam->value.get();
    }
    // A family that did not resolve (unknown, or a morph with an unknown member) leaves its
    // parameters unknown too: they would only repeat that one mistake as more errors.
    const bool familyUnknown = fam && !layer.anonymousPhase && diags_.errorCount() > errorsBefore;
    std::vector<std::string> allowed;
    for (const PropertySpec& s : layerProperties()) allowed.push_back(s.name);
    for (const CheckedLayer::Member& m : members)
        for (const FamilyParam& p : m.family->decl->params) allowed.push_back(p.name);
    for (Property& p : d.props) {
        if (p.name == "family") continue;
        if (const PropertySpec* spec = findSpec(layerProperties(), p.name)) {
            checkProperty(p, *spec, Scope{});
            continue;
        }
        // A family parameter; in a morph, every member with a parameter of that name takes it.
        bool matched = false, checked = false;
        for (CheckedLayer::Member& m : members) {
            const Decl& fd = *m.family->decl;
            for (size_t i = 0; i < fd.params.size(); ++i) {
                const FamilyParam& fp = fd.params[i];
                if (fp.name != p.name) continue;
                if (!checked) {
                    PropertySpec spec{fp.name.c_str(), fp.type, false, false, ""};
                    checkProperty(p, spec, Scope{});
                    checked = true;
                } else {
                    expectType(*p.value, fp.type, fmt::format("'{}'", p.name));
                }
                m.args[i] = p.value.get();
                matched = true;
            }
        }
        if (!matched && familyUnknown) continue;
        if (!matched) {
            std::string owner = members.size() == 1 ? fmt::format("a layer of family '{}'",
                                                                  members[0].family->decl->name)
                                                    : std::string("a layer");
            diags_.error(p.nameRange, Msg::UnknownProperty, p.name, owner,
                         didYouMean(p.name, allowed));
        }
    }
    auto named = [&]() {
        return members.size() == 1 ? fmt::format("'{}'", members[0].family->decl->name)
                                   : std::string("this layer's family");
    };
    // Walking moves each member in its own frame, which only a support-function phase (a
    // family with facets) has. In a morph it applies to the members that can walk.
    for (const char* walk : {"offset", "turn"}) {
        const Property* p = d.prop(walk);
        if (!p) continue;
        layer.walking = true;
        bool any = false;
        for (const CheckedLayer::Member& m : members) any |= m.family->facets != nullptr;
        // A family that did not resolve was reported already; saying it cannot walk as well
        // would only bury that error.
        if (fam && !members.empty() && !any)
            diags_.error(p->nameRange, Msg::NotWalkable, walk, named());
    }
    // A field is encoded into the phase (phi - gain s f), which distance and builtin
    // families do not have.
    if (const Property* p = d.prop("field")) {
        layer.encoded = true;
        for (const CheckedLayer::Member& m : members)
            if (m.family->kind != FamilyKind::Phase) {
                diags_.error(p->nameRange, Msg::NotEncodable, m.family->decl->name);
                break;
            }
    }
    for (const CheckedLayer::Member& m : members) {
        const Decl& fd = *m.family->decl;
        for (size_t i = 0; i < fd.params.size(); ++i)
            if (!m.args[i] && !fd.params[i].defaultValue)
                diags_.error(fam->value->range, Msg::MissingParam, fd.name, fd.params[i].name,
                             fd.params[i].name);
    }
    if (!members.empty()) {
        layer.family = members[0].family;
        layer.args = members[0].args;
    }
    if (layer.morphTiming)
        layer.morph = std::move(members);
    else
        layer.morph.clear();
    out_.layers.push_back(std::move(layer));
}

} // namespace detail

CheckedScene check(const std::vector<Module*>& modules, DiagEngine& diags) {
    return detail::Checker(diags).run(modules);
}

} // namespace moire::sema
