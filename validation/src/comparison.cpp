// comparison.cpp — E_n and zeta scores (vcmm/validation/comparison.h).
//
//   zeta = (x_ref − x_meas) / sqrt(u_ref² + u_meas²)          ISO 13528:2022, 9.6
//   E_n  = (x_ref − x_meas) / sqrt(U_ref² + U_meas²),  U = k·u  ISO 13528:2022, 9.7
// so E_n = zeta / k when both expanded uncertainties use the same k. The sign is reference −
// measured (the convention, opposite to ISO 13528's x_i − x_pt).
#include "vcmm/validation/comparison.h"

#include <cmath>
#include <sstream>
#include <string>

#include "vcmm/geometry/point.h"

namespace vcmm::validation {
namespace {

using geometry::InvalidInput;

std::string number_text(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

void require_finite(double v, const char* caller, const char* name) {
  if (!std::isfinite(v))
    throw InvalidInput(std::string(caller) + ": " + name + " must be finite; got " +
                       number_text(v));
}

void require_uncertainty(double u, const char* caller, const char* name) {
  require_finite(u, caller, name);
  if (u < 0.0)
    throw InvalidInput(std::string(caller) + ": " + name + " must be >= 0; got " +
                       number_text(u));
}

/// Checks the four inputs and returns sqrt(a² + b²) of the two uncertainties (> 0).
double combined(double x_ref, double u_ref, double x_meas, double u_meas, const char* caller,
                const char* u_ref_name, const char* u_meas_name) {
  require_finite(x_ref, caller, "x_ref");
  require_finite(x_meas, caller, "x_meas");
  require_uncertainty(u_ref, caller, u_ref_name);
  require_uncertainty(u_meas, caller, u_meas_name);
  if (u_ref == 0.0 && u_meas == 0.0)
    throw InvalidInput(std::string(caller) + ": " + u_ref_name + " and " + u_meas_name +
                       " are both 0; the score is undefined");
  return std::hypot(u_ref, u_meas);
}

/// A finite quotient of finite inputs can still overflow (differences near 1e308).
double finite_score(double score, const char* caller) {
  if (!std::isfinite(score))
    throw InvalidInput(std::string(caller) + ": the score overflows (" + number_text(score) +
                       "); inputs too large for double");
  return score;
}

void require_k(double k, const char* caller) {
  require_finite(k, caller, "k");
  if (!(k > 0.0))
    throw InvalidInput(std::string(caller) + ": coverage factor k must be > 0; got " +
                       number_text(k));
}

}  // namespace

double en_score(double x_ref, double u_ref, double x_meas, double u_meas, double k) {
  constexpr const char* kCaller = "en_score";
  require_k(k, kCaller);
  const double u = combined(x_ref, u_ref, x_meas, u_meas, kCaller, "u_ref", "u_meas");
  return finite_score((x_ref - x_meas) / (k * u), kCaller);
}

double en_score_expanded(double x_ref, double expanded_u_ref, double x_meas,
                         double expanded_u_meas) {
  constexpr const char* kCaller = "en_score_expanded";
  const double u = combined(x_ref, expanded_u_ref, x_meas, expanded_u_meas, kCaller,
                            "expanded_u_ref", "expanded_u_meas");
  return finite_score((x_ref - x_meas) / u, kCaller);
}

double zeta_score(double x_ref, double u_ref, double x_meas, double u_meas) {
  constexpr const char* kCaller = "zeta_score";
  const double u = combined(x_ref, u_ref, x_meas, u_meas, kCaller, "u_ref", "u_meas");
  return finite_score((x_ref - x_meas) / u, kCaller);
}

Comparison compare(double x_ref, double u_ref, double x_meas, double u_meas, double k) {
  constexpr const char* kCaller = "compare";
  require_k(k, kCaller);
  Comparison out;
  out.u_difference = combined(x_ref, u_ref, x_meas, u_meas, kCaller, "u_ref", "u_meas");
  out.difference = x_ref - x_meas;
  out.k = k;
  out.zeta = finite_score(out.difference / out.u_difference, kCaller);
  out.en = finite_score(out.difference / (k * out.u_difference), kCaller);
  return out;
}

}  // namespace vcmm::validation
