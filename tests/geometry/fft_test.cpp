// Tests of the geometry module's complex FFT (geometry/src/internal/fft.h): against a direct
// DFT in long double for many sizes (smooth, radix 7/11/13, prime and other Bluestein sizes,
// a seeded sample of 1 … 5000), the inverse, and bit-identity of the instruction-set variants
// (internal/isa.h) — of the FFT itself and, end to end, of the filter and the synthesis.
#include "../../geometry/src/internal/fft.h"
#include "../../geometry/src/internal/isa.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <iostream>
#include <numbers>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/equiangular_transform.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"

namespace vcmm::geometry::internal {
namespace {

struct Signal {
  std::vector<double> re, im;
};

Signal random_signal(std::size_t n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Signal s{std::vector<double>(n), std::vector<double>(n)};
  for (std::size_t j = 0; j < n; ++j) {
    s.re[j] = u(rng);
    s.im[j] = u(rng);
  }
  return s;
}

/// X_k = Σ_j x_j e^{−2πi jk/n} in long double (roots from a table of n angles: jk mod n).
std::vector<std::pair<long double, long double>> direct_dft(const Signal& x) {
  const std::size_t n = x.re.size();
  std::vector<long double> c(n), s(n);
  for (std::size_t j = 0; j < n; ++j) {
    const long double a = -2.0L * std::numbers::pi_v<long double> * static_cast<long double>(j) /
                          static_cast<long double>(n);
    c[j] = std::cos(a);
    s[j] = std::sin(a);
  }
  std::vector<std::pair<long double, long double>> out(n);
  for (std::size_t k = 0; k < n; ++k) {
    long double re = 0.0L, im = 0.0L;
    std::size_t jk = 0;  // j·k mod n
    for (std::size_t j = 0; j < n; ++j) {
      re += x.re[j] * c[jk] - x.im[j] * s[jk];
      im += x.re[j] * s[jk] + x.im[j] * c[jk];
      jk += k;
      if (jk >= n) jk -= n;
    }
    out[k] = {re, im};
  }
  return out;
}

/// ‖X − ref‖₂ / ‖ref‖₂.
double relative_error(const Signal& X, const std::vector<std::pair<long double, long double>>& ref) {
  long double err = 0.0L, norm = 0.0L;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const long double dr = X.re[k] - ref[k].first, di = X.im[k] - ref[k].second;
    err += dr * dr + di * di;
    norm += ref[k].first * ref[k].first + ref[k].second * ref[k].second;
  }
  return static_cast<double>(std::sqrt(err / norm));
}

std::vector<std::size_t> test_sizes() {
  std::set<std::size_t> sizes;
  for (std::size_t n = 1; n <= 72; ++n) sizes.insert(n);
  // smooth (radix 8, 4, 2, 3, 5), radix 7/11/13, primes and large prime factors (Bluestein)
  for (std::size_t n : {90u, 96u, 100u, 128u, 180u, 243u, 250u, 256u, 360u, 375u, 450u, 512u,
                        625u, 720u, 900u, 1000u, 1024u, 1125u, 1800u, 2048u, 2187u, 3125u,
                        3600u, 4096u, 4500u, 77u, 91u, 143u, 1001u, 2002u, 97u, 101u, 1009u,
                        2026u, 3607u, 4999u})
    sizes.insert(n);
  std::mt19937_64 rng(20261127);
  std::uniform_int_distribution<std::size_t> pick(73, 5000);
  for (int i = 0; i < 24; ++i) sizes.insert(pick(rng));
  return {sizes.begin(), sizes.end()};
}

// Accuracy: the relative 2-norm error of a floating FFT grows like ε·log n (Stockham passes:
// one rounding per butterfly level; Bluestein: three FFTs of size ≥ 2n and three pointwise
// products). Observed here: ≤ 3.3e-17·(8 + log₂ n) over all these sizes (4.4e-16 at most);
// bound: 6e-17·(8 + log₂ n), 1.2e-15 at n = 5000.
TEST(ComplexFft, MatchesTheDirectDftInLongDoubleForManySizes) {
  for (const std::size_t n : test_sizes()) {
    const Signal x = random_signal(n, static_cast<unsigned>(n));
    Signal X = x;
    ComplexFft fft(n);
    fft.forward(X.re.data(), X.im.data());
    const double err = relative_error(X, direct_dft(x));
    const double bound = 6e-17 * (8.0 + std::log2(static_cast<double>(n)));
    EXPECT_LE(err, bound) << "n = " << n;
  }
}

TEST(ComplexFft, InverseUndoesForwardUpToTheFactorN) {
  for (const std::size_t n : {1u, 2u, 7u, 360u, 1800u, 3607u}) {
    const Signal x = random_signal(n, 7);
    Signal y = x;
    ComplexFft fft(n);
    fft.forward(y.re.data(), y.im.data());
    fft.inverse(y.re.data(), y.im.data());
    for (std::size_t j = 0; j < n; ++j) {
      EXPECT_NEAR(y.re[j] / static_cast<double>(n), x.re[j], 2e-15) << "n " << n << " j " << j;
      EXPECT_NEAR(y.im[j] / static_cast<double>(n), x.im[j], 2e-15) << "n " << n << " j " << j;
    }
  }
}

// The interleaved output of the inverse is the inverse's values, bit for bit, whatever the last
// pass (fused radix 2/3/4/5/8/9 with even or odd pass counts, generic radix 7/11/13, Bluestein,
// n = 1).
TEST(ComplexFft, InterleavedInverseEqualsTheInverseBitForBit) {
  for (const std::size_t n : {1u, 2u, 3u, 4u, 5u, 7u, 8u, 9u, 11u, 13u, 14u, 40u, 72u, 90u, 360u,
                              1001u, 1800u, 3600u, 3607u}) {
    const Signal x = random_signal(n, static_cast<unsigned>(5 * n + 2));
    Signal a = x, b = x;
    ComplexFft fft(n);
    fft.inverse(a.re.data(), a.im.data());
    std::vector<double> out(2 * n);
    fft.inverse_interleaved(b.re.data(), b.im.data(), out.data());
    for (std::size_t j = 0; j < n; ++j) {
      ASSERT_EQ(std::memcmp(&out[2 * j], &a.re[j], sizeof(double)), 0) << "n " << n << " j " << j;
      ASSERT_EQ(std::memcmp(&out[2 * j + 1], &a.im[j], sizeof(double)), 0)
          << "n " << n << " j " << j;
    }
  }
}

// Cross-machine reproducibility: every instruction-set variant this CPU runs gives the bits of
// the baseline (the same operations in the same order, no FMA), for every kind of plan.
TEST(ComplexFft, InstructionSetVariantsAreBitIdentical) {
  const auto& variants = fft_variants();
  ASSERT_GE(variants.size(), 1u);
  EXPECT_EQ(variants.front().name, "baseline");
  for (const auto& v : variants) std::cout << "[ variant  ] " << v.name << "\n";
  for (const std::size_t n : test_sizes()) {
    const Signal x = random_signal(n, static_cast<unsigned>(3 * n + 1));
    Signal base = x;
    ComplexFft fft(n);
    fft.forward_with("baseline", base.re.data(), base.im.data());
    for (const auto& v : variants) {
      Signal y = x;
      fft.forward_with(v.name, y.re.data(), y.im.data());
      EXPECT_EQ(std::memcmp(y.re.data(), base.re.data(), n * sizeof(double)), 0)
          << v.name << ", n = " << n;
      EXPECT_EQ(std::memcmp(y.im.data(), base.im.data(), n * sizeof(double)), 0)
          << v.name << ", n = " << n;
    }
    Signal z = x;  // forward() is one of the variants
    fft.forward(z.re.data(), z.im.data());
    EXPECT_EQ(std::memcmp(z.re.data(), base.re.data(), n * sizeof(double)), 0) << "n = " << n;
  }
}

/// The instruction-set levels this CPU runs, baseline first (internal/isa.h).
std::vector<IsaLevel> levels_on_this_cpu() {
  std::vector<IsaLevel> out = {IsaLevel::baseline};
  if (cpu_has_avx2()) out.push_back(IsaLevel::avx2);
  if (cpu_has_avx2() && cpu_has_avx512()) out.push_back(IsaLevel::avx512);
  return out;
}

// The inverse with interleaved output (its own last-pass kernels, 2, 4 and 8 wide) gives the
// bits of the baseline at every instruction-set level, over the sizes of the accuracy test.
TEST(ComplexFft, InterleavedInverseIsBitIdenticalAtEveryInstructionSetLevel) {
  for (const std::size_t n : test_sizes()) {
    const Signal x = random_signal(n, static_cast<unsigned>(7 * n + 3));
    ComplexFft fft(n);
    std::vector<double> base(2 * n);
    {
      Signal y = x;
      ForceBaselineIsa baseline;
      fft.inverse_interleaved(y.re.data(), y.im.data(), base.data());
    }
    for (const IsaLevel level : levels_on_this_cpu()) {
      Signal y = x;
      std::vector<double> out(2 * n);
      LimitIsa limit(level);
      fft.inverse_interleaved(y.re.data(), y.im.data(), out.data());
      EXPECT_EQ(std::memcmp(out.data(), base.data(), 2 * n * sizeof(double)), 0)
          << "level " << static_cast<int>(level) << ", n = " << n;
    }
  }
}

// The forward transform of interleaved input (split by the first pass's loads for radix 2, 4
// and 8 first passes, else split first; Bluestein; n = 1) gives the bits of split + forward
// with the baseline forced, at every instruction-set level.
TEST(ComplexFft, ForwardFromInterleavedIsTheForwardBitForBitAtEveryLevel) {
  for (const std::size_t n : test_sizes()) {
    const Signal x = random_signal(n, static_cast<unsigned>(11 * n + 5));
    std::vector<double> in(2 * n);
    for (std::size_t j = 0; j < n; ++j) {
      in[2 * j] = x.re[j];
      in[2 * j + 1] = x.im[j];
    }
    ComplexFft fft(n);
    Signal base = x;
    {
      ForceBaselineIsa baseline;
      fft.forward(base.re.data(), base.im.data());
    }
    for (const IsaLevel level : levels_on_this_cpu()) {
      LimitIsa limit(level);
      Signal y{std::vector<double>(n, -1.0), std::vector<double>(n, -1.0)};
      fft.forward_from_interleaved(in.data(), y.re.data(), y.im.data());
      EXPECT_EQ(std::memcmp(y.re.data(), base.re.data(), n * sizeof(double)), 0)
          << "level " << static_cast<int>(level) << ", n = " << n;
      EXPECT_EQ(std::memcmp(y.im.data(), base.im.data(), n * sizeof(double)), 0)
          << "level " << static_cast<int>(level) << ", n = " << n;
    }
  }
}

// End to end: the Gaussian filter (FFT path, with its vectorised first pass and spectrum
// steps) and the equiangular synthesis give the same bits at every instruction-set level
// (internal/isa.h), against the baseline forced.
TEST(InstructionSetVariants, FilterAndSynthesisAreBitIdenticalAtEveryLevel) {
  std::cout << "[ levels   ] " << levels_on_this_cpu().size() << " on this CPU\n";
  for (const std::size_t n : {360u, 3600u, 3601u, 3602u, 36000u}) {
    const std::vector<Point2> profile = test::lobed_noisy_ring(n, 20261127, 5e-5);
    const LeastSquaresCircle ls = least_squares_circle(profile);
    FilteredProfile base;
    LeastSquaresCircle base_ls;
    std::vector<double> deviations(n), base_closed;
    for (std::size_t j = 0; j < n; ++j)
      deviations[j] = std::hypot(profile[j].x - ls.center.x, profile[j].y - ls.center.y) -
                      ls.radius;
    {
      ForceBaselineIsa baseline;
      EXPECT_FALSE(use_avx2());
      EXPECT_FALSE(use_avx512());
      gaussian_filtered_profile(profile, 50.0, ls, base, &base_ls);
      base_closed = gaussian_filter_closed(deviations, 150.0);
    }
    for (const IsaLevel level : levels_on_this_cpu()) {
      LimitIsa limit(level);
      FilteredProfile fast;
      LeastSquaresCircle fast_ls;
      gaussian_filtered_profile(profile, 50.0, ls, fast, &fast_ls);
      ASSERT_EQ(fast.points.size(), base.points.size());
      EXPECT_EQ(fast.path, FilterPath::fft) << "n = " << n;
      EXPECT_EQ(std::memcmp(fast.points.data(), base.points.data(), n * sizeof(Point2)), 0)
          << "level " << static_cast<int>(level) << ", n = " << n;
      EXPECT_EQ(fast_ls.radius, base_ls.radius) << "n = " << n;
      const std::vector<double> closed = gaussian_filter_closed(deviations, 150.0);
      EXPECT_EQ(std::memcmp(closed.data(), base_closed.data(), n * sizeof(double)), 0)
          << "level " << static_cast<int>(level) << ", n = " << n;
    }

    std::vector<double> a(151), b(151), v_fast(n), v_base(n);
    std::mt19937_64 rng(n);
    std::normal_distribution<double> z;
    for (std::size_t k = 0; k < a.size(); ++k) {
      a[k] = z(rng);
      b[k] = z(rng);
    }
    EquiangularTransform tr(n);
    tr.values(a, b, v_fast);
    {
      ForceBaselineIsa baseline;
      tr.values(a, b, v_base);
    }
    EXPECT_EQ(std::memcmp(v_fast.data(), v_base.data(), n * sizeof(double)), 0) << "n = " << n;
  }
}

// A ceiling lowers the level while alive and restores it after; nested ceilings never raise it.
TEST(InstructionSetVariants, LimitIsaLowersTheLevelAndRestoresIt) {
  EXPECT_EQ(isa_ceiling(), IsaLevel::avx512);
  {
    LimitIsa avx2(IsaLevel::avx2);
    EXPECT_EQ(isa_ceiling(), IsaLevel::avx2);
    EXPECT_FALSE(use_avx512());
    EXPECT_EQ(use_avx2(), cpu_has_avx2());
    {
      LimitIsa wider(IsaLevel::avx512);
      EXPECT_EQ(isa_ceiling(), IsaLevel::avx2);
      ForceBaselineIsa baseline;
      EXPECT_EQ(isa_ceiling(), IsaLevel::baseline);
      EXPECT_FALSE(use_avx2());
    }
    EXPECT_EQ(isa_ceiling(), IsaLevel::avx2);
  }
  EXPECT_EQ(isa_ceiling(), IsaLevel::avx512);
  EXPECT_EQ(use_avx512(), cpu_has_avx2() && cpu_has_avx512());
}

TEST(ComplexFft, UnknownVariantIsRefused) {
  ComplexFft fft(8);
  std::vector<double> re(8), im(8);
  EXPECT_THROW(fft.forward_with("sse9", re.data(), im.data()), std::invalid_argument);
}

}  // namespace
}  // namespace vcmm::geometry::internal
