// Where the LLVM backend may keep the object code it generates between runs, so that a second
// `moire render` of a kernel with the same structure skips optimisation and code generation.
// The backend only computes keys and bytes; a store (runtime/JitCache for the command line)
// decides where they live. A store that fails to load or keep an object loses nothing but
// time: the backend compiles again.
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace moire {

class ObjectStore {
  public:
    virtual ~ObjectStore() = default;
    // The object kept under `key`, if any. `key` is a file-name-safe string that already
    // names everything the code depends on except the program's own build.
    virtual std::optional<std::string> load(const std::string& key) = 0;
    virtual void store(const std::string& key, std::string_view object) = 0;
};

} // namespace moire
