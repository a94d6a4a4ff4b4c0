// tests/support/perfect_model.h — the digital model of a perfect machine for the validation
// tests: a moving bridge with zero kinematic errors over 1200 × 1000 × 800 mm, every other
// source zero (tests switch on what they study).
#pragma once

#include <array>

#include "vcmm/errormodel/digital_model.h"

namespace vcmm::test {

inline errormodel::DigitalModel perfect_model() {
  const std::array<errormodel::AxisRange, 3> ranges = {{{0, 1200}, {0, 1000}, {0, 800}}};
  return errormodel::DigitalModel(
      errormodel::KinematicModel::zero(errormodel::KinematicChain::moving_bridge(), ranges));
}

}  // namespace vcmm::test
