// `moire serve`: the scene on a page in the browser (runtime/serve/), reloaded on every save.
#pragma once

#include "compiler/Defines.h"
#include "runtime/cli/Commands.h"

#include <string>

namespace moire::cli {

struct ServeArgs {
    std::string scene;
    std::string host = "127.0.0.1"; // another address only when given (and then a warning)
    bool hostGiven = false;
    int port = 0; // 0: any free port
    std::string backend = "jit";
    int device = -1;
    std::string size; // "WxH": a fixed frame size; empty: the page's
    double time = 0.0;
    bool paused = false;
    int threads = 0;
    int debounceMs = 30;
    Defines defines;    // -D NAME=VALUE: the scene's values before any slider moves
    std::string filter; // --filter point|mean (docs/filtering.md); empty: the scene's
    Verbosity verbosity;
};

// Serves until SIGINT or SIGTERM (exit 0). The page's address, with the run's token, is the
// first line on standard output.
int serve(const ServeArgs& args);

} // namespace moire::cli
