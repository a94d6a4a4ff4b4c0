#include "vcmm/errormodel/atomic_file.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <thread>

namespace vcmm::errormodel {

void write_file_atomically(const std::string& path, const std::string& content) {
  namespace fs = std::filesystem;
  const fs::path target(path);
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  std::string name = ".";  // built by appends: GCC 12 warns falsely on "." + string
  name += target.filename().string();
  name += ".tmp.";
  name += std::to_string(::getpid());
  name += ".";
  name += std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()));
  const fs::path tmp = dir / name;
  {
    std::error_code ec;
    const fs::file_status st = fs::status(target, ec);
    if (!ec && fs::exists(st) && !fs::is_regular_file(st))
      throw OutputError(path + ": cannot write the result there: it exists and is not a regular "
                        "file (a directory or a device)");
  }
  {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      const int err = errno;
      throw OutputError(path + ": cannot create the temporary file " + tmp.string() + ": " +
                        (err ? std::strerror(err) : "unknown reason"));
    }
    out.write(content.data(), static_cast<std::streamsize>(content.size()));
    out.flush();
    if (!out) {
      const int err = errno;
      out.close();
      std::error_code ec;
      fs::remove(tmp, ec);
      throw OutputError(path + ": write failed: " + (err ? std::strerror(err) : "unknown reason"));
    }
  }
  std::error_code ec;
  fs::rename(tmp, target, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw OutputError(path + ": cannot move the result into place: " + ec.message());
  }
}

}  // namespace vcmm::errormodel
