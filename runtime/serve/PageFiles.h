// The page `moire serve` sends (runtime/serve/page/: plain HTML, CSS and JavaScript, no build
// step), compiled into the binary by cmake/Embed.cmake so that the server reads no file but
// the scene.
#pragma once

#include <optional>
#include <string_view>
#include <vector>

namespace moire::serve::page {

struct File {
    const char* path; // relative to the source root: "runtime/serve/page/page.js"
    std::string_view text;
};

// Every file of the page (generated).
const std::vector<File>& files();

struct Asset {
    std::string_view text;
    const char* contentType;
};

// The page's file `name` ("index.html", "page.js", "page.css"), if there is one.
std::optional<Asset> asset(std::string_view name);

} // namespace moire::serve::page
