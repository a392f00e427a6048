// Reading a whole text file (a scene), with a one-line reason when it cannot be read.
#pragma once

#include <string>

namespace moire {

// Reads all of `path` into `text`. False, with the reason (a directory, the system's error
// message), when it cannot be read.
bool readWholeFile(const std::string& path, std::string& text, std::string& reason);

} // namespace moire
