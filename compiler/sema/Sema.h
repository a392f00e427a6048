// Semantic checks: names, arity, types and units, and which expressions may depend on the
// position or the clock. The result points into the checked modules, annotated in place.
#pragma once

#include "compiler/diag/Diagnostics.h"
#include "compiler/parse/Ast.h"
#include "compiler/sema/Properties.h"

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace moire::sema {

// How a family defines its members.
enum class FamilyKind {
    Phase,    // members are the level sets {phase = n * spacing + offset}
    Distance, // the family gives its distance (and index) fields directly
    Builtin,  // the compiler builds the fields (lattices)
};

struct CheckedFamily {
    const ast::Decl* decl = nullptr;
    FamilyKind kind = FamilyKind::Phase;
    const ast::Expr* phase = nullptr;
    std::optional<int> first; // lowest member index, when the family excludes some
    // The phase is the support function of a regular polygon with this many facets, the
    // first facing +x (0: a circle). Such a family can walk: each member moved by n * offset
    // and turned by n * turn (the walking solver).
    const ast::Expr* facets = nullptr;
    const ast::Expr* distance = nullptr; // Distance families
    const ast::Expr* index = nullptr;    // Distance families; null: 0
};

// A named timing: progress from 0 to 1 over `period` seconds after `delay`, then held
// (once), repeated (loop) or reversed (pingpong), shaped by an easing.
enum class TimingMode { Once, Loop, PingPong };
struct CheckedTiming {
    const ast::Decl* decl = nullptr;
    const ast::Expr* period = nullptr;
    const ast::Expr* delay = nullptr; // null: 0
    TimingMode mode = TimingMode::Loop;
    const ast::Decl* easing = nullptr; // an easing declaration; null: linear
};

struct CheckedLayer {
    const ast::Decl* decl = nullptr;
    const CheckedFamily* family = nullptr;     // a named family, or null
    const ast::Expr* anonymousPhase = nullptr; // `family = <expression>`
    bool walking = false; // sets offset or turn: its members are found by the walking solver
    bool encoded = false; // carries a field in its phase (`field`, `gain`)
    // `family = morph(timing, f0, f1, ...)`: the families and each one's arguments (the first
    // is also `family`/`args` above), and the timing that moves between them.
    struct Member {
        const CheckedFamily* family = nullptr;
        std::vector<const ast::Expr*> args;
    };
    std::vector<Member> morph;
    const ast::Decl* morphTiming = nullptr;
    // One entry per parameter of the family: the layer's value, or null for the default.
    std::vector<const ast::Expr*> args;
    const ast::Expr* prop(std::string_view name) const {
        const ast::Property* p = decl->prop(name);
        return p ? p->value.get() : nullptr;
    }
};

// The most layers a scene may have (docs/language.md). Compile time and the time per pixel
// grow with the layers; past this a scene is refused with a located error.
constexpr int kMaxLayers = 1000;

struct CheckedScene {
    const ast::Decl* scene = nullptr;
    const ast::Decl* camera = nullptr;
    std::vector<CheckedLayer> layers;
    std::unordered_map<const ast::Decl*, CheckedFamily> families;
    std::unordered_map<std::string, const ast::Decl*> familyByName;
    std::unordered_map<const ast::Decl*, CheckedTiming> timings;
    std::vector<const ast::Decl*> timingOrder; // declaration order
    std::unordered_map<std::string, const ast::Decl*> easingByName;
    std::vector<const ast::Decl*> params; // the scene's `param`s, in declaration order
};

// Checks the standard library modules and the user's module together. Errors go to
// `diags`; the result is meaningful only when no error was reported.
CheckedScene check(const std::vector<ast::Module*>& modules, DiagEngine& diags);

} // namespace moire::sema
