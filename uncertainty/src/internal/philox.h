// uncertainty/src/internal/philox.h — Philox4x32-10 evaluated for many consecutive counters at
// once (the word generator behind RandomStream; definition of the stream in
// vcmm/uncertainty/random_stream.h).
//
// Philox4x32-R (Salmon, Moraes, Dror, Shaw, SC'11, section 5.1): R = 10 rounds of
//   (c0, c1, c2, c3) ← (hi(M1·c2) ⊕ c1 ⊕ k0, lo(M1·c2), hi(M0·c0) ⊕ c3 ⊕ k1, lo(M0·c0))
// with M0 = 0xD2511F53, M1 = 0xCD9E8D57 (32×32 → 64-bit products), the key bumped by
// (0x9E3779B9, 0xBB67AE85) between rounds. Bit-identical to Random123's philox4x32_R(10, …)
// (checked in tests/uncertainty/random_test.cpp).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vcmm::uncertainty::internal {

inline constexpr std::uint32_t philox_m0 = 0xD2511F53u;
inline constexpr std::uint32_t philox_m1 = 0xCD9E8D57u;
inline constexpr std::uint32_t philox_w0 = 0x9E3779B9u;
inline constexpr std::uint32_t philox_w1 = 0xBB67AE85u;
inline constexpr int philox_rounds = 10;

/// One Philox4x32-10 block, scalar (the reference the SIMD kernel is tested against).
inline std::array<std::uint32_t, 4> philox4x32_10(std::array<std::uint32_t, 4> c,
                                                   std::array<std::uint32_t, 2> k) {
  for (int round = 0; round < philox_rounds; ++round) {
    if (round > 0) {
      k[0] += philox_w0;
      k[1] += philox_w1;
    }
    const std::uint64_t p0 = static_cast<std::uint64_t>(philox_m0) * c[0];
    const std::uint64_t p1 = static_cast<std::uint64_t>(philox_m1) * c[2];
    c = {static_cast<std::uint32_t>(p1 >> 32) ^ c[1] ^ k[0], static_cast<std::uint32_t>(p1),
         static_cast<std::uint32_t>(p0 >> 32) ^ c[3] ^ k[1], static_cast<std::uint32_t>(p0)};
  }
  return c;
}

/// A kernel computing stream words (signature of philox_stream_words).
using PhiloxKernel = void (*)(std::uint64_t seed, std::uint64_t stream, std::uint64_t first_block,
                              std::size_t blocks, std::uint64_t* words);
struct NamedPhiloxKernel {
  const char* name;
  PhiloxKernel kernel;
};
/// The kernels this CPU can run: "scalar" always, "avx2" and "avx512f" on x86-64 CPUs that
/// have them (for tests and benchmarks).
std::vector<NamedPhiloxKernel> available_philox_kernels();

/// Writes the stream words of blocks first_block … first_block + blocks − 1 of stream
/// (seed, stream) to words[0 … 2·blocks): words[2j] = x0 | x1 << 32, words[2j+1] = x2 | x3 << 32
/// of block first_block + j. The block counter wraps modulo 2⁶⁴. Runs the fastest kernel the
/// CPU has (AVX-512F, AVX2, else scalar; chosen once at first call); integer arithmetic, so
/// all kernels agree bit for bit. AVX-512: ~0.8 ns a word on the 2.6 GHz Xeon here.
void philox_stream_words(std::uint64_t seed, std::uint64_t stream, std::uint64_t first_block,
                         std::size_t blocks, std::uint64_t* words);

}  // namespace vcmm::uncertainty::internal
