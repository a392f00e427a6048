// Stage (b): source -> semantic checks (names, arity, types, units, constness). Any module
// that parses must check to a scene or to diagnostics that point into the text; never an
// internal error.
#include "compiler/sema/Symbols.h"
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
        // The symbol table an editor asks for, also of a module that did not parse or check:
        // every declaration and reference points into the text.
        std::vector<const moire::ast::Module*> modules;
        for (auto& m : front->modules) modules.push_back(m.get());
        auto inText = [&](moire::SourceRange r) {
            return r.begin.file < front->sources->size() &&
                   r.begin.offset <= front->sources->file(r.begin.file).text().size();
        };
        for (const moire::sema::Symbol& s : moire::sema::collectSymbols(modules).symbols) {
            if (!inText(s.declaration)) moire::fuzz::finding("a symbol declared outside the text");
            for (moire::SourceRange r : s.references)
                if (!inText(r)) moire::fuzz::finding("a symbol referred to outside the text");
        }
    });
    return 0;
}
