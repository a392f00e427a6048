#include "compiler/lower/FamilyRegistry.h"

#include "compiler/diag/Diagnostics.h"
#include "compiler/lower/LatticeFamily.h"
#include "compiler/lower/PencilFamily.h"
#include "compiler/lower/WalkingFamily.h"

namespace moire::lower {

const std::vector<RegisteredFamily>& registeredFamilies() {
    static const std::vector<RegisteredFamily> all = {
        {"square_lattice", latticeBuilder(LatticeKind::Square)},
        {"triangle_lattice", latticeBuilder(LatticeKind::Triangle)},
        {"hex_lattice", latticeBuilder(LatticeKind::Hex)},
        {"pencil", pencilBuilder()},
        {kWalking, walkingLayerFields},
    };
    return all;
}

const FamilyBuilder& familyBuilder(std::string_view name) {
    for (const RegisteredFamily& f : registeredFamilies())
        if (name == f.name) return f.build;
    MOIRE_ICE("no builder is registered for the builtin family '{}'", name);
}

} // namespace moire::lower
