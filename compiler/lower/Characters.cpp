#include "compiler/lower/Characters.h"

#include <vector>

namespace moire::lower {

using ir::BuiltValue;
using ir::ValueId;

namespace {

ValueId orZero(ir::Builder& b, ValueId v) {
    return v == ir::kNoValue ? b.constF(0.0) : v;
}

// The fractional index a one-index layer's characters combine (LayerFields::smooth).
ValueId indexOf(ir::Builder& b, const LayerFields& f) {
    return f.smooth != ir::kNoValue ? f.smooth : orZero(b, f.index);
}

bool isLattice(const LayerFields& f) {
    return f.genU != ir::kNoValue;
}

// kLatticeRows[row][column] for a row number held as a value (0 to 3).
ValueId rowCoefficient(ir::Builder& b, ValueId row, size_t column) {
    ValueId v = b.constF(kLatticeRows.back()[column]);
    for (size_t r = kLatticeRows.size() - 1; r-- > 0;)
        v = b.select(b.lt(row, b.constF(double(r) + 0.5)), b.constF(kLatticeRows[r][column]), v);
    return v;
}

} // namespace

std::vector<IndexField> characterRows(ir::Builder& b, const LayerFields& f) {
    if (!isLattice(f)) return {{indexOf(b, f), orZero(b, f.gradX), orZero(b, f.gradY)}};
    auto built = [&](ValueId v) { return BuiltValue(b, v); };
    const BuiltValue u = built(f.genU), v = built(f.genV);
    std::vector<Grad<BuiltValue>> grads = latticeRowGradients<BuiltValue>(
        {built(f.genUX), built(f.genUY)}, {built(f.genVX), built(f.genVY)});
    std::vector<IndexField> out;
    for (size_t r = 0; r < kLatticeRows.size(); ++r) {
        const BuiltValue value = smallCombination(kLatticeRows[r][0], u, kLatticeRows[r][1], v);
        out.push_back({value.id, grads[r].x.id, grads[r].y.id});
    }
    return out;
}

Character stackCharacter(ir::Builder& b, std::span<const LayerFields> layers) {
    Character out;
    out.count = static_cast<int>(std::min<size_t>(layers.size(), 3));
    const size_t first = layers.size() - static_cast<size_t>(out.count);
    std::vector<std::vector<Grad<BuiltValue>>> rows;
    for (int i = 0; i < out.count; ++i) {
        const LayerFields& f = layers[first + static_cast<size_t>(i)];
        out.layer[static_cast<size_t>(i)] = static_cast<int>(first) + i;
        std::vector<Grad<BuiltValue>> g;
        for (const IndexField& r : characterRows(b, f))
            g.push_back({BuiltValue(b, r.gradX), BuiltValue(b, r.gradY)});
        rows.push_back(std::move(g));
    }
    if (rows.empty()) {
        out.mu = b.constF(kNoCharacter);
        return out;
    }
    StackCharacterT<BuiltValue> best = bestStackCharacterOfRows<BuiltValue>(rows);
    out.mu = best.mu.id;
    for (size_t i = 0; i < 3; ++i) out.k[i] = best.k[i].id;
    for (int i = 0; i < out.count; ++i) {
        const size_t at = static_cast<size_t>(i);
        if (!isLattice(layers[first + at])) continue;
        out.rowU[at] = rowCoefficient(b, best.row[at].id, 0);
        out.rowV[at] = rowCoefficient(b, best.row[at].id, 1);
    }
    return out;
}

std::array<ValueId, 2> characterGenerators(ir::Builder& b, const Character& c, int i) {
    const size_t at = static_cast<size_t>(i);
    if (c.rowU[at] == ir::kNoValue) return {c.k[at], b.constF(0.0)};
    return {b.mul(c.k[at], c.rowU[at]), b.mul(c.k[at], c.rowV[at])};
}

Combination characterCombination(ir::Builder& b, const Character& c,
                                 std::span<const LayerFields> layers) {
    ValueId value = b.constF(0.0), gx = value, gy = value;
    for (int i = 0; i < c.count; ++i) {
        const LayerFields& f = layers[static_cast<size_t>(c.layer[static_cast<size_t>(i)])];
        // The layer's term: k idx, or a lattice's k (rowU u + rowV v).
        auto [ku, kv] = characterGenerators(b, c, i);
        if (c.rowU[static_cast<size_t>(i)] == ir::kNoValue) {
            value = b.add(value, b.mul(ku, indexOf(b, f)));
            gx = b.add(gx, b.mul(ku, orZero(b, f.gradX)));
            gy = b.add(gy, b.mul(ku, orZero(b, f.gradY)));
            continue;
        }
        value = b.add(value, b.add(b.mul(ku, f.genU), b.mul(kv, f.genV)));
        gx = b.add(gx, b.add(b.mul(ku, f.genUX), b.mul(kv, f.genVX)));
        gy = b.add(gy, b.add(b.mul(ku, f.genUY), b.mul(kv, f.genVY)));
    }
    return {value, gx, gy};
}

ValueId characterOrder(ir::Builder& b, const Character& c) {
    ValueId order = b.constF(0.0);
    for (int i = 0; i < c.count; ++i) order = b.add(order, b.abs(c.k[static_cast<size_t>(i)]));
    return order;
}

} // namespace moire::lower
