// Bisection over whole indices, built as IR: the walking solver's searches for a crossing or
// a run of members (WalkingFamily.cpp, WalkingChains.cpp).
#pragma once

#include "compiler/ir/Builder.h"

#include <span>
#include <vector>

namespace moire::lower {

// The first n in [lo, hi] where `holds` (monotone: false, then true), or hi where it never
// does: one evaluation a step, log2(hi - lo) steps. `holds(n)` emits the test at n.
template <class Holds>
ir::ValueId firstWhere(ir::Builder& b, ir::ValueId lo, ir::ValueId hi, Holds holds) {
    using Vals = std::vector<ir::ValueId>;
    Vals res = b.loop(
        {lo, b.max(lo, hi)}, [&](std::span<const ir::ValueId> v) { return Vals{b.lt(v[0], v[1])}; },
        [&](std::span<const ir::ValueId> v) {
            ir::ValueId mid = b.floor(b.mul(b.add(v[0], v[1]), b.constF(0.5)));
            ir::ValueId yes = holds(mid);
            return Vals{b.select(yes, v[0], b.add(mid, b.constF(1.0))), b.select(yes, mid, v[1])};
        });
    return res[0];
}

} // namespace moire::lower
