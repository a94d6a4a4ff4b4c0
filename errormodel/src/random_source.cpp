#include "vcmm/errormodel/random_source.h"

#include <cmath>

namespace vcmm::errormodel {
namespace {
std::uint64_t splitmix64(std::uint64_t& s) {
  std::uint64_t z = (s += 0x9E3779B97F4A7C15ULL);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}
std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
}  // namespace

SeededRandomSource::SeededRandomSource(std::uint64_t seed) {
  std::uint64_t s = seed;
  for (auto& w : s_) w = splitmix64(s);
}

std::uint64_t SeededRandomSource::next() {  // xoshiro256** (Blackman & Vigna 2018)
  const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
  const std::uint64_t t = s_[1] << 17;
  s_[2] ^= s_[0];
  s_[3] ^= s_[1];
  s_[1] ^= s_[2];
  s_[0] ^= s_[3];
  s_[2] ^= t;
  s_[3] = rotl(s_[3], 45);
  return result;
}

void SeededRandomSource::fill_uniform(std::span<double> out) {
  for (double& v : out) v = static_cast<double>(next() >> 11) * 0x1.0p-53;
}

void SeededRandomSource::fill_standard_normal(std::span<double> out) {
  // Marsaglia polar method: exact N(0,1) from two uniforms on (−1, 1), accepted inside the
  // unit disc (probability π/4), yielding two independent normals.
  for (double& v : out) {
    if (has_spare_) {
      has_spare_ = false;
      v = spare_;
      continue;
    }
    double u, w, s;
    do {
      u = static_cast<double>(next() >> 11) * 0x1.0p-52 - 1.0;
      w = static_cast<double>(next() >> 11) * 0x1.0p-52 - 1.0;
      s = u * u + w * w;
    } while (s >= 1.0 || s == 0.0);
    const double f = std::sqrt(-2.0 * std::log(s) / s);
    spare_ = w * f;
    has_spare_ = true;
    v = u * f;
  }
}

}  // namespace vcmm::errormodel
