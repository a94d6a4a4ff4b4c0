// vcmm/validation/trial_kind.h — which Monte Carlo trial a ring uncertainty evaluation runs:
// the exact point-wise one (ring_experiment.h) or the spectral one (spectral_trial.h).
#pragma once

#include <optional>
#include <string_view>

namespace vcmm::validation {

enum class TrialKind {
  automatic,  ///< spectral where it applies (spectral_trial_applicability), else exact
  exact,      ///< point by point (RingTrial)
  spectral,   ///< in-band harmonics (SpectralRingTrial); refused where it does not apply
};
/// "auto", "exact", "spectral" (the CLI's --trial values and the campaign key "trial").
std::string_view to_string(TrialKind kind);
std::optional<TrialKind> trial_kind_from_string(std::string_view text);

}  // namespace vcmm::validation
