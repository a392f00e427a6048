// `moire fmt` (compiler/format): any bytes either are refused with the parser's diagnostics or
// come back formatted; formatting never reports that its own output would change the scene
// (formatSource compares the trees and comments of its input and output, so a layout that
// lost a comment, a sign or a parenthesis is caught there), and formatting twice changes
// nothing.
#include "compiler/format/Formatter.h"
#include "fuzz/FuzzSupport.h"

#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
    using namespace moire;
    if (size > fuzz::kMaxInput) return -1;
    std::string text(reinterpret_cast<const char*>(data), size);
    fuzz::guarded("format", [&] {
        format::FormatResult once = format::formatSource("fuzz.moire", text);
        if (!once.ok) {
            if (once.diagnostics.starts_with("moire: internal error"))
                fuzz::finding(once.diagnostics);
            return;
        }
        format::FormatResult twice = format::formatSource("fuzz.moire", once.text);
        if (!twice.ok) fuzz::finding("the formatted text is refused:\n" + twice.diagnostics);
        if (twice.text != once.text)
            fuzz::finding("formatting twice changes the text:\n" + once.text + "\n--\n" +
                          twice.text);
    });
    return 0;
}
