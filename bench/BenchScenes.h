// The scenes the benchmarks measure: the embedded default scene and every example, or the
// files named on the command line.
#pragma once

#include "compiler/Compile.h"
#include "runtime/TextFile.h"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace moire::bench {

struct Scene {
    std::string name, path, text;
};

// A scene file named by the user; exits with a message when it cannot be read.
inline Scene sceneFile(const std::string& path) {
    Scene s{std::filesystem::path(path).stem().string(), path, {}};
    std::string reason;
    if (!readWholeFile(path, s.text, reason)) {
        std::fprintf(stderr, "cannot read %s: %s\n", path.c_str(), reason.c_str());
        std::exit(2);
    }
    return s;
}

// The default scene, then examples/*.moire in name order.
inline std::vector<Scene> defaultScenes() {
    std::vector<Scene> out;
    EmbeddedScene d = defaultScene();
    out.push_back({"default", d.path, d.text});
    std::vector<std::string> paths;
    for (auto& e : std::filesystem::directory_iterator(MOIRE_SOURCE_DIR "/examples"))
        if (e.path().extension() == ".moire") paths.push_back(e.path().string());
    std::sort(paths.begin(), paths.end());
    for (const std::string& p : paths) out.push_back(sceneFile(p));
    return out;
}

// Reads the options every benchmark takes, --size WxH and --repeat N, at argv[i] (moving i
// past a value); false when argv[i] is neither.
inline bool sizeOrRepeat(int argc, char** argv, int& i, int& w, int& h, int& repeat) {
    std::string a = argv[i];
    if (a == "--size" && i + 1 < argc)
        std::sscanf(argv[++i], "%dx%d", &w, &h);
    else if (a == "--repeat" && i + 1 < argc)
        repeat = std::max(1, std::atoi(argv[++i]));
    else
        return false;
    return true;
}

} // namespace moire::bench
