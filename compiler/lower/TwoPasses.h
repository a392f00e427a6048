// A piece of IR needed at two inputs, built once: two passes of a loop (WalkingChains.cpp,
// ChainSelection.cpp), where calling its builder twice would write it into the kernel twice.
#pragma once

#include "compiler/ir/Builder.h"

#include <span>
#include <utility>
#include <vector>

namespace moire::lower {

// Runs `body(second)` as two passes of one loop, `second` a bool of the kernel, false on the
// first pass and true on the second; returns what each pass yielded (`width` values each).
template <class Body>
std::pair<std::vector<ir::ValueId>, std::vector<ir::ValueId>> twoPasses(ir::Builder& b,
                                                                        size_t width, Body body) {
    using Vals = std::vector<ir::ValueId>;
    const Vals res = b.loop(
        Vals(1 + 2 * width, b.constF(0.0)),
        [&](std::span<const ir::ValueId> v) { return Vals{b.lt(v[0], b.constF(2.0))}; },
        [&](std::span<const ir::ValueId> v) {
            const ir::ValueId second = b.emit(ir::Op::Eq, {v[0], b.constF(1.0)});
            const Vals got = body(second);
            Vals out{b.add(v[0], b.constF(1.0))};
            for (size_t k = 0; k < width; ++k) out.push_back(b.select(second, v[1 + k], got[k]));
            for (size_t k = 0; k < width; ++k)
                out.push_back(b.select(second, got[k], v[1 + width + k]));
            return out;
        });
    return {Vals(res.begin() + 1, res.begin() + 1 + width),
            Vals(res.begin() + 1 + width, res.end())};
}

} // namespace moire::lower
