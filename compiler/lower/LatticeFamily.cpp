#include "compiler/lower/LatticeFamily.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::lower {

LatticeKind latticeKind(const std::string& familyName) {
    if (familyName == "square_lattice") return LatticeKind::Square;
    if (familyName == "triangle_lattice") return LatticeKind::Triangle;
    if (familyName == "hex_lattice") return LatticeKind::Hex;
    MOIRE_ICE("no builtin family named '{}'", familyName);
}

LayerFields latticeFields(ir::Builder& b, LatticeKind kind, const LatticeInputs& in) {
    MOIRE_ICE("lattices are not built yet");
}

} // namespace moire::lower
