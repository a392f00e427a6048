#include "compiler/lower/Timings.h"

#include "compiler/diag/Diagnostics.h"

namespace moire::lower {

using ir::Op;
using ir::ValueId;

const TimingLowering::Lowered& TimingLowering::lowered(const ast::Decl* timing) {
    auto it = done_.find(timing);
    if (it != done_.end()) return it->second;
    const sema::CheckedTiming& ct = scene_.timings.at(timing);
    // Emitted in the entry block, so that the values dominate every later use even when the
    // first use is inside a region (a family's phase evaluated in a walking search, say).
    const ir::BlockId saved = b_.block();
    b_.setBlock(0);
    b_.setLoc(timing->range.begin);
    Frame constants;
    ValueId period = b_.max(exprs_.scalar(*ct.period, constants), b_.constF(1e-6));
    ValueId delay = ct.delay ? exprs_.scalar(*ct.delay, constants) : b_.constF(0.0);
    ValueId t = b_.leaf(Op::Time);
    ValueId zero = b_.constF(0.0), one = b_.constF(1.0);
    ValueId raw = zero;
    switch (ct.mode) {
    case sema::TimingMode::Once: // 0 until the delay, 0 to 1 over the period, then 1
        raw = b_.clamp(b_.div(b_.sub(t, delay), period), zero, one);
        break;
    case sema::TimingMode::Loop: { // every delay + period seconds: hold at 0, then 0 to 1
        ValueId cycle = b_.add(delay, period);
        ValueId into = b_.emit(Op::Mod, {t, cycle});
        raw = b_.clamp(b_.div(b_.sub(into, delay), period), zero, one);
        break;
    }
    case sema::TimingMode::PingPong: { // every delay + 2 period: hold, 0 to 1, 1 back to 0
        ValueId cycle = b_.add(delay, b_.mul(period, b_.constF(2.0)));
        ValueId into = b_.emit(Op::Mod, {t, cycle});
        ValueId a = b_.clamp(b_.div(b_.sub(into, delay), period), zero, b_.constF(2.0));
        raw = b_.select(b_.le(a, one), a, b_.sub(b_.constF(2.0), a));
        break;
    }
    }
    ValueId eased = raw;
    if (ct.easing) {
        Frame e;
        e.u = raw;
        eased = exprs_.scalar(*ct.easing->value, e);
    }
    b_.setBlock(saved);
    return done_.emplace(timing, Lowered{period, delay, {raw, eased}}).first->second;
}

Progress TimingLowering::progress(const ast::Decl* timing) {
    return lowered(timing).progress;
}

ValueId TimingLowering::period(const ast::Decl* timing) {
    return lowered(timing).period;
}

ValueId TimingLowering::ease(const std::string& easing, ValueId u) {
    auto it = scene_.easingByName.find(easing);
    MOIRE_CHECK(it != scene_.easingByName.end(), "no easing named '{}'", easing);
    Frame e;
    e.u = u;
    return exprs_.scalar(*it->second->value, e);
}

void TimingLowering::outputSettings(OutputLayout& layout, int firstSlot) {
    int slot = firstSlot;
    for (const ast::Decl* timing : scene_.timingOrder) {
        auto it = done_.find(timing);
        if (it == done_.end()) continue; // declared but never used: no part of the clip
        const sema::CheckedTiming& ct = scene_.timings.at(timing);
        const double mode = ct.mode == sema::TimingMode::Once   ? 0
                            : ct.mode == sema::TimingMode::Loop ? 1
                                                                : 2;
        // The period as written (not floored), so that the frame's checks can report it.
        Frame constants;
        b_.output(slot++, exprs_.scalar(*ct.period, constants));
        b_.output(slot++, it->second.delay);
        b_.output(slot++, b_.constF(mode));
        layout.timings.push_back(timing->name);
        layout.timingPeriods.push_back(ct.period->range);
        layout.timingDelays.push_back(ct.delay ? ct.delay->range : timing->nameRange);
    }
}

} // namespace moire::lower
