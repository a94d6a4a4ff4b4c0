#include "vcmm/errormodel/atomic_file.h"

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <functional>
#include <thread>

namespace vcmm::errormodel {
namespace {

namespace fs = std::filesystem;

std::string os_reason(int err) { return err ? std::strerror(err) : "unknown reason"; }

fs::path directory_of(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

// A name beside the target, unique to the process, the thread and the call.
fs::path sibling(const fs::path& target, const char* kind) {
  static std::atomic<unsigned long> counter{0};
  std::string name = ".";  // built by appends: GCC 12 warns falsely on "." + string
  name += target.filename().string();
  name += kind;
  name += std::to_string(::getpid());
  name += ".";
  name += std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
  name += ".";
  name += std::to_string(counter.fetch_add(1));
  return directory_of(target) / name;
}

void refuse_non_regular(const std::string& path, const fs::path& target) {
  std::error_code ec;
  const fs::file_status st = fs::status(target, ec);
  if (!ec && fs::exists(st) && !fs::is_regular_file(st))
    throw OutputError(path + ": cannot write the result there: it exists and is not a regular "
                      "file (a directory or a device)");
}

void remove_quietly(const fs::path& p) {
  std::error_code ignored;
  fs::remove(p, ignored);
}

}  // namespace

void check_output_path(const std::string& path) {
  if (path.empty()) throw OutputError("an output path is empty");
  const fs::path target(path);
  refuse_non_regular(path, target);
  const fs::path dir = directory_of(target);
  std::error_code ec;
  const fs::file_status st = fs::status(dir, ec);
  if (!fs::exists(st))
    throw OutputError(path + ": cannot write the result there: the directory " + dir.string() +
                      " does not exist");
  if (!fs::is_directory(st))
    throw OutputError(path + ": cannot write the result there: " + dir.string() +
                      " is not a directory");
  if (::access(dir.c_str(), W_OK | X_OK) != 0)
    throw OutputError(path + ": cannot write the result there: the directory " + dir.string() +
                      ": " + os_reason(errno));
}

OutputTransaction::~OutputTransaction() { discard(); }

void OutputTransaction::discard() noexcept {
  for (const Staged& s : staged_) remove_quietly(s.tmp);
  staged_.clear();
}

void OutputTransaction::stage(const std::string& path, const std::string& content) {
  const fs::path target(path);
  refuse_non_regular(path, target);
  {
    std::error_code ec;
    const fs::path mine = fs::weakly_canonical(target, ec);
    for (const Staged& s : staged_) {
      std::error_code ec2;
      if (!ec && fs::weakly_canonical(s.target, ec2) == mine && !ec2)
        throw OutputError(path + ": the same file is given for two outputs (" + s.path + ")");
    }
  }
  const fs::path tmp = sibling(target, ".tmp.");
  errno = 0;
  std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
  if (!out) {
    const int err = errno;
    throw OutputError(path + ": cannot create the temporary file " + tmp.string() + ": " +
                      os_reason(err));
  }
  staged_.push_back({path, target, tmp});  // from here the destructor removes it
  out.write(content.data(), static_cast<std::streamsize>(content.size()));
  out.flush();
  if (!out) {
    const int err = errno;
    throw OutputError(path + ": write failed: " + os_reason(err));
  }
}

void OutputTransaction::commit() {
  struct Done {
    fs::path target;
    fs::path backup;  // empty: the target did not exist (or could not be linked)
  };
  std::vector<Done> done;
  done.reserve(staged_.size());
  for (std::size_t i = 0; i < staged_.size(); ++i) {
    const Staged& s = staged_[i];
    Done d{s.target, {}};
    std::error_code ec;
    if (fs::exists(s.target, ec)) {
      const fs::path backup = sibling(s.target, ".bak.");
      std::error_code lec;
      fs::create_hard_link(s.target, backup, lec);
      if (!lec) d.backup = backup;
    }
    fs::rename(s.tmp, s.target, ec);
    if (ec) {
      const std::string reason = ec.message();
      // Undo: restore what was replaced, remove what was new; the rest stays untouched.
      for (auto it = done.rbegin(); it != done.rend(); ++it) {
        std::error_code rec;
        if (!it->backup.empty())
          fs::rename(it->backup, it->target, rec);
        else
          remove_quietly(it->target);
      }
      if (!d.backup.empty()) remove_quietly(d.backup);
      // The message before discard(): discard() clears staged_, of which `s` is an element.
      std::string message = s.path + ": cannot move the result into place: " + reason +
                            (done.empty() ? std::string() : "; the other outputs of this run "
                                                            "were rolled back");
      discard();
      throw OutputError(message);
    }
    done.push_back(std::move(d));
  }
  for (const Done& d : done)
    if (!d.backup.empty()) remove_quietly(d.backup);
  staged_.clear();
}

void write_file_atomically(const std::string& path, const std::string& content) {
  OutputTransaction t;
  t.stage(path, content);
  t.commit();
}

}  // namespace vcmm::errormodel
