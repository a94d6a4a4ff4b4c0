// vcmm/errormodel/atomic_file.h — results are written to a temporary beside the target and
// renamed into place, so an interrupted run never leaves a half-written file that looks whole
// (STYLE.md, "Errors" 5). Shared by every module and the CLI that write files.
#pragma once

#include <string>

namespace vcmm::errormodel {

/// Writes `content` to `path` atomically: a temporary file in the same directory (named after
/// the target, the process and the thread, so concurrent writers never share one), flushed,
/// then renamed over `path` (POSIX rename is atomic within a file system). Throws
/// std::runtime_error naming the path on failure; the temporary is removed.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace vcmm::errormodel
