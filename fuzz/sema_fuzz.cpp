// Stage (b): source -> semantic checks (names, arity, types, units, constness). Any module
// that parses must check to a scene or to diagnostics that point into the text; never an
// internal error.
#include "fuzz/FuzzSupport.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    if (size > moire::fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    moire::fuzz::guarded("sema", [&] {
        auto front = moire::fuzz::runFront(text, /*check=*/true);
        moire::fuzz::checkDiagnostics(*front);
        (void)front->diags->render();
        for (const auto& layer : front->checked.layers)
            if (front->checkedOk && !layer.decl) moire::fuzz::finding("a layer without its decl");
    });
    return 0;
}
