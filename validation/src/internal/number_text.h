// validation/src/internal/number_text.h — shortest round-trip decimal text of a double (the
// files vcmm writes read back to the same doubles).
#pragma once

#include <charconv>
#include <string>

namespace vcmm::validation::internal {

inline std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

}  // namespace vcmm::validation::internal
