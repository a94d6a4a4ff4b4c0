// vcmm/errormodel/atomic_file.h — results are written to a temporary beside the target and
// renamed into place, so an interrupted run never leaves a half-written file that looks whole
// (STYLE.md, "Errors" 5). Shared by every module and the CLI that write files.
#pragma once

#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

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

/// All the files of one command appear together or not at all (STYLE.md, "Errors" 5).
/// stage() checks the target (as write_file_atomically does; the same target twice in one
/// transaction is refused) and writes the content to a flushed temporary beside it — where a
/// full disk or a missing directory shows — so a failing stage() leaves no file of the set.
/// commit() renames every temporary into place; an existing target is first hard-linked to a
/// backup so that, should a rename fail, the targets already replaced are restored and those
/// that did not exist are removed (then OutputError). Destroying an uncommitted transaction
/// removes its temporaries: an exception between the stages and the commit writes nothing.
class OutputTransaction {
 public:
  OutputTransaction() = default;
  OutputTransaction(const OutputTransaction&) = delete;
  OutputTransaction& operator=(const OutputTransaction&) = delete;
  ~OutputTransaction();

  void stage(const std::string& path, const std::string& content);
  void commit();
  /// Removes the staged temporaries (also done by the destructor).
  void discard() noexcept;

 private:
  struct Staged {
    std::string path;  ///< as the user gave it, for messages
    std::filesystem::path target;
    std::filesystem::path tmp;
  };
  std::vector<Staged> staged_;
};

/// Pre-flight check of an output path before a long computation: the path is not an existing
/// directory or device and its directory exists and is a directory. Throws OutputError naming
/// the path and the reason. (The write itself may still fail later: a full disk, permissions.)
void check_output_path(const std::string& path);

}  // namespace vcmm::errormodel
