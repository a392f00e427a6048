// Rebuilding a scene as its source changes, the way live coding needs it: the front end runs
// on every new text, and the backend compiles a kernel only when the kernel's structure
// changed. A change of numbers alone keeps the compiled kernel and changes only uniforms.
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"

#include <cstdint>
#include <memory>
#include <string>

namespace moire {

// One good build of a scene: the front end's program and the backend's kernel for it.
struct LiveProgram {
    std::shared_ptr<const SceneProgram> program;
    // Shared with the previous build when only numbers changed.
    std::shared_ptr<const CompiledKernel> kernel;
    uint64_t contentHash = 0;
};

struct BuildResult {
    enum class Kind {
        Unchanged, // the same bytes as the last text built (good or bad): nothing done
        Failed,    // the text has errors; the current build stays
        Numbers,   // a new build whose kernel is the current one's (uniforms only)
        Structure, // a new build with a newly compiled (or cached) kernel
    };
    Kind kind = Kind::Unchanged;
    uint64_t contentHash = 0;
    std::string diagnostics; // Failed: rendered `file:line:col: error:` lines; else any notes
    std::shared_ptr<const LiveProgram> build; // Numbers and Structure: the new current build
    double frontEndMs = 0.0, kernelMs = 0.0;
    bool unreadable = false; // Failed because the file could not be read

    bool good() const { return kind == Kind::Numbers || kind == Kind::Structure; }
};

// A 64-bit FNV-1a hash of the bytes.
uint64_t contentHash(const std::string& bytes);

class SceneBuilder {
  public:
    // `backend` must outlive the builder and every LiveProgram it returns.
    explicit SceneBuilder(Backend& backend, CompileOptions options = {});

    // Builds `text` (diagnostics name `path`). Never throws for any input: a moire bug found
    // on the way (an internal compiler error, a backend failure) comes back as Failed with
    // its message, and the current build stays.
    BuildResult build(const std::string& path, const std::string& text);

    // Reports a text that could not be read at all (a deleted file): Failed, with `message`.
    BuildResult unreadable(const std::string& message);

    // The last good build, or null before the first.
    std::shared_ptr<const LiveProgram> current() const { return current_; }

    // Counters, for tests and benchmarks: front-end compilations, and kernels this builder
    // asked the backend to compile because the structure changed.
    int frontEndCompiles() const { return frontEnd_; }
    int kernelBuilds() const { return kernels_; }

  private:
    Backend& backend_;
    CompileOptions options_;
    std::shared_ptr<const LiveProgram> current_;
    uint64_t lastHash_ = 0;
    bool haveLast_ = false;
    int frontEnd_ = 0, kernels_ = 0;
};

} // namespace moire
