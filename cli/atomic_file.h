// cli/atomic_file.h — results are written to a temporary beside the target and renamed into
// place, so an interrupted run never leaves a half-written file that looks whole.
#pragma once

#include <string>

namespace vcmm::cli {

/// Writes `content` to `path` atomically (temporary file in the same directory, flushed,
/// then std::filesystem::rename). Throws std::runtime_error naming the path on failure; the
/// temporary is removed.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace vcmm::cli
