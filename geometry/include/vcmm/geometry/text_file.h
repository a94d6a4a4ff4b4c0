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

/// Why `path` cannot be read as a file ("" when it can be opened and is not a directory).
/// For callers that throw their own exception type; read_text_file uses the same wording.
std::string unreadable_file_reason(const std::string& path);

}  // namespace vcmm::geometry
