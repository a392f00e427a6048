// Shared helpers for moire's tests: compiling scenes from text, running every backend that
// is available (one test body, every backend), reading files, comparing images, and skipping
// what cannot run here (Skip.h).
#pragma once

#include "compiler/backend/Backend.h"
#include "compiler/Compile.h"
#include "runtime/Image.h"
#include "tests/support/Skip.h"

#include <memory>
#include <string>
#include <sys/types.h>
#include <vector>

namespace moire::test {

// A path inside the source tree.
std::string sourcePath(const std::string& relative);
std::string readFile(const std::string& path);
// An image file's bytes with the time it was written ("2026:11:24 20:36:36", TIFF's and EXR's
// DateTime) zeroed, so that two files written at different seconds compare equal.
std::string imageBytesWithoutTime(const std::string& path);
// The `moire` executable built beside the tests.
std::string moireBinary();

// Compiles a scene that must be valid; fails the current test with its diagnostics if not.
std::unique_ptr<SceneProgram> compileOk(const std::string& text, const CompileOptions& options = {},
                                        const std::string& path = "test.moire");
// Compiles a scene that must be invalid; returns the rendered diagnostics.
std::string compileErrors(const std::string& text, const std::string& path = "test.moire");

// Backends that can run here. Each test body that checks a backend property loops over
// these; a backend missing at run time is skipped (tests/support/Skip.h), never failed.
std::vector<std::string> availableBackends();
std::unique_ptr<Backend> makeBackendOrSkip(const std::string& name);

// Renders frame `t` of a program at the given size (0: the scene's size) on a backend.
Image renderScene(const SceneProgram& program, Backend& backend, int width = 0, int height = 0,
                  double t = 0.0);

// The pixels [x0, x0 + width) x [y0, y0 + height) of frame `t` rendered at the scene's own
// size: a window at full resolution, without rendering the rest.
Image renderWindow(const SceneProgram& program, Backend& backend, int x0, int y0, int width,
                   int height, double t = 0.0);

// The slot of the literal `value` in the program's table (a sentinel written in the scene, to
// move that number between renders); fails the current test when there is none.
int literalSlot(const SceneProgram& program, double value);
// Runs an already compiled kernel of `program` over its frame with the literal table
// `literals` (the program's own, some moved), at the given size (0: the scene's), frame `t`.
Image runWithLiterals(const SceneProgram& program, CompiledKernel& kernel,
                      const std::vector<double>& literals, int width = 0, int height = 0,
                      double t = 0.0);

// Per-channel comparison of two images of the same size.
struct ImageDiff {
    size_t samples = 0; // pixels x channels compared
    double maxAbs = 0.0;
    double meanAbs = 0.0;
    size_t over = 0; // samples whose difference exceeds the tolerance given
    double fractionWithin() const {
        return samples ? 1.0 - static_cast<double>(over) / samples : 1.0;
    }
};
ImageDiff compareImages(const Image& a, const Image& b, double tolerance, int channels = 4);

// The example scenes (examples/*.moire), sorted, as paths relative to the source root.
std::vector<std::string> exampleScenes();

// A fresh directory under the system's temporary directory, removed with everything in it
// when the object goes.
class TempDir {
  public:
    explicit TempDir(const std::string& tag = "test");
    ~TempDir();
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const { return path_ + "/" + name; }
    void write(const std::string& name, const std::string& text) const;
    // The names in the directory, sorted, leaving out `except`.
    std::vector<std::string> names(const std::string& except = "") const;

  private:
    std::string path_;
};

// A finished moire: its exit status (128 + the signal when killed), its stderr and its peak
// resident memory in bytes.
struct Measured {
    int status = -1;
    std::string err;
    uint64_t maxRss = 0;
};

// Runs `moire ARGS` in `dir` (standard input and output /dev/null, stderr kept), under an
// address space limit when `addressLimit` is not 0, and measures its peak resident memory.
// Not wait4's ru_maxrss: Linux folds the memory the process had before its exec into it, and
// a child forked from a test binary starts with the binary's hundreds of megabytes. VmHWM in
// /proc/PID/status is the peak since the exec, read every few milliseconds while the child
// runs (a render peaks in its middle, not its last milliseconds), from when a close-on-exec
// pipe says the exec has happened.
Measured runMeasured(const std::vector<std::string>& args, const TempDir& dir,
                     uint64_t addressLimit = 0);

// Runs a command through the shell; returns its exit status and captures stdout/stderr.
struct CommandResult {
    int status = -1;
    std::string out, err;
};
CommandResult runCommand(const std::string& command);
// Runs `moire <args>` from the source root, so that a scene given as tests/errors/x.moire is
// named in the diagnostics exactly so.
CommandResult runMoireInSourceRoot(const std::string& args);

// The lines of `text`, without their newlines.
std::vector<std::string> lines(const std::string& text);

} // namespace moire::test
