// A morph (§8.3): `family = morph(timing, f0, f1, ...)`, a layer travelling from one family
// to the next over the timing's pass.
#pragma once

#include "compiler/lower/LayerLowering.h"

namespace moire::lower {

LayerFields morphFields(LayerLowering& layers, const sema::CheckedLayer& layer,
                        const LayerFrame& lf, const StrokeBand& band, const Encoding& enc,
                        bool wantIndex);

} // namespace moire::lower
