// RandomStream: Philox4x32-10 words (internal/philox.h), 53-bit uniforms and the exact
// 256-layer ziggurat for N(0, 1) (internal/ziggurat.h). Definition of the stream and of every
// draw: vcmm/uncertainty/random_stream.h; derivation of the tables: docs/uncertainty.md.
//
// The bulk normal loop. Each word w gives layer i = w & 255, sign bit 8, and the candidate
//   x = (w >> 11) · 2⁻⁵³ · x[i]  =  (w >> 11) · (x[i] · 2⁻⁵³)
// (scaling by a power of two is exact, so the pre-scaled table gives the same bits); x is
// accepted at once when x < x[i+1] (inside the layer's core box: 98.5 % of words). Otherwise
// normal_slow_path() runs the wedge test y < exp(−x²/2), y uniform on [f(x[i]), f(x[i+1]))
// (decided by linear squeezes where they can, the exponential otherwise: same answer, see
// internal::wedge_accepts),
// or for i = 0 and x ≥ r Marsaglia's tail method: a = −ln U₁ / r, b = −ln U₂ with U on
// (0, 1], repeated until 2b ≥ a², giving r + a. A rejected candidate restarts from a fresh
// word (layer and all), which keeps the method exact. Uniforms for the slow paths are fresh
// whole words taken in stream order, so fill_standard_normal and standard_normal agree.
#include "vcmm/uncertainty/random_stream.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>

#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
#define VCMM_PHILOX_X86 1
#include <immintrin.h>
#else
#define VCMM_PHILOX_X86 0
#endif

#include "internal/philox.h"
#include "internal/portable_math.h"
#include "internal/ziggurat.h"

namespace vcmm::uncertainty {
namespace internal {

namespace {

// ---- Philox kernels ------------------------------------------------------------------------
//
// Each writes the words of `blocks` consecutive counters (philox.h). The SIMD kernels keep
// one block per 64-bit lane with the 32-bit state word in the low half: (v)pmuludq multiplies
// the low halves only, so the high halves may hold garbage (the previous product's high
// part, XORs of it) until the final masking. A round per vector is then 2 multiplies, 2
// shifts and 2 three-way XORs (vpternlogq on AVX-512). Four vectors are in flight to cover the
// multiply latency. The masked-zero intrinsics (_mm512_maskz_*, all lanes selected) compile
// to the plain instructions and avoid GCC 12's false -Wmaybe-uninitialized on the unmasked
// ones. Full passes of 4 vectors serve bulk requests; the rest goes one vector at a time, so a
// short refill (8 blocks) costs one vector pass. Integer arithmetic: every kernel gives the
// same bits (tested against Random123).

void philox_scalar(std::uint64_t seed, std::uint64_t stream, std::uint64_t first_block,
                   std::size_t blocks, std::uint64_t* words) {
  const std::array<std::uint32_t, 2> key = {static_cast<std::uint32_t>(seed),
                                            static_cast<std::uint32_t>(seed >> 32)};
  for (std::size_t j = 0; j < blocks; ++j) {
    const std::uint64_t b = first_block + j;
    const auto x = philox4x32_10({static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(b >> 32),
                                  static_cast<std::uint32_t>(stream),
                                  static_cast<std::uint32_t>(stream >> 32)},
                                 key);
    words[2 * j] = x[0] | (static_cast<std::uint64_t>(x[1]) << 32);
    words[2 * j + 1] = x[2] | (static_cast<std::uint64_t>(x[3]) << 32);
  }
}

#if VCMM_PHILOX_X86
// AVX-512F: 8 blocks a vector. A pass computes V vectors (8V blocks) and stores the first n.
struct Avx512Keys {
  __m512i key0[philox_rounds], key1[philox_rounds], s0, s1;
};

// The high 32 bits of each 64-bit product moved to the low half by swapping the halves
// (vpshufd, the shuffle port) rather than shifted (vpsrlq, which shares the multiplier's port
// at 512 bits): the high half then holds the product's low part, garbage the next round
// ignores as above.
__attribute__((target("avx512f"), always_inline)) inline __m512i high_to_low(__m512i p) {
  return _mm512_maskz_shuffle_epi32(0xffff, p, _MM_PERM_CDAB);
}

template <int V>
__attribute__((target("avx512f"), always_inline)) inline void philox_avx512_pass(
    const Avx512Keys& k, std::uint64_t first_block, std::size_t n, std::uint64_t* words) {
  constexpr __mmask8 all = 0xff;
  const __m512i m0 = _mm512_set1_epi64(philox_m0);
  const __m512i m1 = _mm512_set1_epi64(philox_m1);
  const __m512i iota = _mm512_set_epi64(7, 6, 5, 4, 3, 2, 1, 0);
  __m512i c0[V], c1[V], c2[V], c3[V];
  for (int v = 0; v < V; ++v) {
    const __m512i b = _mm512_add_epi64(
        _mm512_set1_epi64(static_cast<long long>(first_block + 8 * static_cast<unsigned>(v))), iota);
    c0[v] = b;
    c1[v] = _mm512_maskz_srli_epi64(all, b, 32);
    c2[v] = k.s0;
    c3[v] = k.s1;
  }
  for (int r = 0; r < philox_rounds; ++r) {
    for (int v = 0; v < V; ++v) {
      const __m512i p0 = _mm512_maskz_mul_epu32(all, c0[v], m0);
      const __m512i p1 = _mm512_maskz_mul_epu32(all, c2[v], m1);
      c0[v] = _mm512_ternarylogic_epi64(high_to_low(p1), c1[v], k.key0[r], 0x96);
      c1[v] = p1;
      c2[v] = _mm512_ternarylogic_epi64(high_to_low(p0), c3[v], k.key1[r], 0x96);
      c3[v] = p0;
    }
  }
  const __m512i low_mask = _mm512_set1_epi64(0xffffffffu);
  const __m512i first_half = _mm512_set_epi64(11, 3, 10, 2, 9, 1, 8, 0);  // interleave w0, w1
  const __m512i second_half = _mm512_set_epi64(15, 7, 14, 6, 13, 5, 12, 4);
  alignas(64) std::uint64_t partial[16 * V];
  std::uint64_t* out = n == 8 * static_cast<std::size_t>(V) ? words : partial;
  for (int v = 0; v < V; ++v) {
    const __m512i w0 = _mm512_or_si512(_mm512_and_si512(c0[v], low_mask),
                                       _mm512_maskz_slli_epi64(all, c1[v], 32));
    const __m512i w1 = _mm512_or_si512(_mm512_and_si512(c2[v], low_mask),
                                       _mm512_maskz_slli_epi64(all, c3[v], 32));
    _mm512_storeu_si512(out + 16 * v, _mm512_permutex2var_epi64(w0, first_half, w1));
    _mm512_storeu_si512(out + 16 * v + 8, _mm512_permutex2var_epi64(w0, second_half, w1));
  }
  if (out == partial) std::copy(partial, partial + 2 * n, words);
}

__attribute__((target("avx512f"))) void philox_avx512(std::uint64_t seed, std::uint64_t stream,
                                                       std::uint64_t first_block,
                                                       std::size_t blocks, std::uint64_t* words) {
  Avx512Keys k;
  auto k0 = static_cast<std::uint32_t>(seed);
  auto k1 = static_cast<std::uint32_t>(seed >> 32);
  for (int r = 0; r < philox_rounds; ++r) {
    k.key0[r] = _mm512_set1_epi64(k0);
    k.key1[r] = _mm512_set1_epi64(k1);
    k0 += philox_w0;
    k1 += philox_w1;
  }
  k.s0 = _mm512_set1_epi64(static_cast<std::uint32_t>(stream));
  k.s1 = _mm512_set1_epi64(static_cast<std::uint32_t>(stream >> 32));
  std::size_t done = 0;
  for (; blocks - done >= 32; done += 32) {  // 4 vectors in flight hide the multiply latency
    philox_avx512_pass<4>(k, first_block + done, 32, words + 2 * done);
  }
  for (; done < blocks; done += 8) {  // short requests: one vector at a time
    philox_avx512_pass<1>(k, first_block + done, std::min<std::size_t>(8, blocks - done),
                          words + 2 * done);
  }
}

// AVX2: 4 blocks a vector, same scheme (two XORs instead of vpternlogq).
struct Avx2Keys {
  __m256i key0[philox_rounds], key1[philox_rounds], s0, s1;
};

template <int V>
__attribute__((target("avx2"), always_inline)) inline void philox_avx2_pass(
    const Avx2Keys& k, std::uint64_t first_block, std::size_t n, std::uint64_t* words) {
  const __m256i m0 = _mm256_set1_epi64x(philox_m0);
  const __m256i m1 = _mm256_set1_epi64x(philox_m1);
  const __m256i iota = _mm256_set_epi64x(3, 2, 1, 0);
  __m256i c0[V], c1[V], c2[V], c3[V];
  for (int v = 0; v < V; ++v) {
    const __m256i b = _mm256_add_epi64(
        _mm256_set1_epi64x(static_cast<long long>(first_block + 4 * static_cast<unsigned>(v))), iota);
    c0[v] = b;
    c1[v] = _mm256_srli_epi64(b, 32);
    c2[v] = k.s0;
    c3[v] = k.s1;
  }
  for (int r = 0; r < philox_rounds; ++r) {
    for (int v = 0; v < V; ++v) {
      const __m256i p0 = _mm256_mul_epu32(c0[v], m0);
      const __m256i p1 = _mm256_mul_epu32(c2[v], m1);
      c0[v] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p1, 32), c1[v]), k.key0[r]);
      c1[v] = p1;
      c2[v] = _mm256_xor_si256(_mm256_xor_si256(_mm256_srli_epi64(p0, 32), c3[v]), k.key1[r]);
      c3[v] = p0;
    }
  }
  const __m256i low_mask = _mm256_set1_epi64x(0xffffffffu);
  alignas(32) std::uint64_t partial[8 * V];
  std::uint64_t* out = n == 4 * static_cast<std::size_t>(V) ? words : partial;
  for (int v = 0; v < V; ++v) {
    const __m256i w0 = _mm256_or_si256(_mm256_and_si256(c0[v], low_mask), _mm256_slli_epi64(c1[v], 32));
    const __m256i w1 = _mm256_or_si256(_mm256_and_si256(c2[v], low_mask), _mm256_slli_epi64(c3[v], 32));
    const __m256i lo = _mm256_unpacklo_epi64(w0, w1);  // w0[0] w1[0] w0[2] w1[2]
    const __m256i hi = _mm256_unpackhi_epi64(w0, w1);  // w0[1] w1[1] w0[3] w1[3]
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 8 * v), _mm256_permute2x128_si256(lo, hi, 0x20));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out + 8 * v + 4), _mm256_permute2x128_si256(lo, hi, 0x31));
  }
  if (out == partial) std::copy(partial, partial + 2 * n, words);
}

__attribute__((target("avx2"))) void philox_avx2(std::uint64_t seed, std::uint64_t stream,
                                                 std::uint64_t first_block, std::size_t blocks,
                                                 std::uint64_t* words) {
  Avx2Keys k;
  auto k0 = static_cast<std::uint32_t>(seed);
  auto k1 = static_cast<std::uint32_t>(seed >> 32);
  for (int r = 0; r < philox_rounds; ++r) {
    k.key0[r] = _mm256_set1_epi64x(k0);
    k.key1[r] = _mm256_set1_epi64x(k1);
    k0 += philox_w0;
    k1 += philox_w1;
  }
  k.s0 = _mm256_set1_epi64x(static_cast<std::uint32_t>(stream));
  k.s1 = _mm256_set1_epi64x(static_cast<std::uint32_t>(stream >> 32));
  std::size_t done = 0;
  for (; blocks - done >= 16; done += 16) {
    philox_avx2_pass<4>(k, first_block + done, 16, words + 2 * done);
  }
  for (; done < blocks; done += 4) {
    philox_avx2_pass<1>(k, first_block + done, std::min<std::size_t>(4, blocks - done),
                        words + 2 * done);
  }
}
#endif  // VCMM_PHILOX_X86

PhiloxKernel select_philox_kernel() {
#if VCMM_PHILOX_X86
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f")) return philox_avx512;
  if (__builtin_cpu_supports("avx2")) return philox_avx2;
#endif
  return philox_scalar;
}

}  // namespace

std::vector<NamedPhiloxKernel> available_philox_kernels() {
  std::vector<NamedPhiloxKernel> out = {{"scalar", philox_scalar}};
#if VCMM_PHILOX_X86
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx2")) out.push_back({"avx2", philox_avx2});
  if (__builtin_cpu_supports("avx512f")) out.push_back({"avx512f", philox_avx512});
#endif
  return out;
}

void philox_stream_words(std::uint64_t seed, std::uint64_t stream, std::uint64_t first_block,
                         std::size_t blocks, std::uint64_t* words) {
  static const PhiloxKernel kernel = select_philox_kernel();
  kernel(seed, stream, first_block, blocks, words);
}

double gaussian_tail_area(double r) {
  // Laplace's continued fraction, bottom-up: t_K = r, t_k = r + k / t_{k+1}; T = f(r) / t_1.
  // The convergents alternate about the limit and the tail of the fraction beyond term K
  // changes t_1 by O(∏ k/t_k²) — negligible for K = 2000 and r ≥ 1 at double precision.
  double t = r;
  for (int k = 2000; k >= 1; --k) t = r + k / t;
  return portable_exp(-0.5 * r * r) / t;
}

namespace {

constexpr int kLayers = ZigguratTables::layers;

struct Recursion {
  bool overshoot = false;  // the layers reached the top before layer N − 1
  double residual = 0.0;   // c(r) (ziggurat.h)
};

// Fills x[1 … N−1] and f[1 … N−1] for tail start r and layer area v; returns c(r).
Recursion layer_recursion(double r, double v, ZigguratTables& z) {
  z.x[1] = r;
  z.f[1] = portable_exp(-0.5 * r * r);
  for (int i = 1; i < kLayers - 1; ++i) {
    const double level = v / z.x[static_cast<std::size_t>(i)] + z.f[static_cast<std::size_t>(i)];
    if (!(level < 1.0)) return {true, 0.0};
    z.x[static_cast<std::size_t>(i + 1)] = std::sqrt(-2.0 * portable_log(level));
    z.f[static_cast<std::size_t>(i + 1)] = level;
  }
  const std::size_t top = kLayers - 1;
  return {false, v / z.x[top] + z.f[top] - 1.0};
}

double layer_area(double r) { return r * portable_exp(-0.5 * r * r) + gaussian_tail_area(r); }

}  // namespace

ZigguratTables compute_ziggurat_tables() {
  // c(r) > 0 (or overshoot) when r is too small (layers too thick), < 0 when too large.
  // The bracket [3, 4.5] holds the root for N = 256 (r ≈ 3.654); bisection on doubles runs
  // until the midpoint equals an end (≤ 53 halvings), then the end with smaller |c| is kept.
  ZigguratTables z;
  double lo = 3.0, hi = 4.5;
  for (;;) {
    const double mid = 0.5 * (lo + hi);
    if (!(lo < mid && mid < hi)) break;
    const Recursion rec = layer_recursion(mid, layer_area(mid), z);
    if (rec.overshoot || rec.residual > 0.0) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  const Recursion rec_lo = layer_recursion(lo, layer_area(lo), z);
  const Recursion rec_hi = layer_recursion(hi, layer_area(hi), z);
  const bool use_lo =
      !rec_lo.overshoot && (rec_hi.overshoot || std::abs(rec_lo.residual) <= std::abs(rec_hi.residual));
  z.r = use_lo ? lo : hi;
  z.v = layer_area(z.r);
  z.closure_residual = layer_recursion(z.r, z.v, z).residual;
  z.x[0] = z.v / z.f[1];
  z.f[0] = portable_exp(-0.5 * z.x[0] * z.x[0]);
  z.x[kLayers] = 0.0;
  z.f[kLayers] = 1.0;
  return z;
}

const ZigguratTables& ziggurat_tables() {
  static const ZigguratTables tables = compute_ziggurat_tables();
  return tables;
}

namespace {

// The tables in the form the hot loop uses, one 16-byte entry per (sign, layer) = the low 9
// bits of the word: the signed scaled abscissa ±x[i]·2⁻⁵³ and the integer threshold A_i of the
// core test. For a = w >> 11 the candidate is fl(a·x[i]·2⁻⁵³) (the same bits as
// fl(a·2⁻⁵³)·x[i]: power-of-two scaling is exact), and it is accepted when it is < x[i+1].
// Rounding is monotone, so fl(a·c) < x[i+1] holds exactly for the integers a < A_i, with A_i
// the least a for which it fails (found by bisection below): the integer test a < A_i is the
// floating-point test itself, bit for bit. Rounding to nearest is symmetric, so
// fl(a·(−c)) = −fl(a·c): the signed entry gives the sign for free (a = 0 gives −0.0 either
// way).
struct FastEntry {
  double x_scaled = 0.0;
  std::uint64_t accept_below = 0;
};
struct ScaledTables {
  std::array<FastEntry, 2 * kLayers> entry{};
  ScaledTables() {
    const ZigguratTables& z = ziggurat_tables();
    for (std::size_t i = 0; i < kLayers; ++i) {
      const double c = z.x[i] * 0x1p-53;
      const double bound = z.x[i + 1];
      // Least a in [0, 2⁵³] with fl(a·c) ≥ bound (2⁵³ if none: then every a is accepted).
      std::uint64_t lo = 0, hi = std::uint64_t{1} << 53;
      while (lo < hi) {
        const std::uint64_t mid = lo + (hi - lo) / 2;
        if (static_cast<double>(mid) * c < bound) {
          lo = mid + 1;
        } else {
          hi = mid;
        }
      }
      entry[i] = {c, lo};
      entry[i + kLayers] = {-c, lo};
    }
  }
};

const ScaledTables& scaled_tables() {
  static const ScaledTables tables;
  return tables;
}

// What the slow path reads for a layer i, in one 64-byte entry (one cache line): the
// abscissae x[i], x[i+1], the wedge's f[i] and f[i+1] − f[i] (the same value the subtraction
// gives in place), and the squeeze lines (ziggurat.h, wedge_accepts): y accepted below
// lower_a + lower_b·x − margin, rejected above upper_a + upper_b·x + margin. Layers 0 (the
// base: no wedge test) and the one containing x = 1 get lines that never decide (±inf).
// About 1.5 % of the words take the slow path, each in a random layer, between bulk passes
// that evict these tables: four scattered tables cost a cache miss each, this one costs one.
constexpr double kSqueezeMargin = 1e-14;
struct alignas(64) SlowLayer {
  double x = 0.0, x_next = 0.0, f = 0.0, f_step = 0.0;
  double lower_a = 0.0, lower_b = 0.0, upper_a = 0.0, upper_b = 0.0;
};
static_assert(sizeof(SlowLayer) == 64, "SlowLayer: one cache line");
struct SlowTables {
  std::array<SlowLayer, kLayers> layer{};
  double r = 0.0;  // start of the tail
  SlowTables() {
    const ZigguratTables& z = ziggurat_tables();
    r = z.r;
    constexpr double inf = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < static_cast<std::size_t>(kLayers); ++i) {
      SlowLayer& e = layer[i];
      e.x = z.x[i];
      e.x_next = z.x[i + 1];
      e.f = z.f[i];
      e.f_step = z.f[i + 1] - z.f[i];
      e.lower_a = -inf;
      e.upper_a = inf;
      if (i == 0) continue;
      const double x0 = z.x[i + 1], x1 = z.x[i];  // the wedge is [x0, x1)
      const bool concave = x1 <= 1.0, convex = x0 >= 1.0;
      if (!concave && !convex) continue;
      const double chord_b = (z.f[i] - z.f[i + 1]) / (x1 - x0);
      const double chord_a = z.f[i + 1] - chord_b * x0;
      const double m = 0.5 * (x0 + x1), fm = portable_exp(-0.5 * m * m);
      const double tangent_b = -m * fm, tangent_a = fm - tangent_b * m;
      e.lower_a = concave ? chord_a : tangent_a;
      e.lower_b = concave ? chord_b : tangent_b;
      e.upper_a = concave ? tangent_a : chord_a;
      e.upper_b = concave ? tangent_b : chord_b;
    }
  }
};

inline const SlowTables& slow_tables() {
  static const SlowTables tables;
  return tables;
}

// y < exp(−x²/2) for a point of layer e's wedge, the squeezes first.
inline bool layer_wedge_accepts(const SlowLayer& e, double x, double y) {
  if (y < e.lower_a + e.lower_b * x - kSqueezeMargin) return true;
  if (y > e.upper_a + e.upper_b * x + kSqueezeMargin) return false;
  return y < portable_exp(-0.5 * x * x);
}

}  // namespace

bool wedge_accepts(std::size_t layer, double x, double y) {
  return layer_wedge_accepts(slow_tables().layer[layer], x, y);
}

}  // namespace internal

namespace {

inline double with_sign_bit(double magnitude, std::uint64_t word) {
  // Bit 8 of the word → bit 63 of the result (magnitude ≥ 0).
  return std::bit_cast<double>(std::bit_cast<std::uint64_t>(magnitude) | ((word & 0x100u) << 55));
}

inline double uniform53(std::uint64_t word) {  // [0, 1)
  return static_cast<double>(static_cast<std::int64_t>(word >> 11)) * 0x1p-53;
}

inline double uniform53_open_at_zero(std::uint64_t word) {  // (0, 1]
  return static_cast<double>(static_cast<std::int64_t>(word >> 11) + 1) * 0x1p-53;
}

// Minimum number of blocks a refill makes: single draws then cost one SIMD pass per 16
// words instead of one per 2.
constexpr std::size_t kMinRefillBlocks = 8;

}  // namespace

RandomStream::RandomStream(std::uint64_t seed, std::uint64_t stream)
    : seed_(seed), stream_(stream) {}  // words_ stays uninitialised until refill() (cheap per trial)

RandomStream::RandomStream(const RandomStream& other)
    : seed_(other.seed_),
      stream_(other.stream_),
      next_block_(other.next_block_),
      position_(other.position_),
      end_(other.end_) {
  std::copy(other.words_.begin() + static_cast<std::ptrdiff_t>(position_),
            other.words_.begin() + static_cast<std::ptrdiff_t>(end_),
            words_.begin() + static_cast<std::ptrdiff_t>(position_));
}

RandomStream& RandomStream::operator=(const RandomStream& other) {
  if (this != &other) {
    seed_ = other.seed_;
    stream_ = other.stream_;
    next_block_ = other.next_block_;
    position_ = other.position_;
    end_ = other.end_;
    std::copy(other.words_.begin() + static_cast<std::ptrdiff_t>(position_),
              other.words_.begin() + static_cast<std::ptrdiff_t>(end_),
              words_.begin() + static_cast<std::ptrdiff_t>(position_));
  }
  return *this;
}

void RandomStream::refill(std::size_t hint_words) {
  const std::size_t blocks =
      std::clamp<std::size_t>((hint_words + 1) / 2, kMinRefillBlocks, buffer_words / 2);
  internal::philox_stream_words(seed_, stream_, next_block_, blocks, words_.data());
  next_block_ += blocks;
  position_ = 0;
  end_ = 2 * blocks;
}

double RandomStream::normal_slow_path(std::uint64_t word) {
  const internal::SlowTables& z = internal::slow_tables();
  for (;;) {
    const std::size_t layer = word & 0xffu;
    const internal::SlowLayer& e = z.layer[layer];
    const double x = uniform53(word) * e.x;
    if (x < e.x_next) return with_sign_bit(x, word);
    if (layer == 0) {  // x ≥ r in the base layer: a draw from the tail beyond r
      double a = 0.0, b = 0.0;
      do {
        a = -internal::portable_log(uniform53_open_at_zero(next_u64())) / z.r;
        b = -internal::portable_log(uniform53_open_at_zero(next_u64()));
      } while (b + b < a * a);
      return with_sign_bit(z.r + a, word);
    }
    const double y = e.f + uniform53(next_u64()) * e.f_step;
    if (internal::layer_wedge_accepts(e, x, y)) return with_sign_bit(x, word);
    word = next_u64();  // rejected: start again with a fresh word
  }
}

double RandomStream::standard_normal() {
  const internal::FastEntry* table = internal::scaled_tables().entry.data();
  const std::uint64_t word = next_u64();
  const internal::FastEntry& e = table[word & 0x1ffu];
  const std::uint64_t a = word >> 11;
  if (a < e.accept_below) return static_cast<double>(static_cast<std::int64_t>(a)) * e.x_scaled;
  return normal_slow_path(word);
}

namespace {

#if VCMM_PHILOX_X86
// The core test of 8 words at once (AVX-512F + DQ): the table entries of the 8 words by two
// gathers, a = w >> 11, accepted when a < A_i; the candidates fl(a·x_i·2⁻⁵³) (times sigma:
// kScaled) — the same operations as the scalar loop (a < 2⁵³ converts exactly), so the same
// bits. Stores and consumes 8 values at a time while all 8 are accepted (≈ 88 % of groups); at
// a group with a rejection it stores the accepted words before it and stops there, for the
// scalar loop and the slow path to take over. Returns the number of words consumed.
template <bool kScaled>
__attribute__((target("avx512f,avx512dq"))) std::size_t accepted_prefix_avx512(
    const std::uint64_t* w, std::size_t m, const internal::FastEntry* table, double sigma,
    double* out) {
  static_assert(sizeof(internal::FastEntry) == 2 * sizeof(double), "FastEntry: 16 bytes");
  const auto* x_base = reinterpret_cast<const double*>(table);
  const auto* a_base = reinterpret_cast<const long long*>(table) + 1;
  constexpr __mmask8 all = 0xff;  // maskz forms: see the Philox kernels
  const __m512i low9 = _mm512_set1_epi64(0x1ff);  // index in doubles: 2 (sign, layer)
  const __m512d s = _mm512_set1_pd(sigma);
  std::size_t k = 0;
  for (; k + 8 <= m; k += 8) {
    const __m512i word = _mm512_loadu_si512(w + k);
    const __m512i index = _mm512_maskz_slli_epi64(all, _mm512_and_si512(word, low9), 1);
    const __m512d x = _mm512_mask_i64gather_pd(_mm512_setzero_pd(), all, index, x_base, 8);
    const __m512i accept =
        _mm512_mask_i64gather_epi64(_mm512_setzero_si512(), all, index, a_base, 8);
    const __m512i a = _mm512_maskz_srli_epi64(all, word, 11);
    const __mmask8 ok = _mm512_cmplt_epu64_mask(a, accept);
    __m512d z = _mm512_mul_pd(_mm512_cvtepu64_pd(a), x);
    if constexpr (kScaled) z = _mm512_mul_pd(z, s);
    if (ok == 0xff) {
      _mm512_storeu_pd(out + k, z);
      continue;
    }
    const auto head = static_cast<unsigned>(std::countr_one(static_cast<unsigned>(ok)));
    _mm512_mask_storeu_pd(out + k, static_cast<__mmask8>((1u << head) - 1u), z);
    return k + head;
  }
  return k;
}

template <bool kScaled>
using AcceptedPrefix = std::size_t (*)(const std::uint64_t*, std::size_t,
                                       const internal::FastEntry*, double, double*);

template <bool kScaled>
AcceptedPrefix<kScaled> select_accepted_prefix() {
  __builtin_cpu_init();
  if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq"))
    return accepted_prefix_avx512<kScaled>;
  return nullptr;
}
#endif

}  // namespace

// The loop below ran at ~2.1 ns a value on the 2.6 GHz AVX-512 Xeon of docs/performance.md, of
// which ~0.75 ns is Philox; there the 8-word AVX-512 test above (two gathers) was slower (2.75
// ns: gathers were slow on that CPU). On the Sapphire Rapids of issue 14's measurements it is
// faster (docs/performance.md, "Issue 14 item 1"), so it runs first where the CPU has it.
// kScaled: each value times sigma as a separate rounding (the bits of scaling afterwards).
template <bool kScaled>
void RandomStream::fill_normal_values(std::span<double> out, double sigma) {
  const internal::FastEntry* table = internal::scaled_tables().entry.data();
#if VCMM_PHILOX_X86
  static const AcceptedPrefix<kScaled> vector_prefix = select_accepted_prefix<kScaled>();
#endif
  double* o = out.data();
  const std::size_t n = out.size();
  std::size_t i = 0;
  while (i < n) {
    if (position_ == end_) refill(n - i + (n - i) / 32 + 2);  // ~1.022 words a value
    const std::size_t m = std::min(end_ - position_, n - i);
    const std::uint64_t* w = words_.data() + position_;
    std::size_t k = 0;
#if VCMM_PHILOX_X86
    if (vector_prefix) k = vector_prefix(w, m, table, sigma, o + i);
#endif
    for (; k < m; ++k) {
      const internal::FastEntry& e = table[w[k] & 0x1ffu];
      const std::uint64_t a = w[k] >> 11;
      if (a >= e.accept_below) break;  // the slow path takes this word
      const double z = static_cast<double>(static_cast<std::int64_t>(a)) * e.x_scaled;
      o[i + k] = kScaled ? z * sigma : z;
    }
    position_ += k;
    i += k;
    if (k < m) {
      const std::uint64_t word = words_[position_++];
      const double z = normal_slow_path(word);
      o[i++] = kScaled ? z * sigma : z;
    }
  }
}

void RandomStream::fill_standard_normal(std::span<double> out) {
  fill_normal_values<false>(out, 1.0);
}

void RandomStream::fill_normal(std::span<double> out, double sigma) {
  fill_normal_values<true>(out, sigma);
}

void RandomStream::fill_uniform(std::span<double> out) {
  double* o = out.data();
  const std::size_t n = out.size();
  std::size_t i = 0;
  while (i < n) {
    if (position_ == end_) refill(n - i);
    const std::size_t m = std::min(end_ - position_, n - i);
    const std::uint64_t* w = words_.data() + position_;
    for (std::size_t k = 0; k < m; ++k) o[i + k] = uniform53(w[k]);
    position_ += m;
    i += m;
  }
}

std::uint64_t derived_seed(std::uint64_t seed, std::uint64_t purpose) {
  const auto mix = [](std::uint64_t z) {
    z += 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31);
  };
  return mix(mix(seed) ^ mix(purpose + 1));
}

}  // namespace vcmm::uncertainty
