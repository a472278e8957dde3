// Files written whole or not at all: content goes to a temporary name in the same
// folder and is renamed into place, so a killed run never leaves a half-written file.
#pragma once

#include <string>

namespace tb {

/// Writes `content` to `path` atomically (temporary file + rename). Creates the
/// parent folder. Throws std::runtime_error naming the path on failure.
void write_file_atomically(const std::string& path, const std::string& content);

/// Reads a whole file. Throws MeshError(path, "cannot open file") if unreadable.
std::string read_file(const std::string& path);

}  // namespace tb
