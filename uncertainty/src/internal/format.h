// uncertainty/src/internal/format.h — number text for the module's error messages and notes.
#pragma once

#include <sstream>
#include <string>

namespace vcmm::uncertainty::internal {

/// 17 significant digits: the value that broke a rule, exactly.
inline std::string format_double(double x) {
  std::ostringstream s;
  s.precision(17);
  s << x;
  return s.str();
}

/// 4 significant digits: values in human-readable notes.
inline std::string format_short(double x) {
  std::ostringstream s;
  s.precision(4);
  s << x;
  return s.str();
}

}  // namespace vcmm::uncertainty::internal
