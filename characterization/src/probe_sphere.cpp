// Probe errors from a calibrated sphere: notation, model and derivation in
// vcmm/characterization/probe_sphere.h; the method and its limits in docs/characterization.md.
//
// Steps: (1) centre the data on their centroid (machine coordinates sit ~1000 mm from the
// origin; the fit works on differences of ~R); (2) algebraic sphere fit |q|² = 2 c·q + k,
// linear, for the start; (3) Gauss-Newton on θ = (c, δr, c_k, s_k) with the design matrix A
// (ρ ≈ ρ₀ − A Δθ), steps from the SVD pseudo-inverse so that a rank-deficient design still
// iterates on its identifiable part; (4) checks (on a sphere, identifiable, diameter close);
// (5) covariance and budgets from the SVD of A/√N.
#include "vcmm/characterization/probe_sphere.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "output_checks.h"
#include "vcmm/errormodel/errors.h"

namespace vcmm::characterization {
namespace {

using errormodel::InvalidInput;
constexpr const char* kCaller = "characterize_probe_sphere";
constexpr double kUmPerMm = 1e3;
constexpr int kMaxIterations = 50;

[[noreturn]] void fail(const std::string& what) {
  throw InvalidInput(std::string(kCaller) + ": " + what);
}

std::string number(double v) {
  std::ostringstream os;
  os.precision(6);
  os << v;
  return os.str();
}

/// Column names of θ for messages.
std::vector<std::string> parameter_names(const std::vector<int>& orders) {
  std::vector<std::string> names = {"centre_x", "centre_y", "centre_z", "tip_radius_error"};
  for (int k : orders) {
    names.push_back("cos_" + std::to_string(k));
    names.push_back("sin_" + std::to_string(k));
  }
  return names;
}

/// Residuals ρ and design matrix A at θ for centred points q (file comment of the header).
void evaluate(const Eigen::Matrix3Xd& q, double radius_cal, const Eigen::VectorXd& theta,
              const std::vector<int>& orders, Eigen::VectorXd& rho, Eigen::MatrixXd& a) {
  const Eigen::Index n = q.cols();
  const int max_order = orders.empty() ? 0 : orders.back();
  const Eigen::Vector3d c = theta.head<3>();
  rho.resize(n);
  a.resize(n, theta.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector3d v = q.col(i) - c;
    const double r = v.norm();
    const Eigen::Vector3d u = v / r;
    a(i, 0) = u.x();
    a(i, 1) = u.y();
    a(i, 2) = u.z();
    a(i, 3) = 1.0;
    double model = radius_cal + theta[3];
    // (d_x + i d_y)^k by complex multiplication, d = −u.
    const double dx = -u.x(), dy = -u.y();
    double re = 1.0, im = 0.0;
    std::size_t next = 0;
    for (int k = 1; k <= max_order; ++k) {
      const double next_re = re * dx - im * dy;
      im = re * dy + im * dx;
      re = next_re;
      if (next < orders.size() && orders[next] == k) {
        const Eigen::Index col = 4 + 2 * static_cast<Eigen::Index>(next);
        a(i, col) = re;
        a(i, col + 1) = im;
        model += theta[col] * re + theta[col + 1] * im;
        ++next;
      }
    }
    rho[i] = r - model;
  }
}

/// "0.71·cos_8 − 0.71·tip_radius_error": the terms of a right singular vector with |v| ≥ 0.1.
std::string combination(const Eigen::VectorXd& v, const std::vector<std::string>& names) {
  std::vector<Eigen::Index> idx;
  for (Eigen::Index j = 0; j < v.size(); ++j)
    if (std::abs(v[j]) >= 0.1) idx.push_back(j);
  std::sort(idx.begin(), idx.end(),
            [&](Eigen::Index x, Eigen::Index y) { return std::abs(v[x]) > std::abs(v[y]); });
  const double sign = v[idx.front()] < 0.0 ? -1.0 : 1.0;
  std::ostringstream os;
  os.precision(2);
  os << std::fixed;
  for (std::size_t t = 0; t < idx.size(); ++t) {
    const double c = sign * v[idx[t]];
    if (t > 0) os << (c < 0.0 ? " - " : " + ");
    os << (t == 0 ? c : std::abs(c)) << "*" << names[static_cast<std::size_t>(idx[t])];
  }
  return os.str();
}

void check_finite_non_negative(double v, const char* what) {
  if (!std::isfinite(v) || v < 0.0)
    fail(std::string(what) + " must be finite and >= 0; got " + number(v));
}

nlohmann::json uncertain_um(double value_mm, double u_mm) {
  return {{"value_um", value_mm * kUmPerMm}, {"uncertainty_um", u_mm * kUmPerMm}};
}

std::string orders_text(const std::vector<int>& orders) {
  std::string s;
  for (int k : orders) {
    if (!s.empty()) s += ',';
    s += std::to_string(k);
  }
  return s.empty() ? "none" : s;
}

nlohmann::json section(const SphereProbeCharacterization& r, std::string_view source) {
  if (!r.usable)
    throw InvalidInput("probe_section_json: the characterisation is not usable (" + r.message +
                       ")");
  std::ostringstream src;
  src.precision(6);
  src << source << (source.empty() ? "" : "; ")
      << "vcmm characterize sphere: least-squares fit of centre, tip radius error and "
         "directional orders "
      << orders_text(r.orders) << " to " << r.point_count
      << " points on a sphere D = " << r.sphere.diameter_mm << " mm (u "
      << r.sphere.diameter_u_mm * kUmPerMm << " um, form " << r.sphere.form_mm * kUmPerMm
      << " um); nu = " << r.degrees_of_freedom << ", s = " << r.residual_sigma_mm * kUmPerMm
      << " um";
  for (const NotIdentifiable& ni : r.not_identifiable) src << "; " << ni.what << ": " << ni.reason;
  nlohmann::json out;
  out["source"] = src.str();
  out["tip_radius_error"] =
      uncertain_um(r.probe.tip_radius_error_mm.value, r.probe.tip_radius_error_mm.u);
  out["directional_error"] = nlohmann::json::array();
  for (const errormodel::ProbeHarmonic& h : r.probe.directional)
    out["directional_error"].push_back({{"order", h.order},
                                        {"cos", uncertain_um(h.cos_mm.value, h.cos_mm.u)},
                                        {"sin", uncertain_um(h.sin_mm.value, h.sin_mm.u)}});
  return out;
}

nlohmann::json budget_json(const ProbeParameterEstimate& e) {
  return {{"name", e.name},
          {"value_um", e.value_mm * kUmPerMm},
          {"uncertainty_um", e.u_mm * kUmPerMm},
          {"u_statistical_um", e.u_statistical_mm * kUmPerMm},
          {"u_diameter_um", e.u_diameter_mm * kUmPerMm},
          {"u_form_um", e.u_form_mm * kUmPerMm}};
}

}  // namespace

std::string_view to_string(SphereFitStatus status) {
  switch (status) {
    case SphereFitStatus::ok:
      return "ok";
    case SphereFitStatus::rank_deficient:
      return "rank_deficient";
    case SphereFitStatus::not_converged:
      return "not_converged";
  }
  return "?";
}

SphereProbeCharacterization characterize_probe_sphere(const Eigen::Matrix3Xd& points_mm,
                                                      const CalibratedSphere& sphere,
                                                      const SphereProbeOptions& options) {
  // ---- preconditions ----
  if (!std::isfinite(sphere.diameter_mm) || sphere.diameter_mm <= 0.0)
    fail("the calibrated diameter must be finite and > 0; got " + number(sphere.diameter_mm) +
         " mm");
  check_finite_non_negative(sphere.diameter_u_mm, "the diameter's standard uncertainty (mm)");
  check_finite_non_negative(sphere.form_mm, "the sphere's form deviation (mm)");
  if (!(sphere.diameter_u_mm <= 0.01 * sphere.diameter_mm))
    fail("the diameter's standard uncertainty " + number(sphere.diameter_u_mm) +
         " mm exceeds 1 % of the diameter (a calibrated sphere's is a fraction of a um)");
  if (!(sphere.form_mm <= 0.01 * sphere.diameter_mm))
    fail("the sphere's form deviation " + number(sphere.form_mm) +
         " mm exceeds 1 % of the diameter (a calibrated sphere's is a fraction of a um)");
  if (options.probing_sigma_mm &&
      !(*options.probing_sigma_mm > 0.0 && *options.probing_sigma_mm <= 0.005 * sphere.diameter_mm))
    fail("the probing sigma must be > 0 and at most 1 % of the radius; got " +
         number(*options.probing_sigma_mm) + " mm");
  for (Eigen::Index i = 0; i < points_mm.cols(); ++i)
    for (int j = 0; j < 3; ++j)
      if (!std::isfinite(points_mm(j, i)))
        fail("point " + std::to_string(i) + " has a non-finite coordinate (" + "xyz"[j] + " = " +
             number(points_mm(j, i)) + ")");
  SphereProbeCharacterization out;
  out.sphere = sphere;
  for (int k : options.orders) {
    if (k < 1 || k > errormodel::max_probe_harmonic_order)
      fail("harmonic orders must be 1 to " + std::to_string(errormodel::max_probe_harmonic_order) +
           "; got " + std::to_string(k));
    if (k == 1) continue;
    if (std::find(out.orders.begin(), out.orders.end(), k) == out.orders.end())
      out.orders.push_back(k);
  }
  std::sort(out.orders.begin(), out.orders.end());
  if (std::find(options.orders.begin(), options.orders.end(), 1) != options.orders.end())
    out.not_identifiable.push_back(
        {"order 1",
         "not identifiable: Re/Im of (dx + i dy) are the sphere centre's own columns "
         "(a first-order directional error is a shift of every feature); no value "
         "is given"});
  const Eigen::Index p = 4 + 2 * static_cast<Eigen::Index>(out.orders.size());
  const Eigen::Index n = points_mm.cols();
  out.point_count = n;
  if (n < p + 3)
    fail("needs at least " + std::to_string(p + 3) + " points for " + std::to_string(p) +
         " parameters (centre, tip radius error, orders " + orders_text(out.orders) +
         ") and nu >= 3 degrees of freedom; got " + std::to_string(n));

  // ---- (1) centre the data, (2) algebraic start ----
  const Eigen::Vector3d centroid = points_mm.rowwise().mean();
  const Eigen::Matrix3Xd q = points_mm.colwise() - centroid;
  const double radius_cal = 0.5 * sphere.diameter_mm;
  Eigen::MatrixXd alg(n, 4);
  Eigen::VectorXd rhs(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    alg.row(i) << 2.0 * q(0, i), 2.0 * q(1, i), 2.0 * q(2, i), 1.0;
    rhs[i] = q.col(i).squaredNorm();
  }
  if (!alg.allFinite() || !rhs.allFinite())
    fail("the coordinates are too large to square in double precision (|x| above ~1e150)");
  Eigen::JacobiSVD<Eigen::MatrixXd> alg_svd(alg, Eigen::ComputeThinU | Eigen::ComputeThinV);
  alg_svd.setThreshold(1e-12);
  const Eigen::Vector4d start = alg_svd.solve(rhs);
  const double r2 = start[3] + start.head<3>().squaredNorm();
  if (!(r2 > 0.0) || !std::isfinite(r2))
    fail("the points do not lie on a sphere (the algebraic fit has no real radius)");

  // ---- (3) Gauss-Newton ----
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(p);
  theta.head<3>() = start.head<3>();
  theta[3] = std::sqrt(r2) - radius_cal;
  Eigen::VectorXd rho;
  Eigen::MatrixXd a;
  bool converged = false;
  // Converged when the step is below 1e-11 R (0.1 pm on a 25 mm sphere): the iteration
  // contracts by ~1e-5 per step (the neglected basis derivative), so this is reached in ≤ 5.
  const double tolerance = 1e-11 * radius_cal;
  // A point at the current centre (or a diverging iterate) makes ρ or A non-finite: such
  // data are no sphere, and an SVD of non-finite numbers must not be attempted.
  auto require_finite = [&] {
    if (!rho.allFinite() || !a.allFinite())
      fail("the points do not lie on a sphere (the fit reached a non-finite residual)");
  };
  for (int it = 0; it < kMaxIterations && !converged; ++it) {
    evaluate(q, radius_cal, theta, out.orders, rho, a);
    require_finite();
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
    svd.setThreshold(1e-12);
    const Eigen::VectorXd step = svd.solve(rho);
    theta += step;
    out.iterations = it + 1;
    converged = step.lpNorm<Eigen::Infinity>() <= tolerance;
  }
  evaluate(q, radius_cal, theta, out.orders, rho, a);
  require_finite();

  // ---- (4) checks ----
  Eigen::Index worst = 0;
  const double max_residual = rho.cwiseAbs().maxCoeff(&worst);
  if (!(max_residual <= 0.01 * radius_cal))
    fail("the points do not lie on a sphere: residual of point " + std::to_string(worst) + " is " +
         number(rho[worst]) + " mm, more than 1 % of the calibrated radius " + number(radius_cal) +
         " mm");
  out.residuals_mm.assign(rho.data(), rho.data() + rho.size());
  out.residual_range_mm = rho.maxCoeff() - rho.minCoeff();
  out.center_mm = centroid + theta.head<3>();
  out.iterations = std::max(out.iterations, 1);

  const double root_n = std::sqrt(static_cast<double>(n));
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(a / root_n, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd& sv = svd.singularValues();
  out.min_singular_value = sv[sv.size() - 1];
  out.degrees_of_freedom = static_cast<int>(n - p);
  const std::vector<std::string> names = parameter_names(out.orders);
  if (out.min_singular_value < kMinSingularValue) {
    out.status = SphereFitStatus::rank_deficient;
    std::string list;
    for (Eigen::Index j = 0; j < sv.size(); ++j) {
      if (sv[j] >= kMinSingularValue) continue;
      const std::string what = combination(svd.matrixV().col(j), names);
      out.not_identifiable.push_back(
          {what, "not identifiable with this point distribution (singular value " + number(sv[j]) +
                     " of A/sqrt(N) < " + number(kMinSingularValue) + ")"});
      if (!list.empty()) list += "; ";
      list += what;
    }
    out.message = "rank-deficient design: not identifiable from these points: " + list +
                  " (drop the orders involved or probe more points / more circles)";
    return out;
  }
  const double diameter = 2.0 * (radius_cal + theta[3]);
  if (!(std::abs(diameter - sphere.diameter_mm) <= 0.01 * sphere.diameter_mm))
    fail("the fitted diameter " + number(diameter) + " mm differs from the calibrated " +
         number(sphere.diameter_mm) + " mm by more than 1 % (wrong sphere or units?)");
  if (!converged) {
    out.status = SphereFitStatus::not_converged;
    out.message =
        "Gauss-Newton did not converge in " + std::to_string(kMaxIterations) + " iterations";
    return out;
  }
  out.diameter_mm = diameter;

  // ---- (5) uncertainties ----
  const int nu = out.degrees_of_freedom;
  const double s = std::sqrt(rho.squaredNorm() / nu);
  out.residual_sigma_mm = s;
  out.t_factor = std::sqrt(static_cast<double>(nu) / static_cast<double>(nu - 2));
  // A/√N = U S Vᵀ: (AᵀA)⁻¹ = V S⁻² Vᵀ / N, pseudo-inverse (AᵀA)⁻¹Aᵀ = V S⁻¹ Uᵀ / √N.
  const Eigen::VectorXd inv_s = sv.cwiseInverse();
  const Eigen::MatrixXd vs = svd.matrixV() * inv_s.asDiagonal();
  const Eigen::MatrixXd pinv = vs * svd.matrixU().transpose() / root_n;  // p × N
  auto estimate = [&](Eigen::Index j, const std::string& name) {
    ProbeParameterEstimate e;
    e.name = name;
    e.value_mm = theta[j];
    e.u_statistical_mm = out.t_factor * s * vs.row(j).norm() / root_n;
    e.u_form_mm = 0.5 * sphere.form_mm * pinv.row(j).lpNorm<1>() / std::sqrt(3.0);
    e.u_diameter_mm = j == 3 ? 0.5 * sphere.diameter_u_mm : 0.0;
    e.u_mm = std::sqrt(e.u_statistical_mm * e.u_statistical_mm + e.u_form_mm * e.u_form_mm +
                       e.u_diameter_mm * e.u_diameter_mm);
    return e;
  };
  out.tip_radius_error = estimate(3, "tip_radius_error");
  out.probe.tip_radius_error_mm = {out.tip_radius_error.value_mm, out.tip_radius_error.u_mm};
  for (std::size_t t = 0; t < out.orders.size(); ++t) {
    const Eigen::Index col = 4 + 2 * static_cast<Eigen::Index>(t);
    const ProbeParameterEstimate c = estimate(col, names[static_cast<std::size_t>(col)]);
    const ProbeParameterEstimate sn = estimate(col + 1, names[static_cast<std::size_t>(col) + 1]);
    out.directional.push_back(c);
    out.directional.push_back(sn);
    errormodel::ProbeHarmonic h;
    h.order = out.orders[t];
    h.cos_mm = {c.value_mm, c.u_mm};
    h.sin_mm = {sn.value_mm, sn.u_mm};
    out.probe.directional.push_back(h);
  }
  // ---- (6) consistency of the residuals with the stated noise and form ----
  {
    const Eigen::VectorXd h = svd.matrixU().rowwise().squaredNorm();
    const double u = options.probing_sigma_mm
                         ? std::sqrt(*options.probing_sigma_mm * *options.probing_sigma_mm +
                                     sphere.form_mm * sphere.form_mm / 12.0)
                         : 1.0;  // a common factor only: the studentized test
    std::vector<FitResidual> res(static_cast<std::size_t>(n));
    for (Eigen::Index i = 0; i < n; ++i) {
      FitResidual& f = res[static_cast<std::size_t>(i)];
      f.value = rho[i];
      f.uncertainty = u;
      f.leverage = h[i];
      std::ostringstream where;
      where.precision(10);
      where << "point " << i + 1 << " (" << points_mm(0, i) << ", " << points_mm(1, i) << ", "
            << points_mm(2, i) << ")";
      f.where = where.str();
    }
    out.consistency = test_consistency(res, nu, options.probing_sigma_mm.has_value());
  }
  out.usable = true;
  std::ostringstream msg;
  msg.precision(4);
  msg << "tip radius error " << out.tip_radius_error.value_mm * kUmPerMm << " um (u "
      << out.tip_radius_error.u_mm * kUmPerMm << " um), orders " << orders_text(out.orders)
      << ", nu = " << nu << ", s = " << s * kUmPerMm << " um";
  out.message = msg.str();
  return out;
}

std::string probe_section_json(const SphereProbeCharacterization& result, std::string_view source) {
  const nlohmann::json sec = section(result, source);
  internal::require_finite_numbers(sec, source, "probe");
  return sec.dump(2);
}

std::string probe_characterization_json(const SphereProbeCharacterization& r,
                                        std::string_view source, bool accepted_inconsistent) {
  nlohmann::json out;
  out["probe"] = section(r, source);
  nlohmann::json c;
  c["method"] = "least-squares sphere fit with directional terms (docs/characterization.md)";
  c["status"] = std::string(to_string(r.status));
  c["points"] = r.point_count;
  c["sphere"] = {{"diameter_mm", r.sphere.diameter_mm},
                 {"diameter_uncertainty_um", r.sphere.diameter_u_mm * kUmPerMm},
                 {"form_um", r.sphere.form_mm * kUmPerMm}};
  c["center_mm"] = {r.center_mm.x(), r.center_mm.y(), r.center_mm.z()};
  c["measured_diameter_mm"] = r.diameter_mm;
  c["degrees_of_freedom"] = r.degrees_of_freedom;
  c["residual_sigma_um"] = r.residual_sigma_mm * kUmPerMm;
  c["t_factor"] = r.t_factor;
  c["residual_range_um"] = r.residual_range_mm * kUmPerMm;
  c["min_singular_value"] = r.min_singular_value;
  c["iterations"] = r.iterations;
  nlohmann::json budget = nlohmann::json::array();
  budget.push_back(budget_json(r.tip_radius_error));
  for (const ProbeParameterEstimate& e : r.directional) budget.push_back(budget_json(e));
  c["budget"] = budget;
  nlohmann::json ni = nlohmann::json::array();
  for (const NotIdentifiable& x : r.not_identifiable)
    ni.push_back({{"what", x.what}, {"reason", x.reason}});
  c["not_identifiable"] = ni;
  c["consistency"] = internal::consistency_json<nlohmann::json>(r.consistency, accepted_inconsistent);
  out["characterization"] = c;
  internal::require_finite_numbers(out, source);
  return out.dump(2) + "\n";
}

// ---- plans and simulated data ----

Eigen::Matrix3Xd sphere_directions(std::span<const SphereCircle> circles) {
  Eigen::Index n = 0;
  for (std::size_t c = 0; c < circles.size(); ++c) {
    const SphereCircle& s = circles[c];
    if (!std::isfinite(s.polar_angle_rad) || !std::isfinite(s.azimuth_offset_rad))
      throw InvalidInput("sphere_directions: circle " + std::to_string(c) +
                         " has a non-finite angle");
    if (s.points < 1)
      throw InvalidInput("sphere_directions: circle " + std::to_string(c) +
                         " needs at least 1 point; got " + std::to_string(s.points));
    n += s.points;
  }
  Eigen::Matrix3Xd out(3, n);
  Eigen::Index i = 0;
  for (const SphereCircle& s : circles) {
    for (int j = 0; j < s.points; ++j, ++i) {
      const double phi = s.azimuth_offset_rad + 2.0 * std::numbers::pi * j / s.points;
      out.col(i) << std::sin(s.polar_angle_rad) * std::cos(phi),
          std::sin(s.polar_angle_rad) * std::sin(phi), std::cos(s.polar_angle_rad);
    }
  }
  return out;
}

Eigen::Matrix3Xd iso10360_5_directions() {
  constexpr double deg = std::numbers::pi / 180.0;
  const SphereCircle circles[] = {{0.0, 1, 0.0},
                                  {22.5 * deg, 4, 0.0},
                                  {45.0 * deg, 8, 22.5 * deg},
                                  {67.5 * deg, 4, 45.0 * deg},
                                  {90.0 * deg, 8, 67.5 * deg}};
  return sphere_directions(circles);
}

Eigen::Matrix3Xd dense_hemisphere_directions() {
  constexpr double deg = std::numbers::pi / 180.0;
  const SphereCircle circles[] = {
      {0.0, 1, 0.0}, {30.0 * deg, 24, 0.0}, {60.0 * deg, 24, 7.5 * deg}, {90.0 * deg, 24, 0.0}};
  return sphere_directions(circles);
}

errormodel::Measurement sphere_measurement(double diameter_mm, const Eigen::Matrix3Xd& directions,
                                           const errormodel::Placement& placement,
                                           errormodel::ProbingMode mode) {
  if (!std::isfinite(diameter_mm) || diameter_mm <= 0.0)
    throw InvalidInput("sphere_measurement: the diameter must be finite and > 0; got " +
                       number(diameter_mm));
  for (Eigen::Index i = 0; i < directions.cols(); ++i)
    if (!(std::abs(directions.col(i).norm() - 1.0) <= 1e-9))
      throw InvalidInput("sphere_measurement: direction " + std::to_string(i) +
                         " is not a unit vector (|u| = " + number(directions.col(i).norm()) + ")");
  errormodel::Measurement m;
  m.points_mm = 0.5 * diameter_mm * directions;
  m.normals = directions;
  m.placement = placement;
  m.mode = mode;
  errormodel::validate_measurement(m, "sphere_measurement");
  return m;
}

}  // namespace vcmm::characterization
