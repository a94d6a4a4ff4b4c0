// vcmm/errormodel/atomic_file.h — results are written to a temporary beside the target and
// renamed into place, so an interrupted run never leaves a half-written file that looks whole
// (STYLE.md, "Errors" 5). Shared by every module and the CLI that write files.
#pragma once

#include <stdexcept>
#include <string>

namespace vcmm::errormodel {

/// A result file cannot be written: the message names the path and the operating system's
/// reason ("out/r.json: cannot create the temporary file …: No such file or directory"). A
/// user error (a missing or read-only directory, a full disk), not a bug: the CLI exits 3.
class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Writes `content` to `path` atomically: a temporary file in the same directory (named after
/// the target, the process and the thread, so concurrent writers never share one), flushed,
/// then renamed over `path` (POSIX rename is atomic within a file system). Refuses a `path`
/// that exists and is not a regular file (a directory, a device such as /dev/null: renaming
/// over it would replace it). Throws OutputError naming the path and the reason on failure;
/// the temporary is removed.
void write_file_atomically(const std::string& path, const std::string& content);

}  // namespace vcmm::errormodel
