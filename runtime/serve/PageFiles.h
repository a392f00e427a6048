// The page `moire serve` sends (runtime/serve/page/: plain HTML, CSS and JavaScript, no build
// step), compiled into the binary by cmake/Embed.cmake so that the server reads no file but
// the scene, as moire::embedded::servePage().
#pragma once

#include <optional>
#include <string_view>

namespace moire::serve::page {

struct Asset {
    std::string_view text;
    const char* contentType;
};

// The page's file `name` ("index.html", "page.js", "page.css"), if there is one.
std::optional<Asset> asset(std::string_view name);

} // namespace moire::serve::page
