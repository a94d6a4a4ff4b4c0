// capi/src/vcmm_c.cpp — the C interface over vcmm::geometry::evaluate_roundness
// (include/vcmm/vcmm_c.h). No exception leaves this file: each entry point catches
// everything and turns it into a status and a message in the caller's buffer.
#include "vcmm/vcmm_c.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <new>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/roundness.h"

namespace g = vcmm::geometry;

namespace {

constexpr double kDegreesPerRadian = 57.295779513082320876798154814105;

/// Copies `text` into buf[0..size) cut and 0-terminated (nothing when buf is null or size 0).
void copy_text(std::string_view text, char* buf, std::size_t size) {
  if (buf == nullptr || size == 0) return;
  const std::size_t n = std::min(text.size(), size - 1);
  std::memcpy(buf, text.data(), n);
  buf[n] = '\0';
}

/// An argument the caller got wrong (reported as VCMM_ERROR_INVALID_ARGUMENT).
struct BadArgument {
  std::string message;
};

/// A defined circle: centre, radii (MZ: inner and outer; the others: both the radius),
/// RON parameters and contacts (MZ: the outer ones first).
void fill(vcmm_circle& out, g::Point2 center, double inner_radius, double outer_radius,
          const g::RoundnessParameters& ron, const std::vector<std::size_t>& first,
          const std::vector<std::size_t>& second = {}) {
  out.defined = 1;
  out.center_x = center.x;
  out.center_y = center.y;
  out.inner_radius = inner_radius;
  out.outer_radius = outer_radius;
  out.radius = inner_radius == outer_radius ? inner_radius : 0.5 * (inner_radius + outer_radius);
  out.ront = ron.ront;
  out.ronp = ron.ronp;
  out.ronv = ron.ronv;
  out.ronq = ron.ronq;
  if (first.size() + second.size() > VCMM_MAX_CONTACTS)
    throw std::logic_error("a circle with more than VCMM_MAX_CONTACTS contacts");
  std::size_t k = 0;
  for (std::size_t i : first) out.contacts[k++] = i;
  for (std::size_t i : second) out.contacts[k++] = i;
  out.n_contacts = k;
  out.n_outer_contacts = first.size();
}

template <class Circle>
void set_verification(vcmm_circle& out, std::span<const g::Point2> profile, const Circle& circle,
                      bool run) {
  out.global_optimum = circle.certificate.optimality == g::Optimality::global ? 1 : 0;
  if (!run) {
    out.verified = -1;
    return;
  }
  const g::Verification v = g::verify(profile, circle);
  out.verified = v.valid ? 1 : 0;
  if (!v.valid) copy_text("verification failed: " + v.reason, out.reason, VCMM_REASON_SIZE);
}

/// Requested; the reason it is undefined, or its caution.
void set_outcome(vcmm_circle& out, g::ReferenceCircle which, const g::RoundnessEvaluation& e) {
  out.requested = 1;
  if (const auto u = e.undefined.find(which); u != e.undefined.end())
    copy_text(u->second, out.reason, VCMM_REASON_SIZE);
  if (const auto c = e.cautions.find(which); c != e.cautions.end()) {
    out.caution = 1;
    if (out.reason[0] == '\0') copy_text(c->second, out.reason, VCMM_REASON_SIZE);
  }
}

vcmm_status evaluate(const double* xy, std::size_t n, const vcmm_roundness_options& options,
                     vcmm_roundness_result& result, double* filtered_xy) {
  if (options.circles == 0 || (options.circles & ~VCMM_CIRCLE_ALL) != 0)
    throw BadArgument{"options.circles must be a non-empty combination of VCMM_CIRCLE_LS, "
                      "_MZ, _MI and _MC (got " + std::to_string(options.circles) + ")"};
  if (!(options.filter_cutoff_upr >= 0.0) || !std::isfinite(options.filter_cutoff_upr))
    throw BadArgument{"options.filter_cutoff_upr must be 0 (unfiltered) or a finite cut-off "
                      "> 0 UPR (got " + std::to_string(options.filter_cutoff_upr) + ")"};
  if (options.verify != 0 && options.verify != 1)
    throw BadArgument{"options.verify must be 0 or 1"};

  std::vector<g::Point2> points(n);
  for (std::size_t i = 0; i < n; ++i) points[i] = {xy[2 * i], xy[2 * i + 1]};

  g::RoundnessRequest request;
  request.least_squares = (options.circles & VCMM_CIRCLE_LS) != 0;
  request.minimum_zone = (options.circles & VCMM_CIRCLE_MZ) != 0;
  request.maximum_inscribed = (options.circles & VCMM_CIRCLE_MI) != 0;
  request.minimum_circumscribed = (options.circles & VCMM_CIRCLE_MC) != 0;
  if (options.filter_cutoff_upr > 0.0) request.filter_cutoff_upr = options.filter_cutoff_upr;

  const g::RoundnessEvaluation e = g::evaluate_roundness(points, request);
  const std::span<const g::Point2> profile =
      e.filtered_points.empty() ? std::span<const g::Point2>(points) : e.filtered_points;
  const bool run_verify = options.verify == 1;

  result.n_points = e.n_points;
  result.filter_cutoff_upr = e.filter_cutoff_upr.value_or(0.0);
  result.open_profile_filter = e.filter_path == g::FilterPath::open_profile ? 1 : 0;
  result.n_defined = e.defined_count();
  if (result.n_defined > 0) {
    result.covered_deg = e.coverage.covered_rad * kDegreesPerRadian;
    result.closed = e.coverage.closed ? 1 : 0;
  }

  if (request.least_squares) {
    if (const auto& ls = e.least_squares) {
      fill(result.ls, ls->center, ls->radius, ls->radius, ls->ron, ls->contacts);
      result.ls.global_optimum = 1;
      result.ls.verified = -1;
    }
    set_outcome(result.ls, g::ReferenceCircle::least_squares, e);
  }
  if (request.minimum_zone) {
    if (const auto& mz = e.minimum_zone) {
      fill(result.mz, mz->center, mz->inner_radius, mz->outer_radius, mz->ron,
           mz->outer_contacts, mz->inner_contacts);
      set_verification(result.mz, profile, *mz, run_verify);
    }
    set_outcome(result.mz, g::ReferenceCircle::minimum_zone, e);
  }
  if (request.maximum_inscribed) {
    if (const auto& mi = e.maximum_inscribed) {
      fill(result.mi, mi->center, mi->radius, mi->radius, mi->ron, mi->contacts);
      set_verification(result.mi, profile, *mi, run_verify);
    }
    set_outcome(result.mi, g::ReferenceCircle::maximum_inscribed, e);
  }
  if (request.minimum_circumscribed) {
    if (const auto& mc = e.minimum_circumscribed) {
      fill(result.mc, mc->center, mc->radius, mc->radius, mc->ron, mc->contacts);
      set_verification(result.mc, profile, *mc, run_verify);
    }
    set_outcome(result.mc, g::ReferenceCircle::minimum_circumscribed, e);
  }

  if (filtered_xy != nullptr) {
    for (std::size_t i = 0; i < profile.size(); ++i) {
      filtered_xy[2 * i] = profile[i].x;
      filtered_xy[2 * i + 1] = profile[i].y;
    }
  }
  return result.n_defined > 0 ? VCMM_OK : VCMM_ERROR_UNDEFINED;
}

}  // namespace

extern "C" {

const char* vcmm_version(void) { return VCMM_C_VERSION; }

const char* vcmm_status_string(vcmm_status status) {
  switch (status) {
    case VCMM_OK: return "ok";
    case VCMM_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case VCMM_ERROR_INVALID_INPUT: return "invalid input";
    case VCMM_ERROR_UNDEFINED: return "no requested circle is defined";
    case VCMM_ERROR_OUT_OF_MEMORY: return "out of memory";
    case VCMM_ERROR_INTERNAL: return "internal error";
  }
  return "unknown status";
}

void vcmm_roundness_options_init(vcmm_roundness_options* options) {
  if (options == nullptr) return;
  *options = vcmm_roundness_options{};
  options->struct_size = sizeof(vcmm_roundness_options);
  options->circles = VCMM_CIRCLE_ALL;
  options->filter_cutoff_upr = 0.0;
  options->verify = 1;
}

vcmm_status vcmm_roundness(const double* xy, size_t n, const vcmm_roundness_options* options,
                           vcmm_roundness_result* result, double* filtered_xy, char* error,
                           size_t error_size) {
  copy_text("", error, error_size);
  try {
    if (result == nullptr) throw BadArgument{"result is a null pointer"};
    if (result->struct_size != sizeof(vcmm_roundness_result))
      throw BadArgument{"result->struct_size is " + std::to_string(result->struct_size) +
                        ", expected sizeof(vcmm_roundness_result) = " +
                        std::to_string(sizeof(vcmm_roundness_result)) +
                        " (set it before the call; header and library must match)"};
    *result = vcmm_roundness_result{};
    result->struct_size = sizeof(vcmm_roundness_result);
    if (xy == nullptr && n > 0) throw BadArgument{"xy is a null pointer with n > 0"};
    if (n > (std::size_t{1} << 40)) throw BadArgument{"n is implausibly large"};
    vcmm_roundness_options defaults;
    vcmm_roundness_options_init(&defaults);
    if (options != nullptr && options->struct_size != sizeof(vcmm_roundness_options))
      throw BadArgument{"options->struct_size is " + std::to_string(options->struct_size) +
                        ", expected sizeof(vcmm_roundness_options) = " +
                        std::to_string(sizeof(vcmm_roundness_options)) +
                        " (initialise with vcmm_roundness_options_init)"};
    const vcmm_status s = evaluate(xy, n, options ? *options : defaults, *result, filtered_xy);
    if (s == VCMM_ERROR_UNDEFINED)
      copy_text("none of the requested reference circles is defined for these points (the "
                "reason of each is in the result)",
                error, error_size);
    return s;
  } catch (const BadArgument& e) {
    copy_text(e.message, error, error_size);
    return VCMM_ERROR_INVALID_ARGUMENT;
  } catch (const g::InvalidInput& e) {
    copy_text(e.what(), error, error_size);
    return VCMM_ERROR_INVALID_INPUT;
  } catch (const g::UndefinedResult& e) {
    copy_text(e.what(), error, error_size);
    return VCMM_ERROR_UNDEFINED;
  } catch (const std::bad_alloc&) {
    copy_text("out of memory", error, error_size);
    return VCMM_ERROR_OUT_OF_MEMORY;
  } catch (const std::exception& e) {
    copy_text(std::string("internal error (a bug in vcmm, please report it): ") + e.what(),
              error, error_size);
    return VCMM_ERROR_INTERNAL;
  } catch (...) {
    copy_text("internal error (a bug in vcmm, please report it): unknown exception", error,
              error_size);
    return VCMM_ERROR_INTERNAL;
  }
}

}  // extern "C"
