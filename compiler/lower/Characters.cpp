#include "compiler/lower/Characters.h"

#include <vector>

namespace moire::lower {

using ir::BuiltValue;
using ir::ValueId;

namespace {

ValueId orZero(ir::Builder& b, ValueId v) {
    return v == ir::kNoValue ? b.constF(0.0) : v;
}

} // namespace

Character stackCharacter(ir::Builder& b, std::span<const LayerFields> layers) {
    Character out;
    out.count = static_cast<int>(std::min<size_t>(layers.size(), 3));
    const size_t first = layers.size() - static_cast<size_t>(out.count);
    std::vector<Grad<BuiltValue>> g;
    for (int i = 0; i < out.count; ++i) {
        const LayerFields& f = layers[first + static_cast<size_t>(i)];
        out.layer[static_cast<size_t>(i)] = static_cast<int>(first) + i;
        g.push_back({BuiltValue(b, orZero(b, f.gradX)), BuiltValue(b, orZero(b, f.gradY))});
    }
    if (g.empty()) {
        out.mu = b.constF(kNoCharacter);
        return out;
    }
    StackCharacterT<BuiltValue> best = bestStackCharacter<BuiltValue>(g);
    out.mu = best.mu.id;
    for (size_t i = 0; i < 3; ++i) out.k[i] = best.k[i].id;
    return out;
}

Combination characterCombination(ir::Builder& b, const Character& c,
                                 std::span<const LayerFields> layers) {
    ValueId value = b.constF(0.0), gx = value, gy = value;
    for (int i = 0; i < c.count; ++i) {
        const LayerFields& f = layers[static_cast<size_t>(c.layer[static_cast<size_t>(i)])];
        ValueId k = c.k[static_cast<size_t>(i)];
        value = b.add(value, b.mul(k, orZero(b, f.index)));
        gx = b.add(gx, b.mul(k, orZero(b, f.gradX)));
        gy = b.add(gy, b.mul(k, orZero(b, f.gradY)));
    }
    return {value, gx, gy};
}

ValueId characterOrder(ir::Builder& b, const Character& c) {
    ValueId order = b.constF(0.0);
    for (int i = 0; i < c.count; ++i) order = b.add(order, b.abs(c.k[static_cast<size_t>(i)]));
    return order;
}

} // namespace moire::lower
