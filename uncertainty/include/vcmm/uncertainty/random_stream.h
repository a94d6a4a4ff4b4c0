// vcmm/uncertainty/random_stream.h — the counter-based random stream of one Monte Carlo trial.
//
// Definition of the stream (docs/uncertainty.md, "Random numbers"). For a 64-bit seed s and a
// 64-bit stream index k, block b (b = 0, 1, 2, …) is the Philox4x32-10 bijection (Salmon et
// al., "Parallel random numbers: as easy as 1, 2, 3", SC'11; the Random123 reference
// implementation, philox4x32_R<10>) of
//   counter = (lo32(b), hi32(b), lo32(k), hi32(k)),  key = (lo32(s), hi32(s)),
// giving four 32-bit words (x0, x1, x2, x3). The stream is the sequence of 64-bit words
//   w(2b) = x0 | x1 << 32,   w(2b + 1) = x2 | x3 << 32.
// Every draw consumes whole words from the front of this sequence:
//   next_u64()         one word;
//   uniform()          one word: (w >> 11) · 2⁻⁵³, a multiple of 2⁻⁵³ in [0, 1);
//   standard_normal()  one word in 98.5 % of the cases (256-layer ziggurat, below), more on
//                      rejection.
// The fill_* functions give exactly the values of the same number of single calls, so a
// stream may be consumed in any mixture of bulk and single calls. Only integer arithmetic,
// IEEE-754 double +, −, ×, ÷, √ and a portable exp/log written here (no <random>, no libm
// transcendental function) are used, and FMA contraction is off in the implementation: the
// values are bit-identical on every machine, standard library, compiler and thread count.
//
// Normal variates: the ziggurat of Marsaglia & Tsang (J. Stat. Softw. 5(8), 2000) with 256
// layers of equal area, with the layer index, the sign and the abscissa taken from disjoint
// bits of one word (bits 0–7: layer, bit 8: sign, bits 11–63: a 53-bit uniform; this avoids
// the correlation Doornik (2005) found in the original, which reused bits), the wedge test
// against exp(−x²/2) and Marsaglia's exact tail method beyond r ≈ 3.654. The method is
// exact: its output law is N(0, 1) exactly for exact tables and exact uniforms. With the
// double-precision tables (computed once at first use from a bisection for r; docs) the
// layer areas are equal to ~1e-15 relative, and the abscissa is quantised to 2⁻⁵³ of the
// layer width: both far below what any statistical test on < 10²⁰ draws can see.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>

namespace vcmm::uncertainty {

/// Counter-based stream: Philox4x32-10 keyed by the 64-bit seed, counter = (stream index,
/// position). Stream k of seed s is the same numbers on every machine, every thread count,
/// every standard library. One stream per Monte Carlo trial (trial t uses stream t).
///
/// Cost (docs/performance.md; 2.6 GHz Xeon with AVX-512): construction is a few stores (no
/// random numbers are made until the first draw); fill_standard_normal ≈ 2.1 ns a value,
/// fill_uniform ≈ 1.3 ns, single calls ≈ 3–6 ns; the object holds a 4 KiB buffer of
/// generated words. Not thread-safe: one stream per thread (streams are cheap: make one per
/// trial).
class RandomStream {
 public:
  /// The stream `stream` of seed `seed`; any values are valid (all 2⁶⁴ × 2⁶⁴ pairs give
  /// distinct, statistically independent streams of length 2⁶⁵ words).
  RandomStream(std::uint64_t seed, std::uint64_t stream);
  /// Copies continue the same sequence independently (only the unread buffered words are
  /// copied: construction does not initialise the 4 KiB buffer).
  RandomStream(const RandomStream& other);
  RandomStream& operator=(const RandomStream& other);

  /// The next 64-bit word of the stream (file comment). O(1) amortised.
  std::uint64_t next_u64() {
    if (position_ == end_) refill(1);
    return words_[position_++];
  }
  /// Uniform on [0, 1): the top 53 bits of one word times 2⁻⁵³ (every value a multiple of
  /// 2⁻⁵³; 0 has probability 2⁻⁵³, 1 is never returned).
  double uniform() { return static_cast<double>(next_u64() >> 11) * 0x1p-53; }
  /// One N(0, 1) variate by the exact 256-layer ziggurat (file comment).
  double standard_normal();
  /// out[i] = uniform(), i = 0, 1, … (same values as single calls).
  void fill_uniform(std::span<double> out);
  /// out[i] = standard_normal(), i = 0, 1, … (same values as single calls). The bulk hot path:
  /// 1.022 words a value on average, Philox evaluated up to 256 blocks at a time with SIMD,
  /// the ziggurat's core test on 8 words at once where the CPU has AVX-512F/DQ, ~2.1 ns a
  /// value. O(n).
  void fill_standard_normal(std::span<double> out);
  /// out[i] = sigma · standard_normal(), i = 0, 1, … — the values of fill_standard_normal
  /// times sigma (one more rounding, the same bits as scaling them afterwards), without the
  /// second pass over `out` (~2 µs for 14 400 values). O(n).
  void fill_normal(std::span<double> out, double sigma);

  std::uint64_t seed() const { return seed_; }
  std::uint64_t stream() const { return stream_; }
  /// Number of 64-bit words consumed so far.
  std::uint64_t words_consumed() const { return 2 * next_block_ - (end_ - position_); }

  /// Words generated per refill at most (256 Philox blocks; from 128: ~3 % less time a
  /// normal in bulk fills, fewer calls and key set-ups).
  static constexpr std::size_t buffer_words = 512;

 private:
  // Generates the next min(256, max(8, ⌈hint/2⌉)) blocks into the buffer.
  void refill(std::size_t hint_words);
  template <bool kScaled>
  void fill_normal_values(std::span<double> out, double sigma);
  double normal_slow_path(std::uint64_t word);
  std::uint64_t seed_;
  std::uint64_t stream_;
  std::uint64_t next_block_ = 0;  // Philox counter of the next block to generate
  std::size_t position_ = 0;      // next unread word in words_
  std::size_t end_ = 0;           // words_[position_, end_) are generated and unread
  std::array<std::uint64_t, buffer_words> words_;  // filled by refill() before any read
};

/// The seed of a further, statistically independent run derived from a run's seed and a
/// purpose tag (e.g. a pilot run, or a second Monte Carlo run of the same evaluation):
/// splitmix64(splitmix64(seed) ⊕ splitmix64(purpose + 1)), so different tags and different
/// seeds give unrelated Philox keys. O(1).
std::uint64_t derived_seed(std::uint64_t seed, std::uint64_t purpose);

}  // namespace vcmm::uncertainty
