// `moire fmt`: rewrites scene files in the canonical layout (compiler/format/Formatter.h,
// docs/formatting.md), or with --check only names the files that are not in it.
#include "compiler/format/Formatter.h"
#include "runtime/cli/Shared.h"
#include "runtime/output/OutputFile.h"

#include <fmt/format.h>

namespace moire::cli {

int formatFiles(const FmtArgs& args) {
    int status = kExitOk;
    auto fail = [&](int code) {
        if (status == kExitOk) status = code;
    };
    for (const std::string& path : args.files) {
        Source src;
        if (path.empty()) { // readScene would read the embedded default scene
            fmt::print(stderr, "moire: error: an empty file name\n");
            fail(kExitIo);
            continue;
        }
        if (!readScene(path, src)) {
            fail(kExitIo);
            continue;
        }
        format::FormatResult r = format::formatSource(src.path, src.text);
        if (!r.ok) {
            fmt::print(stderr, "{}", r.diagnostics);
            fail(kExitScene);
            continue;
        }
        bool changed = r.text != src.text;
        if (args.check) {
            if (changed) {
                if (!args.verbosity.quiet) fmt::print("{}\n", path);
                fail(kExitScene);
            }
            continue;
        }
        try {
            // A file already formatted is not written at all: its time stamp (and a watcher
            // such as `moire watch`) is left alone.
            if (path == kStdinPath)
                writeStandardOutput(r.text.data(), r.text.size());
            else if (changed)
                writeFileAtomically(path, r.text.data(), r.text.size());
        } catch (const IoError& e) {
            fmt::print(stderr, "moire: error: {}\n", e.what());
            fail(kExitIo);
            continue;
        }
        if (args.verbosity.verbose && path != kStdinPath)
            fmt::print(stderr, "moire: {} {}\n",
                       changed ? "formatted" : "already formatted:", path);
    }
    return status;
}

} // namespace moire::cli
