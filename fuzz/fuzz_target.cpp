// fuzz/fuzz_target.cpp — the libFuzzer entry point of every vcmm fuzz target (docs/fuzzing.md).
// CMake compiles it once per target with VCMM_FUZZ_CHECK set to the check of input_checks.h
// (e.g. check_points_csv). The check returns for any input the reader accepts or refuses with
// its documented error; anything else — an unexpected exception (PropertyViolation included),
// a sanitizer report, a timeout — ends the run and libFuzzer saves the input.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "input_checks.h"

#ifndef VCMM_FUZZ_CHECK
#error "VCMM_FUZZ_CHECK must name a check of fuzz/input_checks.h"
#endif

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  (void)vcmm::fuzz::VCMM_FUZZ_CHECK(bytes);
  return 0;
}
