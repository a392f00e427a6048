#include "runtime/serve/PageFiles.h"

#include <string>

namespace moire::serve::page {

namespace {
constexpr std::string_view kFolder = "runtime/serve/page/";

const char* contentTypeOf(std::string_view name) {
    auto endsWith = [&](std::string_view ext) {
        return name.size() >= ext.size() && name.substr(name.size() - ext.size()) == ext;
    };
    if (endsWith(".html")) return "text/html; charset=utf-8";
    if (endsWith(".css")) return "text/css; charset=utf-8";
    if (endsWith(".js")) return "text/javascript; charset=utf-8";
    return "application/octet-stream";
}
} // namespace

std::optional<Asset> asset(std::string_view name) {
    for (const File& f : files()) {
        std::string_view path = f.path;
        if (path.substr(0, kFolder.size()) == kFolder && path.substr(kFolder.size()) == name)
            return Asset{f.text, contentTypeOf(name)};
    }
    return std::nullopt;
}

} // namespace moire::serve::page
