#include "vcmm/geometry/text_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>

#include "vcmm/geometry/point.h"

namespace vcmm::geometry {
namespace {

struct FileCloser {
  void operator()(std::FILE* f) const { std::fclose(f); }
};
using File = std::unique_ptr<std::FILE, FileCloser>;

std::string os_reason(int error) {
  if (error == ENOENT) return "no such file";
  if (error == EISDIR) return "it is a directory, not a file";
  return std::strerror(error);
}

/// Opens `path`; on failure returns null and sets `reason`.
File open_for_reading(const std::string& path, std::string& reason) {
  if (path.empty()) {
    reason = "no file name given";
    return nullptr;
  }
  errno = 0;
  File f(std::fopen(path.c_str(), "rb"));
  if (!f) {
    reason = os_reason(errno != 0 ? errno : EIO);
    return nullptr;
  }
  struct stat st {};
  if (::fstat(::fileno(f.get()), &st) == 0 && S_ISDIR(st.st_mode)) {
    reason = os_reason(EISDIR);
    return nullptr;
  }
  return f;
}

}  // namespace

bool try_read_text_file(const std::string& path, std::string& text, std::string& reason) {
  text.clear();
  File f = open_for_reading(path, reason);
  if (!f) return false;
  char buf[1 << 16];
  std::size_t got = 0;
  while ((got = std::fread(buf, 1, sizeof buf, f.get())) > 0) text.append(buf, got);
  if (std::ferror(f.get())) {
    reason = os_reason(errno != 0 ? errno : EIO);
    return false;
  }
  return true;
}

std::string read_text_file(const std::string& path, std::string_view what) {
  std::string text, reason;
  if (!try_read_text_file(path, text, reason))
    throw InvalidInput(path + ": cannot read the " + std::string(what) + ": " + reason);
  return text;
}

}  // namespace vcmm::geometry
