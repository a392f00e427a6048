// Reading a whole text file (a scene), with a one-line reason when it cannot be read.
#pragma once

#include <cstddef>
#include <string>

namespace moire {

// The largest scene source read: 4 MiB, a hundred times the largest example. A longer file is
// refused rather than read without bound (a device such as /dev/zero never ends).
constexpr size_t kMaxSourceBytes = size_t{4} << 20;

// Reads all of `path` into `text`. Only a regular file is read: a directory, a FIFO, a socket
// or a device is refused without reading (and without waiting for a FIFO's writer), as is a
// file longer than kMaxSourceBytes. False, with the reason, when it cannot be read.
bool readWholeFile(const std::string& path, std::string& text, std::string& reason);

// Reads standard input to its end (a pipe, a file or a terminal), at most kMaxSourceBytes.
bool readStandardInput(std::string& text, std::string& reason);

} // namespace moire
