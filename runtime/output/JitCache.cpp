#include "runtime/output/JitCache.h"

#include "runtime/output/OutputFile.h"
#include "runtime/TextFile.h"

#include <cstdlib>
#include <cstring>
#include <elf.h>
#include <filesystem>
#include <fmt/format.h>
#include <link.h>

namespace moire {

namespace {

// The GNU build id of the running program, as hex ("" if it has none).
std::string buildId() {
    std::string id;
    dl_iterate_phdr(
        [](dl_phdr_info* info, size_t, void* out) -> int {
            // The first object listed is the program itself.
            for (int i = 0; i < info->dlpi_phnum; ++i) {
                const ElfW(Phdr)& ph = info->dlpi_phdr[i];
                if (ph.p_type != PT_NOTE) continue;
                auto* p = reinterpret_cast<const unsigned char*>(info->dlpi_addr + ph.p_vaddr);
                const unsigned char* end = p + ph.p_memsz;
                while (p + sizeof(ElfW(Nhdr)) <= end) {
                    auto* note = reinterpret_cast<const ElfW(Nhdr)*>(p);
                    const unsigned char* name = p + sizeof(ElfW(Nhdr));
                    const unsigned char* desc = name + ((note->n_namesz + 3) & ~3u);
                    if (note->n_type == NT_GNU_BUILD_ID && note->n_namesz == 4 &&
                        std::memcmp(name, "GNU", 4) == 0 && desc + note->n_descsz <= end) {
                        auto& s = *static_cast<std::string*>(out);
                        for (unsigned k = 0; k < note->n_descsz; ++k)
                            s += fmt::format("{:02x}", desc[k]);
                        return 1;
                    }
                    p = desc + ((note->n_descsz + 3) & ~3u);
                }
            }
            return 1;
        },
        &id);
    return id;
}

} // namespace

std::string JitCache::rootDirectory() {
    const char* dir = std::getenv("MOIRE_CACHE_DIR");
    if (dir && std::strcmp(dir, "off") == 0) return "";
    if (dir && *dir) return dir;
    const char* xdg = std::getenv("XDG_CACHE_HOME");
    if (xdg && *xdg == '/') return std::string(xdg) + "/moire/jit";
    const char* home = std::getenv("HOME");
    if (home && *home == '/') return std::string(home) + "/.cache/moire/jit";
    return "";
}

std::shared_ptr<JitCache> JitCache::forThisBuild() {
    std::string root = rootDirectory();
    std::string id = buildId();
    if (root.empty() || id.empty()) return nullptr;
    return std::make_shared<JitCache>(root + "/" + id);
}

std::optional<std::string> JitCache::load(const std::string& key) {
    std::string bytes, reason;
    if (!readWholeFile(dir_ + "/" + key + ".o", bytes, reason)) return std::nullopt;
    return bytes;
}

void JitCache::store(const std::string& key, std::string_view object) {
    try {
        std::error_code ec;
        std::filesystem::create_directories(dir_, ec);
        if (ec) return;
        writeFileAtomically(dir_ + "/" + key + ".o", object.data(), object.size());
    } catch (const std::exception&) {
        // A cache that cannot be written costs the next run a compile, nothing more.
    }
}

} // namespace moire
