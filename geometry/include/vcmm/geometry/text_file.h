// vcmm/geometry/text_file.h — the one way every vcmm reader opens a file: the whole file read
// at once (C stdio, binary), and when it cannot be read, a message that names the path, what
// the file was meant to be and why: "no such file", "a directory, not a file", or the OS reason.
// (A std::ifstream opens a directory without complaint on Linux; its first read then throws
// "basic_filebuf::underflow" or reads nothing, and the file looked empty or not JSON.)
#pragma once

#include <string>
#include <string_view>

namespace vcmm::geometry {

/// The content of the file at `path`. Throws InvalidInput
/// "<path>: cannot read the <what>: <reason>" (e.g. what = "measurement file").
std::string read_text_file(const std::string& path, std::string_view what);

/// The same without throwing, for callers that throw their own exception type: true and the
/// content in `text`, or false and why in `reason` (read_text_file's wording). One open.
bool try_read_text_file(const std::string& path, std::string& text, std::string& reason);

}  // namespace vcmm::geometry
