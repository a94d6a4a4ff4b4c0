// vcmm/validation/provenance.h — what made a result: the library's version and source
// revision, and SHA-256 digests of the input files (the digital model, the points), written
// into every result file (uncertainty JSON, campaign run_info.json) so that a result can be
// traced to the exact code and inputs that produced it.
#pragma once

#include <string>
#include <string_view>

namespace vcmm::validation {

/// The release version, e.g. "0.1.0" (CMake's project version).
std::string_view vcmm_version();

/// The source revision of this build: `git describe --always --dirty` at build time
/// (e.g. "8f2ee13d1a2b-dirty"), or "unknown" when built outside a git checkout.
std::string_view vcmm_revision();

/// SHA-256 (FIPS 180-4) of `bytes`, as 64 lower-case hexadecimal digits.
std::string sha256_hex(std::string_view bytes);

/// SHA-256 of a file's bytes. Throws std::invalid_argument naming the path when it cannot be
/// read.
std::string file_sha256(const std::string& path);

}  // namespace vcmm::validation
