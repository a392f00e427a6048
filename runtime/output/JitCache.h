// The on-disk store of the JIT's object code (compiler/backend/llvm/ObjectStore.h) that the
// command line uses: a second `moire render` of a kernel with the same structure loads its
// code instead of compiling it.
//
// The cache lives in $MOIRE_CACHE_DIR, else $XDG_CACHE_HOME/moire/jit, else
// ~/.cache/moire/jit, in a folder per build of moire (named by the program's GNU build id), so
// a rebuilt moire never loads another build's code. MOIRE_CACHE_DIR=off turns it off.
// Deleting the folder clears it. Objects are written through a temporary and renamed, so a
// reader never sees half of one; a store that cannot be read or written is skipped silently:
// the kernel is compiled as if there were no cache.
#pragma once

#include "compiler/backend/llvm/ObjectStore.h"

#include <memory>
#include <string>

namespace moire {

class JitCache : public ObjectStore {
  public:
    explicit JitCache(std::string directory) : dir_(std::move(directory)) {}
    // The cache of this build of moire where the environment says; null when it is off or no
    // folder can be named (no HOME).
    static std::shared_ptr<JitCache> forThisBuild();
    // The folder the cache of every build lives in (what to delete to clear it), or "" when
    // the cache is off.
    static std::string rootDirectory();

    std::optional<std::string> load(const std::string& key) override;
    void store(const std::string& key, std::string_view object) override;
    const std::string& directory() const { return dir_; }

  private:
    std::string dir_;
};

} // namespace moire
