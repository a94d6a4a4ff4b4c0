// validation/src/form_bias.cpp — the shrinkage bias treatment (method and notation in
// vcmm/validation/form_bias.h).
#include "vcmm/validation/form_bias.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "internal/stream_random_source.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"

namespace vcmm::validation {
namespace {

using internal::StreamRandomSource;
namespace em = vcmm::errormodel;

/// Whether any harmonic of order ≥ 2 survives the shrinkage. When none does, the surrogate
/// is a circle: its deviations a_0 + a_1 cos θ + b_1 sin θ are a circle displaced by (a_1, b_1)
/// to second order, off it by at most (a_1² + b_1²)/R — below 1e-10 mm for the µm-level
/// centre offsets of a fitted profile — so its RONt is taken as 0 rather than asked of the
/// reference-circle fitters, which are slow on data co-circular to the last ulp (issue 11).
bool has_form(std::span<const double> gains) {
  for (std::size_t k = 2; k < gains.size(); ++k)
    if (gains[k] != 0.0) return true;
  return false;
}

/// Pilot trial (step 1): the power of the error's harmonics, |X_k(x̂ + e) − X_k(x̂)|².
class PilotTrial {
 public:
  PilotTrial(const em::DigitalModel& model, std::shared_ptr<const em::PreparedMeasurement> best,
             const em::Stages& stages, std::shared_ptr<const geometry::ProfileHarmonics> reference)
      : model_(&model), best_(std::move(best)), stages_(stages), reference_(std::move(reference)) {}

  void operator()(uncertainty::RandomStream& rng, std::span<double> out) {
    StreamRandomSource source(rng);
    em::draw_errors(*model_, *best_, source, stages_, draw_, em::NoiseComponents::xy);
    em::simulate_corrected(*best_, *model_, draw_, stages_, em::Formula::first_order, profile_);
    const geometry::LeastSquaresCircle ls = geometry::least_squares_circle(profile_);
    harmonics_.analyse(profile_, ls.center, ls.radius, reference_->max_order());
    for (std::size_t k = 0; k < out.size(); ++k) {
      const double da = harmonics_.cos_mm(k) - reference_->cos_mm(k);
      const double db = harmonics_.sin_mm(k) - reference_->sin_mm(k);
      out[k] = da * da + db * db;
    }
  }

 private:
  const em::DigitalModel* model_;
  std::shared_ptr<const em::PreparedMeasurement> best_;
  em::Stages stages_;
  std::shared_ptr<const geometry::ProfileHarmonics> reference_;
  em::ErrorDraw draw_;
  std::vector<geometry::Point2> profile_;
  geometry::ProfileHarmonics harmonics_;
};

/// Trial of the run at the surrogate (step 4): diameter, y*, z*.
class SurrogateTrial {
 public:
  SurrogateTrial(const em::DigitalModel& model,
                 std::shared_ptr<const em::PreparedMeasurement> surrogate,
                 const RingEvaluationOptions& evaluation, const em::Stages& stages,
                 const HarmonicShrinkage& shrinkage)
      : model_(&model),
        surrogate_(std::move(surrogate)),
        evaluation_(evaluation),
        stages_(stages),
        shrinkage_(&shrinkage),
        transmission_(filter_transmission(evaluation, shrinkage.max_order)),
        gains_(shrinkage.max_order + 1) {}

  void operator()(uncertainty::RandomStream& rng, std::span<double> out) {
    StreamRandomSource source(rng);
    em::draw_errors(*model_, *surrogate_, source, stages_, draw_, em::NoiseComponents::xy);
    em::simulate_corrected(*surrogate_, *model_, draw_, stages_, em::Formula::first_order,
                           profile_);
    const geometry::LeastSquaresCircle ls = geometry::least_squares_circle(profile_);
    out[surrogate_diameter] = 2.0 * ls.radius;
    if (evaluation_.filter_cutoff_upr) {
      const auto filtered =
          geometry::gaussian_filtered_profile(profile_, *evaluation_.filter_cutoff_upr, ls);
      out[surrogate_roundness] = ront_about(filtered.points, evaluation_.reference);
    } else {
      out[surrogate_roundness] = ront_about(profile_, evaluation_.reference);
    }
    harmonics_.analyse(profile_, ls.center, ls.radius, shrinkage_->max_order);
    shrinkage_->gains(harmonics_, transmission_, gains_);
    if (has_form(gains_)) {
      harmonics_.synthesize(gains_, shrunk_);
      out[surrogate_shrunk] = ront_about(shrunk_, evaluation_.reference);
    } else {
      out[surrogate_shrunk] = 0.0;  // no form left: a circle (has_form)
    }
  }

 private:
  const em::DigitalModel* model_;
  std::shared_ptr<const em::PreparedMeasurement> surrogate_;
  RingEvaluationOptions evaluation_;
  em::Stages stages_;
  const HarmonicShrinkage* shrinkage_;
  std::vector<double> transmission_, gains_;
  em::ErrorDraw draw_;
  std::vector<geometry::Point2> profile_, shrunk_;
  geometry::ProfileHarmonics harmonics_;
};

}  // namespace

std::string_view to_string(RoundnessBiasTreatment treatment) {
  switch (treatment) {
    case RoundnessBiasTreatment::shrinkage: return "shrinkage";
    case RoundnessBiasTreatment::paper: return "paper";
  }
  return "?";
}

std::optional<RoundnessBiasTreatment> roundness_bias_treatment_from_string(std::string_view text) {
  if (text == "shrinkage") return RoundnessBiasTreatment::shrinkage;
  if (text == "paper") return RoundnessBiasTreatment::paper;
  return std::nullopt;
}

void HarmonicShrinkage::gains(const geometry::ProfileHarmonics& h,
                              std::span<const double> transmission,
                              std::span<double> out) const {
  if (h.max_order() != max_order || out.size() != max_order + 1 ||
      (!transmission.empty() && transmission.size() != max_order + 1))
    throw std::invalid_argument(
        "HarmonicShrinkage::gains: the profile must be analysed up to K = " +
        std::to_string(max_order) + " (got " + std::to_string(h.max_order()) + ") and out (" +
        std::to_string(out.size()) + ") and the transmission (" +
        std::to_string(transmission.size()) + ") must hold K + 1 values");
  for (std::size_t k = 0; k <= max_order; ++k) {
    double s = 1.0;
    if (k >= 2) {
      const double p = h.power_mm2(k);
      s = p > 0.0 ? std::sqrt(std::max(0.0, 1.0 - threshold[k] * error_power_mm2[k] / p)) : 0.0;
    }
    out[k] = transmission.empty() ? s : s * transmission[k];
  }
}

std::size_t shrinkage_max_order(const RingEvaluationOptions& evaluation, std::size_t points,
                                double min_filter_gain) {
  const std::size_t half = points / 2;
  if (!evaluation.filter_cutoff_upr) return half;
  if (!(min_filter_gain > 0.0 && min_filter_gain < 1.0))
    throw std::invalid_argument("shrinkage_max_order: min_filter_gain must lie in (0, 1); got " +
                                std::to_string(min_filter_gain));
  // 2^−(k/f_c)² ≥ g  ⇔  k ≤ f_c √(log₂(1/g)).
  const double k = *evaluation.filter_cutoff_upr * std::sqrt(std::log2(1.0 / min_filter_gain));
  return std::clamp<std::size_t>(static_cast<std::size_t>(std::floor(k)), std::min<std::size_t>(2, half),
                                 half);
}

std::vector<double> filter_transmission(const RingEvaluationOptions& evaluation, std::size_t K) {
  std::vector<double> h(K + 1, 1.0);
  if (evaluation.filter_cutoff_upr) {
    const double fc = *evaluation.filter_cutoff_upr;
    for (std::size_t k = 0; k <= K; ++k) {
      const double r = static_cast<double>(k) / fc;
      h[k] = std::exp2(-r * r);
    }
  }
  return h;
}

std::optional<HarmonicShrinkage> estimate_harmonic_shrinkage(
    const em::DigitalModel& model, const em::Measurement& best,
    const RingEvaluationOptions& evaluation, const em::Stages& stages,
    const ShrinkageOptions& options, const uncertainty::MonteCarloOptions& run) {
  if (!(options.dominance_ratio > 0.0 && std::isfinite(options.dominance_ratio)))
    throw std::invalid_argument(
        "estimate_harmonic_shrinkage: dominance_ratio must be a finite number > 0; got " +
        std::to_string(options.dominance_ratio));
  if (options.pilot_trials < 2)
    throw std::invalid_argument(
        "estimate_harmonic_shrinkage: pilot_trials must be at least 2; got " +
        std::to_string(options.pilot_trials));
  const auto prepared = std::make_shared<const em::PreparedMeasurement>(best, model);
  const std::vector<geometry::Point2> profile = ring_profile(best);
  const std::size_t K = shrinkage_max_order(evaluation, profile.size(), options.min_filter_gain);
  const geometry::LeastSquaresCircle ls = geometry::least_squares_circle(profile);
  const auto reference =
      std::make_shared<const geometry::ProfileHarmonics>(profile, ls.center, ls.radius, K);

  uncertainty::MonteCarloOptions mc = run;
  mc.trials = options.pilot_trials;
  mc.progress = {};
  const uncertainty::ExperimentFactory factory = [&model, prepared, stages, reference]() {
    auto trial = std::make_shared<PilotTrial>(model, prepared, stages, reference);
    return uncertainty::Experiment(
        [trial](uncertainty::RandomStream& rng, std::span<double> out) { (*trial)(rng, out); });
  };
  const uncertainty::MonteCarloResult pilot = uncertainty::run_monte_carlo(factory, K + 1, mc);
  if (pilot.status == uncertainty::RunStatus::cancelled) return std::nullopt;

  HarmonicShrinkage s;
  s.max_order = K;
  s.pilot_trials = pilot.trials;
  s.error_power_mm2.resize(K + 1);
  for (std::size_t k = 0; k <= K; ++k) s.error_power_mm2[k] = pilot.summaries[k].mean;
  std::vector<double> v(s.error_power_mm2.begin() + 2, s.error_power_mm2.end());
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
  s.median_error_power_mm2 = v[v.size() / 2];
  const double log_k = std::log(static_cast<double>(K));
  s.threshold.assign(K + 1, 0.0);
  for (std::size_t k = 2; k <= K; ++k) {
    const bool dominant =
        s.error_power_mm2[k] > options.dominance_ratio * s.median_error_power_mm2;
    s.threshold[k] = dominant ? 1.0 : log_k;
    s.dominant_orders += dominant ? 1 : 0;
  }
  return s;
}

Surrogate shrunk_ring(const em::Measurement& best, const HarmonicShrinkage& shrinkage,
                      const RingEvaluationOptions& evaluation) {
  const std::vector<geometry::Point2> profile = ring_profile(best);
  const geometry::LeastSquaresCircle ls = geometry::least_squares_circle(profile);
  const geometry::ProfileHarmonics h(profile, ls.center, ls.radius, shrinkage.max_order);
  std::vector<double> gains(shrinkage.max_order + 1);
  shrinkage.gains(h, {}, gains);
  Surrogate out;
  for (std::size_t k = 2; k < gains.size(); ++k) out.kept_harmonics += gains[k] > 0.0 ? 1 : 0;
  const std::vector<geometry::Point2> shrunk = h.synthesized(gains);
  out.surface = best;
  for (Eigen::Index i = 0; i < out.surface.size(); ++i) {
    out.surface.points_mm(0, i) = shrunk[static_cast<std::size_t>(i)].x;
    out.surface.points_mm(1, i) = shrunk[static_cast<std::size_t>(i)].y;
  }
  if (out.kept_harmonics > 0) {
    out.measurands = evaluate_ring(shrunk, evaluation);
  } else {
    out.measurands.diameter_mm = 2.0 * geometry::least_squares_circle(shrunk).radius;
    out.measurands.roundness_mm = 0.0;  // a circle (has_form)
  }
  return out;
}

uncertainty::ExperimentFactory surrogate_experiment_factory(
    const em::DigitalModel& model, const em::Measurement& surrogate,
    const RingEvaluationOptions& evaluation, const em::Stages& stages,
    const HarmonicShrinkage& shrinkage) {
  auto prepared = std::make_shared<const em::PreparedMeasurement>(surrogate, model);
  return [&model, prepared, evaluation, stages, &shrinkage]() -> uncertainty::Experiment {
    auto trial = std::make_shared<SurrogateTrial>(model, prepared, evaluation, stages, shrinkage);
    return [trial](uncertainty::RandomStream& rng, std::span<double> out) { (*trial)(rng, out); };
  };
}

}  // namespace vcmm::validation
