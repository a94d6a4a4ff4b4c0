// tests/uncertainty/varied_experiment.h — the experiment the engine's determinism tests share.
#pragma once

#include <cstddef>
#include <span>

#include "vcmm/uncertainty/monte_carlo.h"

namespace vcmm::test {

// An experiment that uses a trial-dependent number of normals and uniforms (so a mix-up of
// streams or slots between threads or processes cannot go unnoticed): three measurands.
inline const uncertainty::Experiment kVariedExperiment = [](uncertainty::RandomStream& rng,
                                                            std::span<double> y) {
  const auto n = static_cast<std::size_t>(1 + rng.next_u64() % 40);
  double normals[40];
  rng.fill_standard_normal({normals, n});
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) sum += normals[i];
  y[0] = sum;
  y[1] = rng.uniform();
  y[2] = static_cast<double>(n);
};

}  // namespace vcmm::test
