// claim_check.cpp — another program's reference circle against the exact one (method in
// vcmm/geometry/claim_check.h).
//
// The containment test sign(|p − c|² − r²) for double p, c, r: in floating point,
// d = fl(p − c) per coordinate (relative error ≤ u), d² + d² and r² each carry a relative error
// below 3u + O(u²), so |fl(|p − c|²) − |p − c|²| ≤ 4u·|p − c|² and |fl(r²) − r²| ≤ u·r²: a
// floating difference beyond 8u·(fl(|p − c|²) + fl(r²)) (plus the smallest normal, for
// underflow) has the exact sign; otherwise the sign is computed in GMP rationals.
#include "vcmm/geometry/claim_check.h"

#include <cmath>
#include <limits>
#include <sstream>

#include "internal/exact.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::geometry {
namespace {

constexpr double kUnitRoundoff = std::numeric_limits<double>::epsilon() / 2.0;
/// LS is a numerical fit: a claim within this of vcmm's centre and radius is the same fit
/// (vcmm's LS is within ~1e-13 mm of NIST's 60-digit references, docs/method.md).
constexpr double kLeastSquaresToleranceMm = 1e-9;

/// sign(|p − c|² − r²), exactly (file comment).
int compare_to_radius(Point2 p, Point2 c, double r) {
  const double dx = p.x - c.x, dy = p.y - c.y;
  const double d2 = dx * dx + dy * dy, r2 = r * r;
  const double diff = d2 - r2;
  const double bound = 8.0 * kUnitRoundoff * (d2 + r2) + std::numeric_limits<double>::min();
  if (diff > bound) return 1;
  if (diff < -bound) return -1;
  const internal::RationalPoint pe = internal::to_rational(p), ce = internal::to_rational(c);
  const internal::Rational re(r);
  const internal::Rational s = internal::squared_distance(pe, ce) - re * re;
  return s > 0 ? 1 : (s < 0 ? -1 : 0);
}

double ulp(double x) {
  const double a = std::fabs(x);
  return std::nextafter(a, std::numeric_limits<double>::infinity()) - a;
}

void require(bool ok, const std::string& message) {
  if (!ok) throw InvalidInput("check_claimed_circle: " + message);
}

}  // namespace

ClaimCheck check_claimed_circle(std::span<const Point2> points, const ClaimedCircle& claim) {
  require(std::isfinite(claim.center.x) && std::isfinite(claim.center.y),
          "the claimed centre must be finite");
  if (claim.radii) {
    const auto [r, R] = *claim.radii;
    std::ostringstream os;
    os << "the claimed radii must be finite with 0 <= inner <= outer; got " << r << ", " << R;
    require(std::isfinite(r) && std::isfinite(R) && r >= 0.0 && r <= R, os.str());
  }
  require(std::isfinite(claim.center_resolution_mm) && claim.center_resolution_mm >= 0.0,
          "the centre's resolution must be a finite number >= 0");
  ClaimCheck out;
  out.reference = claim.reference;
  const Point2 c = claim.center;

  // The exact circle (validates the points as its fitter does).
  switch (claim.reference) {
    case ReferenceCircle::minimum_zone: {
      const MinimumZoneCircle mz = minimum_zone_circle(points);
      out.exact_center = mz.center;
      out.exact_inner_radius = mz.inner_radius;
      out.exact_outer_radius = mz.outer_radius;
      out.exact_contacts = mz.outer_contacts;
      out.exact_contacts.insert(out.exact_contacts.end(), mz.inner_contacts.begin(),
                                mz.inner_contacts.end());
      out.exact_ront = mz.ron.ront;
      out.exact_certificate = mz.certificate.argument;
      out.exact_certified = verify(points, mz).valid;
      break;
    }
    case ReferenceCircle::maximum_inscribed: {
      const MaximumInscribedCircle mi = maximum_inscribed_circle(points);
      out.exact_center = mi.center;
      out.exact_inner_radius = out.exact_outer_radius = mi.radius;
      out.exact_contacts = mi.contacts;
      out.exact_ront = mi.ron.ront;
      out.exact_certificate = mi.certificate.argument;
      out.exact_certified = verify(points, mi).valid;
      break;
    }
    case ReferenceCircle::minimum_circumscribed: {
      const MinimumCircumscribedCircle mc = minimum_circumscribed_circle(points);
      out.exact_center = mc.center;
      out.exact_inner_radius = out.exact_outer_radius = mc.radius;
      out.exact_contacts = mc.contacts;
      out.exact_ront = mc.ron.ront;
      out.exact_certificate = mc.certificate.argument;
      out.exact_certified = verify(points, mc).valid;
      break;
    }
    case ReferenceCircle::least_squares: {
      const LeastSquaresCircle ls = least_squares_circle(points);
      out.exact_center = ls.center;
      out.exact_inner_radius = out.exact_outer_radius = ls.radius;
      out.exact_contacts = ls.contacts;
      out.exact_ront = ls.ron.ront;
      out.exact_certificate = "least squares: a numerical fit (Gauss-Newton), no certificate";
      out.exact_certified = false;
      break;
    }
  }

  // Distances about the claimed centre.
  double dmin = std::numeric_limits<double>::infinity(), dmax = 0.0, dsum = 0.0;
  for (const Point2& p : points) {
    const double d = std::hypot(p.x - c.x, p.y - c.y);
    dmin = std::min(dmin, d);
    dmax = std::max(dmax, d);
    dsum += d;
  }
  out.radii_given = claim.radii.has_value();
  if (claim.radii) {
    out.claimed_inner_radius = claim.radii->first;
    out.claimed_outer_radius = claim.radii->second;
  } else {
    switch (claim.reference) {
      case ReferenceCircle::minimum_zone:
        out.claimed_inner_radius = dmin;
        out.claimed_outer_radius = dmax;
        break;
      case ReferenceCircle::maximum_inscribed:
        out.claimed_inner_radius = out.claimed_outer_radius = dmin;
        break;
      case ReferenceCircle::minimum_circumscribed:
        out.claimed_inner_radius = out.claimed_outer_radius = dmax;
        break;
      case ReferenceCircle::least_squares:
        out.claimed_inner_radius = out.claimed_outer_radius =
            dsum / static_cast<double>(points.size());
        break;
    }
  }

  // Feasibility, exactly (derived radii are feasible by construction and are not tested:
  // their rounded distances could put the nearest or farthest point a rounding off its circle).
  if (claim.radii && claim.reference != ReferenceCircle::least_squares) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      bool bad = false;
      switch (claim.reference) {
        case ReferenceCircle::minimum_zone:
          bad = compare_to_radius(points[i], c, out.claimed_inner_radius) < 0 ||
                compare_to_radius(points[i], c, out.claimed_outer_radius) > 0;
          break;
        case ReferenceCircle::maximum_inscribed:
          bad = compare_to_radius(points[i], c, out.claimed_inner_radius) < 0;
          break;
        case ReferenceCircle::minimum_circumscribed:
          bad = compare_to_radius(points[i], c, out.claimed_outer_radius) > 0;
          break;
        case ReferenceCircle::least_squares:
          break;
      }
      if (bad) {
        ++out.violations;
        if (out.violating.size() < 10) out.violating.push_back(i);
      }
    }
    out.feasible = out.violations == 0;
  }

  switch (claim.reference) {
    case ReferenceCircle::minimum_zone:
      out.claimed_ront = out.claimed_outer_radius - out.claimed_inner_radius;
      break;
    case ReferenceCircle::maximum_inscribed:
      out.claimed_ront = dmax - out.claimed_inner_radius;
      out.radius_excess = out.exact_inner_radius - out.claimed_inner_radius;
      break;
    case ReferenceCircle::minimum_circumscribed:
      out.claimed_ront = out.claimed_outer_radius - dmin;
      out.radius_excess = out.claimed_outer_radius - out.exact_outer_radius;
      break;
    case ReferenceCircle::least_squares:
      out.claimed_ront = dmax - dmin;
      break;
  }
  out.excess_ront = out.claimed_ront - out.exact_ront;
  out.center_distance = std::hypot(c.x - out.exact_center.x, c.y - out.exact_center.y);
  if (claim.reference == ReferenceCircle::least_squares) {
    out.tolerance = out.radius_tolerance = kLeastSquaresToleranceMm;
    out.optimal = out.center_distance <= out.tolerance &&
                  (!claim.radii ||
                   std::fabs(out.claimed_inner_radius - out.exact_inner_radius) <= out.tolerance);
  } else {
    const double ulps = 4.0 * (ulp(c.x) + ulp(c.y)) + 8.0 * ulp(out.exact_outer_radius);
    out.tolerance = 2.0 * std::sqrt(2.0) * claim.center_resolution_mm + ulps;
    out.radius_tolerance = std::sqrt(2.0) * claim.center_resolution_mm + ulps;
    out.optimal = out.feasible && out.excess_ront <= out.tolerance &&
                  out.radius_excess <= out.radius_tolerance;
  }
  return out;
}

}  // namespace vcmm::geometry
