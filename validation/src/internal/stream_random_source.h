// validation/src/internal/stream_random_source.h — errormodel's bulk RandomSource interface
// over a Monte Carlo trial's own counter-based uncertainty::RandomStream, so that trial t's
// errors depend on (seed, t) only. Not part of the public API.
#pragma once

#include <span>

#include "vcmm/errormodel/random_source.h"
#include "vcmm/uncertainty/random_stream.h"

namespace vcmm::validation::internal {

class StreamRandomSource final : public errormodel::RandomSource {
 public:
  explicit StreamRandomSource(uncertainty::RandomStream& stream) : stream_(stream) {}
  void fill_standard_normal(std::span<double> out) override { stream_.fill_standard_normal(out); }
  void fill_uniform(std::span<double> out) override { stream_.fill_uniform(out); }
  void fill_normal(std::span<double> out, double sigma) override {
    stream_.fill_normal(out, sigma);
  }

 private:
  uncertainty::RandomStream& stream_;
};

}  // namespace vcmm::validation::internal
