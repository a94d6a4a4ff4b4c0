// vcmm/geometry/text_lines.h — reading the lines of a vcmm text file whatever its line ends:
// "\n" (Unix), "\r\n" (Windows) and a lone "\r" (classic Mac OS, and some instrument exports).
// std::getline alone sees a CR-only file as one long line. Used by every vcmm text reader.
#pragma once

#include <istream>
#include <string>

namespace vcmm::geometry {

/// Reads the next line of `in` into `line` without its end ("\n", "\r\n" or "\r"). Returns
/// false at the end of the input when nothing was read (like std::getline). O(line length).
inline bool read_text_line(std::istream& in, std::string& line) {
  line.clear();
  std::streambuf* buf = in.rdbuf();
  if (buf == nullptr) {
    in.setstate(std::ios::badbit);
    return false;
  }
  using traits = std::istream::traits_type;
  bool any = false;
  for (;;) {
    const traits::int_type c = buf->sbumpc();
    if (traits::eq_int_type(c, traits::eof())) {
      in.setstate(any ? std::ios::eofbit : std::ios::eofbit | std::ios::failbit);
      return any;
    }
    any = true;
    if (c == '\n') return true;
    if (c == '\r') {
      if (traits::eq_int_type(buf->sgetc(), '\n')) buf->sbumpc();
      return true;
    }
    line += traits::to_char_type(c);
  }
}

}  // namespace vcmm::geometry
