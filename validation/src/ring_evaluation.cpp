// validation/src/ring_evaluation.cpp — the measurands of a ring section (see the header).
#include "vcmm/validation/ring_evaluation.h"

#include <cmath>
#include <numbers>

#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/maximum_inscribed_from_extremes.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/minimum_zone_from_extremes.h"

namespace vcmm::validation {
namespace {

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
    // The filter about the LS circle just fitted (bit for bit the filter's own fit), into a
    // per-thread profile (a Monte Carlo run allocates no points per trial). With the LS
    // reference only the LS circle of the filter's output is needed: one step on its rays
    // instead of a second fit (the same circle to ~1e-14 mm), without forming the points, and
    // without checking the points again (least_squares_circle has; gaussian_filter.h; the
    // other references skip that check too).
    thread_local geometry::FilteredProfile filtered;
    if (options.reference == ReferenceCircle::least_squares) {
      out.roundness_mm = geometry::gaussian_filtered_least_squares_circle(
                             profile, *options.filter_cutoff_upr, ls, /*points_validated=*/true)
                             .ron.ront;
    } else if (options.reference == ReferenceCircle::minimum_zone ||
               options.reference == ReferenceCircle::maximum_inscribed) {
      // MZ and MI from a subset of the filtered profile's extremes about the filter centre,
      // proven to decide the circle of all points: RONt bit for bit minimum_zone_circle's and
      // maximum_inscribed_circle's (*_from_extremes.h), at a fraction of the full fit's cost.
      thread_local geometry::ExtremesScratch extremes;
      geometry::gaussian_filtered_profile(profile, *options.filter_cutoff_upr, ls, filtered,
                                          nullptr, geometry::FilterPathChoice::automatic,
                                          /*points_validated=*/true);
      out.roundness_mm =
          options.reference == ReferenceCircle::minimum_zone
              ? geometry::minimum_zone_ront_from_extremes(filtered.points,
                                                          filtered.filter_center, extremes)
              : geometry::maximum_inscribed_ront_from_extremes(filtered.points,
                                                               filtered.filter_center, extremes);
    } else {
      geometry::gaussian_filtered_profile(profile, *options.filter_cutoff_upr, ls, filtered,
                                          nullptr, geometry::FilterPathChoice::automatic,
                                          /*points_validated=*/true);
      out.roundness_mm = fit_reference(filtered.points, options.reference).ront;
    }
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

double ront_about(std::span<const geometry::Point2> profile, ReferenceCircle circle) {
  return fit_reference(profile, circle).ront;
}

}  // namespace vcmm::validation
