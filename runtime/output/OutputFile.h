// Every file moire writes reaches the disk through this one place (images of render, clip,
// watch and the viewer's stills as bytes encoded in memory; videos as a temporary that
// ffmpeg filled). It is the one place that talks to the file system when writing, so that
// an output written wrong without an error (a full disk turned into a truncated image and
// "wrote", a 0-byte frame, a libjpeg exit(1)) cannot come back through a writer of its own:
// tests/output_safety_test.cpp fails when code outside this file opens a file for writing.
//
// The rules it keeps:
//   - the bytes go to a temporary beside the target, named for this process
//     (.<stem>.<pid>-<start>-<n>.tmp<ext>), and are renamed into place only once every
//     write(2), the fsync(2) and the close(2) have succeeded, so a reader never sees half a
//     file and a failed write leaves any earlier file untouched;
//   - every failure removes the temporary and throws IoError("cannot write '<path>':
//     <the system's words for errno>"), naming the user's path, never the temporary;
//   - a temporary whose process has gone (killed mid-write) is removed by the next command
//     that writes into its directory (removeStaleTemporaries).
#pragma once

#include "runtime/output/ImageIO.h"

#include <cstddef>
#include <string>

namespace moire {

// A file written piece by piece under the same rules: the pieces go to a temporary beside
// `path`, and commit() moves it into place (a file replaced keeps its permissions). Dropped
// without a commit (a failed write, an exception on the way), the temporary is removed and
// any earlier file is left as it was. Every failure throws IoError naming `path`.
class AtomicFile {
  public:
    explicit AtomicFile(const std::string& path);
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    void write(const void* data, size_t size);
    // fsync, close, rename into place. A destination that exists and is not a regular file
    // (/dev/null, a FIFO) is written straight into instead, never replaced.
    void commit();
    // The temporary's descriptor, for a writer that seeks back (TIFF, EXR: OiioCodec.h) and
    // writes at offsets (pwrite) instead of write(); not when writtenInPlace().
    int descriptor() const { return fd_; }
    // The destination is not a regular file and is written straight into: it cannot seek.
    bool writtenInPlace() const { return temp_.empty(); }

  private:
    [[noreturn]] void fail(int error);
    std::string path_, temp_;
    int fd_ = -1;
};

// Writes `size` bytes to `path` through a temporary beside it (one AtomicFile). Throws IoError.
void writeFileAtomically(const std::string& path, const void* data, size_t size);

// Writes `size` bytes to standard output (render -o -), every write checked. Throws
// IoError("cannot write to standard output: ...").
void writeStandardOutput(const void* data, size_t size);

// A fresh temporary name beside `target`, keeping its extension (ffmpeg chooses the
// container by it), in the naming removeStaleTemporaries recognises.
std::string temporaryBeside(const std::string& target);

// Moves a temporary that another process (ffmpeg) has finished writing into place: fsync,
// then rename. Removes the temporary and throws IoError naming `path` on failure.
void commitTemporary(const std::string& temp, const std::string& path);

// Creates the directory that will hold `path` when it is missing (a fresh folder of frames,
// render -o out/x.png). Throws IoError naming the directory when something else is there.
void prepareOutputDirectory(const std::string& path);

// Removes, from the directory that holds `path`, the temporaries of moire processes that are
// no longer running: the process is gone, or its number now belongs to a process started at
// another time. Returns how many it removed; never throws.
int removeStaleTemporaries(const std::string& path);

} // namespace moire
