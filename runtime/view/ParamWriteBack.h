// Writing the panel's parameter values back into the scene's text (the viewer's `W`): each
// changed parameter's default, where the declaration writes it as a plain literal, is replaced
// by the new value's literal (literalText), and every other byte is kept, comments and layout
// included. The reload that follows sees the same structure with other numbers, so the kernel
// is not compiled again.
//
// A default written as an expression (`1.5 * t`, `rgb(1, 0, 0)`, another parameter) is not
// overwritten: the expression is the scene's meaning (an animated value, a value tied to
// another), and a number in its place would freeze it at the instant of the write. Such a
// parameter is skipped, with the reason, for the viewer to say.
#pragma once

#include "runtime/view/ParamValues.h"

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace moire::view {

struct ParamWriteBack {
    std::string text;                 // the source with the edits made
    std::vector<std::string> written; // the parameters whose text changed, in source order
    std::vector<std::string> skipped; // `name: why` for each value that could not be written
};

// `source` (the text of file `fileId`) with each value of `set`, where set, written as the
// default of `params[i]`. A value equal to the literal already there changes nothing.
ParamWriteBack writeBackParameters(const std::string& source, uint32_t fileId,
                                   std::span<const Parameter> params, const ParamSet& set);

} // namespace moire::view
