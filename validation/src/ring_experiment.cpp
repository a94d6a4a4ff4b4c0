// validation/src/ring_experiment.cpp — the ring-gauge virtual experiment (see the header for
// the flow and docs/validation.md for the method).
//
// The adapter StreamRandomSource gives errormodel's bulk RandomSource interface the numbers of
// the trial's own counter-based stream, so trial t's errors depend on (seed, t) only.
#include "vcmm/validation/ring_experiment.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <string>

#include "vcmm/geometry/point.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::validation {
namespace {

/// errormodel::RandomSource over the trial's uncertainty::RandomStream.
class StreamRandomSource final : public errormodel::RandomSource {
 public:
  explicit StreamRandomSource(uncertainty::RandomStream& stream) : stream_(stream) {}
  void fill_standard_normal(std::span<double> out) override { stream_.fill_standard_normal(out); }
  void fill_uniform(std::span<double> out) override { stream_.fill_uniform(out); }

 private:
  uncertainty::RandomStream& stream_;
};

void project_xy(const errormodel::Measurement& m, std::vector<geometry::Point2>& out) {
  const Eigen::Index n = m.size();
  out.resize(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    out[static_cast<std::size_t>(i)] = {m.points_mm(0, i), m.points_mm(1, i)};
  }
}

struct ReferenceFit {
  geometry::Point2 center;
  double radius = 0.0;
  double ront = 0.0;
};

ReferenceFit fit_reference(std::span<const geometry::Point2> pts, ReferenceCircle circle) {
  switch (circle) {
    case ReferenceCircle::minimum_zone: {
      const auto mz = geometry::minimum_zone_circle(pts);
      return {mz.center, 0.5 * (mz.inner_radius + mz.outer_radius), mz.ron.ront};
    }
    case ReferenceCircle::maximum_inscribed: {
      const auto mi = geometry::maximum_inscribed_circle(pts);
      return {mi.center, mi.radius, mi.ron.ront};
    }
    case ReferenceCircle::least_squares: {
      const auto ls = geometry::least_squares_circle(pts);
      return {ls.center, ls.radius, ls.ron.ront};
    }
    case ReferenceCircle::minimum_circumscribed: {
      const auto mc = geometry::minimum_circumscribed_circle(pts);
      return {mc.center, mc.radius, mc.ron.ront};
    }
  }
  throw geometry::InvalidInput("evaluate_ring: unknown reference circle");
}

}  // namespace

std::vector<geometry::Point2> ring_profile(const errormodel::Measurement& m) {
  std::vector<geometry::Point2> out;
  project_xy(m, out);
  return out;
}

RingMeasurands evaluate_ring(std::span<const geometry::Point2> profile,
                             const RingEvaluationOptions& options) {
  RingMeasurands out;
  const geometry::LeastSquaresCircle ls = geometry::least_squares_circle(profile);
  out.diameter_mm = 2.0 * ls.radius;
  if (options.filter_cutoff_upr) {
    // The filter about the LS circle just fitted (bit for bit the filter's own fit).
    const auto filtered =
        geometry::gaussian_filtered_profile(profile, *options.filter_cutoff_upr, ls);
    out.roundness_mm = fit_reference(filtered.points, options.reference).ront;
  } else {
    out.roundness_mm = fit_reference(profile, options.reference).ront;
  }
  return out;
}

RingMeasurands evaluate_ring(const errormodel::Measurement& m,
                             const RingEvaluationOptions& options) {
  errormodel::validate_measurement(m, "evaluate_ring");
  return evaluate_ring(ring_profile(m), options);
}

RingProfileEvaluation evaluate_ring_profile(std::span<const geometry::Point2> profile,
                                            const RingEvaluationOptions& options) {
  RingProfileEvaluation out;
  out.measurands.diameter_mm = 2.0 * geometry::least_squares_circle(profile).radius;
  std::vector<geometry::Point2> filtered(profile.begin(), profile.end());
  if (options.filter_cutoff_upr) {
    filtered = geometry::gaussian_filtered_profile(profile, *options.filter_cutoff_upr).points;
  }
  const ReferenceFit fit = fit_reference(filtered, options.reference);
  out.measurands.roundness_mm = fit.ront;
  out.reference_center = fit.center;
  out.reference_radius_mm = fit.radius;
  const std::size_t n = profile.size();
  out.angle_rad.resize(n);
  out.deviation_mm.resize(n);
  out.filtered_deviation_mm.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double dx = profile[i].x - fit.center.x, dy = profile[i].y - fit.center.y;
    double a = std::atan2(dy, dx);
    if (a < 0.0) a += 2.0 * std::numbers::pi;
    out.angle_rad[i] = a;
    out.deviation_mm[i] = std::hypot(dx, dy) - fit.radius;
    out.filtered_deviation_mm[i] =
        std::hypot(filtered[i].x - fit.center.x, filtered[i].y - fit.center.y) - fit.radius;
  }
  return out;
}

errormodel::Measurement denoised_ring(const errormodel::Measurement& m, double cutoff_upr) {
  errormodel::validate_measurement(m, "denoised_ring");
  const auto profile = ring_profile(m);
  const auto filtered = geometry::gaussian_filtered_profile(profile, cutoff_upr);
  errormodel::Measurement out = m;
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    out.points_mm(0, i) = filtered.points[static_cast<std::size_t>(i)].x;
    out.points_mm(1, i) = filtered.points[static_cast<std::size_t>(i)].y;
  }
  return out;
}

RingTrial::RingTrial(const errormodel::DigitalModel& model,
                     std::shared_ptr<const errormodel::PreparedMeasurement> prepared,
                     const RingEvaluationOptions& options, const errormodel::Stages& stages)
    : model_(&model), prepared_(std::move(prepared)), options_(options), stages_(stages) {
  if (!prepared_) throw geometry::InvalidInput("RingTrial: no prepared measurement");
}

void RingTrial::operator()(uncertainty::RandomStream& rng, std::span<double> measurands) {
  StreamRandomSource source(rng);
  errormodel::draw_errors(*model_, *prepared_, source, stages_, draw_);
  errormodel::simulate_corrected(*prepared_, *model_, draw_, stages_,
                                 errormodel::Formula::first_order, profile_);
  const RingMeasurands y = evaluate_ring(profile_, options_);
  measurands[diameter] = y.diameter_mm;
  measurands[roundness] = y.roundness_mm;
}

uncertainty::ExperimentFactory ring_experiment_factory(const errormodel::DigitalModel& model,
                                                       const errormodel::Measurement& best,
                                                       const RingEvaluationOptions& options,
                                                       const errormodel::Stages& stages) {
  auto prepared = std::make_shared<const errormodel::PreparedMeasurement>(best, model);
  return [&model, prepared, options, stages]() -> uncertainty::Experiment {
    auto trial = std::make_shared<RingTrial>(model, prepared, options, stages);
    return [trial](uncertainty::RandomStream& rng, std::span<double> out) { (*trial)(rng, out); };
  };
}

namespace {

RingUncertaintyResult run_on_surface(const errormodel::DigitalModel& model,
                                     errormodel::Measurement surface,
                                     const RingUncertaintyOptions& options) {
  RingUncertaintyResult result;
  result.best_estimate = std::move(surface);
  result.estimate = evaluate_ring(result.best_estimate, options.evaluation);
  const auto factory = ring_experiment_factory(model, result.best_estimate, options.evaluation,
                                               options.stages);
  result.monte_carlo =
      options.adaptive
          ? uncertainty::run_adaptive_monte_carlo(factory, ring_measurand_count,
                                                  *options.adaptive, options.monte_carlo)
          : uncertainty::run_monte_carlo(factory, ring_measurand_count, options.monte_carlo);
  if (!result.monte_carlo.summaries.empty()) {  // none below the minimum sample count
    result.diameter = uncertainty::correct_bias(
        result.estimate.diameter_mm, result.monte_carlo.summaries[diameter], true);
    result.roundness = uncertainty::correct_bias(
        result.estimate.roundness_mm, result.monte_carlo.summaries[roundness], true);
  }
  return result;
}

}  // namespace

RingUncertaintyResult evaluate_ring_uncertainty(const errormodel::DigitalModel& model,
                                                const errormodel::Measurement& measured,
                                                const RingUncertaintyOptions& options) {
  errormodel::validate_measurement(measured, "evaluate_ring_uncertainty");
  return run_on_surface(model,
                        errormodel::correct(measured, model, options.stages,
                                            errormodel::Formula::first_order),
                        options);
}

RingUncertaintyResult evaluate_ring_uncertainty_on_surface(
    const errormodel::DigitalModel& model, const errormodel::Measurement& truth_estimate,
    const RingUncertaintyOptions& options) {
  errormodel::validate_measurement(truth_estimate, "evaluate_ring_uncertainty_on_surface");
  return run_on_surface(model, truth_estimate, options);
}

}  // namespace vcmm::validation
