#include "compiler/lex/Keywords.h"

#include <algorithm>

namespace moire {

const std::vector<std::string>& declarationKeywords() {
    static const std::vector<std::string> words = {"scene",  "camera", "layer",  "field",
                                                   "family", "timing", "easing", "param"};
    return words;
}

bool isKeyword(std::string_view word) {
    const std::vector<std::string>& decl = declarationKeywords();
    return word == kLetKeyword || std::find(decl.begin(), decl.end(), word) != decl.end();
}

bool isBuiltinValueName(std::string_view word) {
    return std::find(std::begin(kBuiltinValueNames), std::end(kBuiltinValueNames), word) !=
           std::end(kBuiltinValueNames);
}

} // namespace moire
