// vcmm/errormodel/random_source.h — where error draws get their random numbers.
//
// The error model only consumes random numbers; the uncertainty module owns seeding and
// supplies one independent stream per Monte Carlo trial (validation/ adapts its counter-based
// generator to this interface). Numbers are requested in bulk so that one virtual call serves
// a whole ring (the inner loop of Monte Carlo).
#pragma once

#include <cstdint>
#include <span>

namespace vcmm::errormodel {

class RandomSource {
 public:
  virtual ~RandomSource() = default;
  /// Fills `out` with independent standard normal variates N(0, 1).
  virtual void fill_standard_normal(std::span<double> out) = 0;
  /// Fills `out` with independent variates uniform on [0, 1).
  virtual void fill_uniform(std::span<double> out) = 0;
  /// Fills `out` with sigma times independent standard normal variates: by default
  /// fill_standard_normal, then each value times sigma; a source may fuse the two (the same
  /// values bit for bit).
  virtual void fill_normal(std::span<double> out, double sigma) {
    fill_standard_normal(out);
    for (double& v : out) v *= sigma;
  }

  double standard_normal() {
    double v = 0.0;
    fill_standard_normal({&v, 1});
    return v;
  }
  double uniform() {
    double v = 0.0;
    fill_uniform({&v, 1});
    return v;
  }
};

/// A seeded, portable source (xoshiro256** with splitmix64 seeding; uniforms from the top 53
/// bits; normals by the Marsaglia polar method written here, not std::normal_distribution) —
/// the same numbers with any standard library. For tests, examples and `vcmm simulate`.
class SeededRandomSource final : public RandomSource {
 public:
  explicit SeededRandomSource(std::uint64_t seed);
  void fill_standard_normal(std::span<double> out) override;
  void fill_uniform(std::span<double> out) override;

 private:
  std::uint64_t next();
  std::uint64_t s_[4];
  double spare_ = 0.0;
  bool has_spare_ = false;
};

}  // namespace vcmm::errormodel
