// python/src/geometry_bindings.cpp — the extension vcmm._vcmm: the module, the exception
// mapping, the numpy ↔ point conversions and the geometry bindings (reference circles, their
// certificates and verify, the roundness evaluation, the Gaussian filter, harmonics, the claim
// check). Conversions and forwarding only; docs/python.md documents the Python API and
// python/vcmm/__init__.py is the façade users import.
//
// Threads: every library call runs with the GIL released (inputs are converted to C++ first,
// results converted back after), so other Python threads run meanwhile.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cctype>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "vcmm/errormodel/errors.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/claim_check.h"
#include "vcmm/geometry/gaussian_filter.h"
#include "vcmm/geometry/least_squares.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"
#include "vcmm/geometry/profile_harmonics.h"
#include "vcmm/geometry/roundness.h"
#include "vcmm/uncertainty/errors.h"

namespace vcmm::python {

namespace g = vcmm::geometry;
using namespace pybind11::literals;

namespace {

std::string shape_text(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i)
    s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

}  // namespace

std::vector<g::Point2> points_from_array(const py::handle& object, const char* what,
                                         std::vector<double>& z) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  Array a;
  try {
    a = Array::ensure(object);
  } catch (const py::error_already_set&) {
  }
  if (!a)
    throw g::InvalidInput(std::string(what) +
                          ": expected an (n, 2) or (n, 3) array of x, y[, z] in mm; got an "
                          "object of type " +
                          std::string(py::str(py::type::handle_of(object).attr("__name__"))));
  std::vector<g::Point2> points;
  z.clear();
  if (a.size() == 0) return points;  // the library names the rule (too few points)
  if (a.ndim() != 2 || (a.shape(1) != 2 && a.shape(1) != 3))
    throw g::InvalidInput(std::string(what) +
                          ": expected an (n, 2) or (n, 3) array of x, y[, z] in mm; got shape " +
                          shape_text(a));
  const auto n = static_cast<std::size_t>(a.shape(0));
  const auto columns = static_cast<std::size_t>(a.shape(1));
  const double* data = a.data();
  points.resize(n);
  z.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    points[i] = {data[i * columns], data[i * columns + 1]};
    if (columns == 3) z[i] = data[i * columns + 2];
  }
  return points;
}

std::vector<g::Point2> points_from_array(const py::handle& object, const char* what) {
  std::vector<double> z;
  return points_from_array(object, what, z);
}

py::array_t<double> points_to_array(std::span<const g::Point2> points) {
  py::array_t<double> out({static_cast<py::ssize_t>(points.size()), py::ssize_t{2}});
  auto view = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < points.size(); ++i) {
    view(static_cast<py::ssize_t>(i), 0) = points[i].x;
    view(static_cast<py::ssize_t>(i), 1) = points[i].y;
  }
  return out;
}

namespace {

py::array_t<double> vector_to_array(std::span<const double> values) {
  py::array_t<double> out(static_cast<py::ssize_t>(values.size()));
  std::copy(values.begin(), values.end(), out.mutable_data());
  return out;
}

std::pair<double, double> pair_of(g::Point2 p) { return {p.x, p.y}; }

std::string optimality_text(g::Optimality o) {
  return o == g::Optimality::global ? "global" : "local";
}

std::string filter_path_text(g::FilterPath path) {
  switch (path) {
    case g::FilterPath::fft: return "fft";
    case g::FilterPath::nonuniform: return "nonuniform";
    case g::FilterPath::open_profile: return "open_profile";
  }
  return "?";
}

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

g::ReferenceCircle reference_of(const std::string& name, const char* what) {
  if (const auto r = g::reference_circle_from_string(upper(name))) return *r;
  throw g::InvalidInput(std::string(what) + ": reference circle must be LS, MZ, MI or MC; got '" +
                        name + "'");
}

/// center and the four RON parameters of any circle type.
template <class Circle, class PyClass>
void add_common(PyClass& c) {
  c.def_property_readonly("center", [](const Circle& x) { return pair_of(x.center); },
                          "centre (x, y) in mm")
      .def_property_readonly("ront", [](const Circle& x) { return x.ron.ront; },
                             "RONt, peak-to-valley about the circle (mm)")
      .def_property_readonly("ronp", [](const Circle& x) { return x.ron.ronp; },
                             "RONp, peak-to-reference (mm)")
      .def_property_readonly("ronv", [](const Circle& x) { return x.ron.ronv; },
                             "RONv, reference-to-valley depth (mm)")
      .def_property_readonly("ronq", [](const Circle& x) { return x.ron.ronq; },
                             "RONq, root mean square deviation (mm)");
}

template <class Circle, class PyClass>
void add_certificate(PyClass& c) {
  c.def_readonly("certificate", &Circle::certificate, "the proof attached to the result")
      .def_property_readonly(
          "optimality", [](const Circle& x) { return optimality_text(x.certificate.optimality); },
          "'global' or 'local': how far optimality is proven");
}

std::string circle_repr(const char* kind, g::Point2 c, double radius, double ront) {
  return "<vcmm." + std::string(kind) + " center=(" + py::str(py::float_(c.x)).cast<std::string>() +
         ", " + py::str(py::float_(c.y)).cast<std::string>() + ") radius=" +
         py::str(py::float_(radius)).cast<std::string>() +
         " ront=" + py::str(py::float_(ront)).cast<std::string>() + ">";
}

/// The input and the evaluation of one roundness call (certificates refer to the profile:
/// the filtered points when filtered, else the input).
struct Evaluated {
  std::vector<g::Point2> points;
  g::RoundnessEvaluation evaluation;
  std::span<const g::Point2> profile() const {
    return evaluation.filtered_points.empty()
               ? std::span<const g::Point2>(points)
               : std::span<const g::Point2>(evaluation.filtered_points);
  }
};

template <class F>
auto without_gil(F&& f) {
  py::gil_scoped_release release;
  return f();
}

// The Python exception types, made once by register_exceptions and kept for the interpreter's
// lifetime (a translator is a plain function: it cannot capture them).
py::exception<g::InvalidInput>* invalid_input_type = nullptr;
py::exception<g::UndefinedResult>* undefined_result_type = nullptr;
py::exception<errormodel::InvalidParameter>* invalid_parameter_type = nullptr;

void register_exceptions(py::module_& m) {
  invalid_input_type = new py::exception<g::InvalidInput>(m, "InvalidInput", PyExc_ValueError);
  undefined_result_type =
      new py::exception<g::UndefinedResult>(m, "UndefinedResult", PyExc_ValueError);
  invalid_parameter_type = new py::exception<errormodel::InvalidParameter>(
      m, "InvalidParameter", invalid_input_type->ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const errormodel::InvalidParameter& e) {
      auto type = py::reinterpret_borrow<py::object>(invalid_parameter_type->ptr());
      py::object instance = type(e.what());
      instance.attr("key_path") = e.key_path();
      PyErr_SetObject(type.ptr(), instance.ptr());
    } catch (const g::InvalidInput& e) {
      (*invalid_input_type)(e.what());
    } catch (const uncertainty::InvalidInput& e) {
      (*invalid_input_type)(e.what());
    } catch (const g::UndefinedResult& e) {
      (*undefined_result_type)(e.what());
    }
  });
}

void bind_circles(py::module_& m) {
  py::class_<g::Certificate>(m, "Certificate",
                             "What a reference circle's result proves about itself.")
      .def_property_readonly("optimality",
                             [](const g::Certificate& c) { return optimality_text(c.optimality); },
                             "'global' or 'local'")
      .def_readonly("argument", &g::Certificate::argument, "plain-language proof")
      .def_readonly("region_radius", &g::Certificate::region_radius,
                    "region arguments: any better centre lies within this distance (mm); 0 "
                    "otherwise")
      .def("__repr__", [](const g::Certificate& c) {
        return "<vcmm.Certificate " + optimality_text(c.optimality) + ": " + c.argument + ">";
      });

  py::class_<g::Verification>(m, "Verification", "Outcome of an independent exact check.")
      .def_readonly("valid", &g::Verification::valid)
      .def_readonly("reason", &g::Verification::reason, "empty when valid")
      .def("__bool__", [](const g::Verification& v) { return v.valid; })
      .def("__repr__", [](const g::Verification& v) {
        return v.valid ? std::string("<vcmm.Verification valid>")
                       : "<vcmm.Verification invalid: " + v.reason + ">";
      });

  py::class_<g::LeastSquaresCircle> ls(m, "LeastSquaresCircle",
                                       "The least-squares (LSCI) reference circle.");
  add_common<g::LeastSquaresCircle>(ls);
  ls.def_readonly("radius", &g::LeastSquaresCircle::radius, "mm")
      .def_readonly("contacts", &g::LeastSquaresCircle::contacts,
                    "[index of the highest peak, index of the deepest valley]")
      .def_readonly("iterations", &g::LeastSquaresCircle::iterations,
                    "Gauss-Newton iterations used")
      .def_property_readonly("optimality", [](const g::LeastSquaresCircle&) { return "numerical"; })
      .def("__repr__", [](const g::LeastSquaresCircle& c) {
        return circle_repr("LeastSquaresCircle", c.center, c.radius, c.ron.ront);
      });

  py::class_<g::MinimumZoneCircle> mz(m, "MinimumZoneCircle",
                                      "The minimum-zone (MZCI) reference circles.");
  add_common<g::MinimumZoneCircle>(mz);
  add_certificate<g::MinimumZoneCircle>(mz);
  mz.def_readonly("inner_radius", &g::MinimumZoneCircle::inner_radius, "r (mm)")
      .def_readonly("outer_radius", &g::MinimumZoneCircle::outer_radius, "R (mm)")
      .def_property_readonly(
          "radius", [](const g::MinimumZoneCircle& c) { return 0.5 * (c.inner_radius + c.outer_radius); },
          "mean radius (R + r)/2 (mm)")
      .def_readonly("outer_contacts", &g::MinimumZoneCircle::outer_contacts)
      .def_readonly("inner_contacts", &g::MinimumZoneCircle::inner_contacts)
      .def_property_readonly(
          "contacts",
          [](const g::MinimumZoneCircle& c) {
            std::vector<std::size_t> all = c.outer_contacts;
            all.insert(all.end(), c.inner_contacts.begin(), c.inner_contacts.end());
            return all;
          },
          "outer contacts then inner contacts")
      .def("__repr__", [](const g::MinimumZoneCircle& c) {
        return circle_repr("MinimumZoneCircle", c.center, 0.5 * (c.inner_radius + c.outer_radius),
                           c.ron.ront);
      });

  py::class_<g::MaximumInscribedCircle> mi(m, "MaximumInscribedCircle",
                                           "The maximum-inscribed (MICI) reference circle.");
  add_common<g::MaximumInscribedCircle>(mi);
  add_certificate<g::MaximumInscribedCircle>(mi);
  mi.def_readonly("radius", &g::MaximumInscribedCircle::radius, "mm")
      .def_readonly("contacts", &g::MaximumInscribedCircle::contacts)
      .def("__repr__", [](const g::MaximumInscribedCircle& c) {
        return circle_repr("MaximumInscribedCircle", c.center, c.radius, c.ron.ront);
      });

  py::class_<g::MinimumCircumscribedCircle> mc(
      m, "MinimumCircumscribedCircle", "The minimum-circumscribed (MCCI) reference circle.");
  add_common<g::MinimumCircumscribedCircle>(mc);
  add_certificate<g::MinimumCircumscribedCircle>(mc);
  mc.def_readonly("radius", &g::MinimumCircumscribedCircle::radius, "mm")
      .def_readonly("contacts", &g::MinimumCircumscribedCircle::contacts)
      .def("__repr__", [](const g::MinimumCircumscribedCircle& c) {
        return circle_repr("MinimumCircumscribedCircle", c.center, c.radius, c.ron.ront);
      });

  m.def("least_squares_circle", [](const py::handle& points) {
    const auto p = points_from_array(points, "least_squares_circle");
    return without_gil([&] { return g::least_squares_circle(p); });
  }, "points"_a);
  m.def(
      "minimum_zone_circle",
      [](const py::handle& points, const std::string& method, bool prove_global) {
        const auto p = points_from_array(points, "minimum_zone_circle");
        g::MinimumZoneOptions o;
        o.prove_global = prove_global;
        if (method == "automatic") o.method = g::MinimumZoneMethod::automatic;
        else if (method == "exchange") o.method = g::MinimumZoneMethod::exchange;
        else if (method == "overlay") o.method = g::MinimumZoneMethod::overlay;
        else
          throw g::InvalidInput("minimum_zone_circle: method must be automatic, exchange or "
                                "overlay; got '" + method + "'");
        return without_gil([&] { return g::minimum_zone_circle(p, o); });
      },
      "points"_a, "method"_a = "automatic", "prove_global"_a = true);
  m.def("maximum_inscribed_circle", [](const py::handle& points) {
    const auto p = points_from_array(points, "maximum_inscribed_circle");
    return without_gil([&] { return g::maximum_inscribed_circle(p); });
  }, "points"_a);
  m.def("minimum_circumscribed_circle", [](const py::handle& points) {
    const auto p = points_from_array(points, "minimum_circumscribed_circle");
    return without_gil([&] { return g::minimum_circumscribed_circle(p); });
  }, "points"_a);

  m.def("verify", [](const py::handle& points, const g::MinimumZoneCircle& c) {
    const auto p = points_from_array(points, "verify");
    return without_gil([&] { return g::verify(p, c); });
  }, "points"_a, "circle"_a);
  m.def("verify", [](const py::handle& points, const g::MaximumInscribedCircle& c) {
    const auto p = points_from_array(points, "verify");
    return without_gil([&] { return g::verify(p, c); });
  }, "points"_a, "circle"_a);
  m.def("verify", [](const py::handle& points, const g::MinimumCircumscribedCircle& c) {
    const auto p = points_from_array(points, "verify");
    return without_gil([&] { return g::verify(p, c); });
  }, "points"_a, "circle"_a);
}

void bind_roundness(py::module_& m) {
  py::class_<g::AngularCoverage>(m, "AngularCoverage",
                                 "Angular coverage of a profile about a centre.")
      .def_readonly("covered_rad", &g::AngularCoverage::covered_rad)
      .def_readonly("largest_gap_rad", &g::AngularCoverage::largest_gap_rad)
      .def_readonly("gap_start_rad", &g::AngularCoverage::gap_start_rad)
      .def_readonly("gap_start_index", &g::AngularCoverage::gap_start_index)
      .def_readonly("gap_end_index", &g::AngularCoverage::gap_end_index)
      .def_readonly("closed", &g::AngularCoverage::closed);

  py::class_<Evaluated>(m, "RoundnessEvaluation")
      .def_property_readonly("n_points", [](const Evaluated& e) { return e.evaluation.n_points; })
      .def_property_readonly("filter_upr",
                             [](const Evaluated& e) { return e.evaluation.filter_cutoff_upr; })
      .def_property_readonly("filter_path",
                             [](const Evaluated& e) -> std::optional<std::string> {
                               if (!e.evaluation.filter_path) return std::nullopt;
                               return filter_path_text(*e.evaluation.filter_path);
                             })
      .def_property_readonly("profile",
                             [](const Evaluated& e) { return points_to_array(e.profile()); })
      .def_property_readonly("coverage", [](const Evaluated& e) { return e.evaluation.coverage; })
      .def_property_readonly("least_squares",
                             [](const Evaluated& e) { return e.evaluation.least_squares; })
      .def_property_readonly("minimum_zone",
                             [](const Evaluated& e) { return e.evaluation.minimum_zone; })
      .def_property_readonly("maximum_inscribed",
                             [](const Evaluated& e) { return e.evaluation.maximum_inscribed; })
      .def_property_readonly("minimum_circumscribed",
                             [](const Evaluated& e) { return e.evaluation.minimum_circumscribed; })
      .def_property_readonly("undefined",
                             [](const Evaluated& e) {
                               py::dict d;
                               for (const auto& [c, reason] : e.evaluation.undefined)
                                 d[py::str(std::string(g::to_string(c)))] = reason;
                               return d;
                             })
      .def_property_readonly("cautions",
                             [](const Evaluated& e) {
                               py::dict d;
                               for (const auto& [c, text] : e.evaluation.cautions)
                                 d[py::str(std::string(g::to_string(c)))] = text;
                               return d;
                             })
      .def("verify", [](const Evaluated& e, const std::string& name) -> std::optional<g::Verification> {
        const g::RoundnessEvaluation& ev = e.evaluation;
        py::gil_scoped_release release;
        switch (reference_of(name, "verify")) {
          case g::ReferenceCircle::minimum_zone:
            if (ev.minimum_zone) return g::verify(e.profile(), *ev.minimum_zone);
            break;
          case g::ReferenceCircle::maximum_inscribed:
            if (ev.maximum_inscribed) return g::verify(e.profile(), *ev.maximum_inscribed);
            break;
          case g::ReferenceCircle::minimum_circumscribed:
            if (ev.minimum_circumscribed) return g::verify(e.profile(), *ev.minimum_circumscribed);
            break;
          case g::ReferenceCircle::least_squares:
            break;
        }
        return std::nullopt;
      }, "circle"_a, "the independent exact check of a circle's certificate on the evaluated "
                     "profile; None for LS (no certificate) and circles not evaluated");

  m.def(
      "evaluate_roundness",
      [](const py::handle& points, std::optional<double> filter_upr,
         const std::vector<std::string>& circles) {
        Evaluated e;
        e.points = points_from_array(points, "roundness");
        g::RoundnessRequest request;
        request.least_squares = request.minimum_zone = request.maximum_inscribed =
            request.minimum_circumscribed = false;
        for (const std::string& name : circles) {
          switch (reference_of(name, "roundness")) {
            case g::ReferenceCircle::least_squares: request.least_squares = true; break;
            case g::ReferenceCircle::minimum_zone: request.minimum_zone = true; break;
            case g::ReferenceCircle::maximum_inscribed: request.maximum_inscribed = true; break;
            case g::ReferenceCircle::minimum_circumscribed:
              request.minimum_circumscribed = true;
              break;
          }
        }
        request.filter_cutoff_upr = filter_upr;
        e.evaluation = without_gil([&] { return g::evaluate_roundness(e.points, request); });
        return e;
      },
      "points"_a, "filter_upr"_a = py::none(),
      "circles"_a = std::vector<std::string>{"LS", "MZ", "MI", "MC"});
}

void bind_filter_harmonics_claims(py::module_& m) {
  py::class_<g::FilteredProfile>(m, "FilteredProfile", "An ISO 16610-21 filtered profile.")
      .def_property_readonly("points",
                             [](const g::FilteredProfile& f) { return points_to_array(f.points); },
                             "(n, 2) filtered points, input order (mm)")
      .def_property_readonly("filter_center",
                             [](const g::FilteredProfile& f) { return pair_of(f.filter_center); })
      .def_readonly("mean_radius", &g::FilteredProfile::mean_radius)
      .def_property_readonly("path",
                             [](const g::FilteredProfile& f) { return filter_path_text(f.path); });

  m.def(
      "gaussian_filter",
      [](const py::handle& points, double cutoff_upr, const std::string& profile,
         const std::string& path) {
        const auto p = points_from_array(points, "gaussian_filter");
        if (profile != "closed" && profile != "open")
          throw g::InvalidInput("gaussian_filter: profile must be 'closed' or 'open'; got '" +
                                profile + "'");
        if (path != "automatic" && path != "nonuniform")
          throw g::InvalidInput(
              "gaussian_filter: path must be 'automatic' or 'nonuniform'; got '" + path + "'");
        if (profile == "open" && path != "automatic")
          throw g::InvalidInput("gaussian_filter: the open-profile filter has one path; give "
                                "path='automatic'");
        return without_gil([&] {
          return profile == "open"
                     ? g::gaussian_filtered_open_profile(p, cutoff_upr)
                     : g::gaussian_filtered_profile(p, cutoff_upr,
                                                    path == "nonuniform"
                                                        ? g::FilterPathChoice::nonuniform
                                                        : g::FilterPathChoice::automatic);
        });
      },
      "points"_a, "cutoff_upr"_a, "profile"_a = "closed", "path"_a = "automatic");
  m.def(
      "gaussian_filter_deviations",
      [](const std::vector<double>& deviations, double cutoff_upr) {
        return vector_to_array(
            without_gil([&] { return g::gaussian_filter_closed(deviations, cutoff_upr); }));
      },
      "deviations"_a, "cutoff_upr"_a);

  py::class_<g::ProfileHarmonics>(m, "ProfileHarmonics",
                                  "Harmonic content of a closed profile about a circle.")
      .def_property_readonly("max_order", &g::ProfileHarmonics::max_order)
      .def_property_readonly("point_count", &g::ProfileHarmonics::point_count)
      .def_property_readonly("path",
                             [](const g::ProfileHarmonics& h) {
                               return h.path() == g::HarmonicsPath::fft ? "fft" : "quadrature";
                             })
      .def_property_readonly("center", [](const g::ProfileHarmonics& h) { return pair_of(h.center()); })
      .def_property_readonly("radius", &g::ProfileHarmonics::radius)
      .def_property_readonly("cos",
                             [](const g::ProfileHarmonics& h) {
                               std::vector<double> v(h.max_order() + 1);
                               for (std::size_t k = 0; k < v.size(); ++k) v[k] = h.cos_mm(k);
                               return vector_to_array(v);
                             },
                             "a_k (mm), k = 0 … max_order")
      .def_property_readonly("sin",
                             [](const g::ProfileHarmonics& h) {
                               std::vector<double> v(h.max_order() + 1);
                               for (std::size_t k = 0; k < v.size(); ++k) v[k] = h.sin_mm(k);
                               return vector_to_array(v);
                             },
                             "b_k (mm), k = 0 … max_order (b_0 = 0)")
      .def_property_readonly("deviations",
                             [](const g::ProfileHarmonics& h) {
                               return vector_to_array(h.deviations_mm());
                             },
                             "radial deviations d_i (mm), input order")
      .def(
          "synthesized",
          [](const g::ProfileHarmonics& h, const std::vector<double>& gains) {
            return points_to_array(without_gil([&] { return h.synthesized(gains); }));
          },
          "gains"_a, "the points moved to the deviations re-synthesised with one gain per "
                     "harmonic 0 … max_order");

  m.def(
      "profile_harmonics",
      [](const py::handle& points, std::pair<double, double> center, double radius,
         std::size_t max_order) {
        const auto p = points_from_array(points, "harmonics");
        return without_gil([&] {
          return g::ProfileHarmonics(p, {center.first, center.second}, radius, max_order);
        });
      },
      "points"_a, "center"_a, "radius"_a, "max_order"_a);

  py::class_<g::ClaimCheck>(m, "ClaimCheck", "Another program's circle against the exact one.")
      .def_property_readonly("reference",
                             [](const g::ClaimCheck& c) { return std::string(g::to_string(c.reference)); })
      .def_readonly("claimed_inner_radius", &g::ClaimCheck::claimed_inner_radius)
      .def_readonly("claimed_outer_radius", &g::ClaimCheck::claimed_outer_radius)
      .def_readonly("radii_given", &g::ClaimCheck::radii_given)
      .def_readonly("feasible", &g::ClaimCheck::feasible)
      .def_readonly("violations", &g::ClaimCheck::violations)
      .def_readonly("violating", &g::ClaimCheck::violating, "indices of the first 10")
      .def_readonly("claimed_ront", &g::ClaimCheck::claimed_ront)
      .def_readonly("exact_ront", &g::ClaimCheck::exact_ront)
      .def_readonly("excess_ront", &g::ClaimCheck::excess_ront)
      .def_readonly("radius_excess", &g::ClaimCheck::radius_excess)
      .def_readonly("center_distance", &g::ClaimCheck::center_distance)
      .def_readonly("tolerance", &g::ClaimCheck::tolerance)
      .def_readonly("radius_tolerance", &g::ClaimCheck::radius_tolerance)
      .def_readonly("optimal", &g::ClaimCheck::optimal)
      .def_property_readonly("exact_center",
                             [](const g::ClaimCheck& c) { return pair_of(c.exact_center); })
      .def_readonly("exact_inner_radius", &g::ClaimCheck::exact_inner_radius)
      .def_readonly("exact_outer_radius", &g::ClaimCheck::exact_outer_radius)
      .def_readonly("exact_contacts", &g::ClaimCheck::exact_contacts)
      .def_readonly("exact_certificate", &g::ClaimCheck::exact_certificate)
      .def_readonly("exact_certified", &g::ClaimCheck::exact_certified);

  m.def(
      "check_claimed_circle",
      [](const py::handle& points, const std::string& reference, std::pair<double, double> center,
         std::optional<std::pair<double, double>> radii, double center_resolution) {
        const auto p = points_from_array(points, "check_claim");
        g::ClaimedCircle claim;
        claim.reference = reference_of(reference, "check_claim");
        claim.center = {center.first, center.second};
        claim.radii = radii;
        claim.center_resolution_mm = center_resolution;
        return without_gil([&] { return g::check_claimed_circle(p, claim); });
      },
      "points"_a, "reference"_a, "center"_a, "radii"_a = py::none(),
      "center_resolution"_a = 0.0);
}

}  // namespace
}  // namespace vcmm::python

PYBIND11_MODULE(_vcmm, m) {
  using namespace vcmm::python;
  m.doc() = "vcmm's C++ library (compiled part of the vcmm package; import vcmm instead)";
  register_exceptions(m);
  bind_circles(m);
  bind_roundness(m);
  bind_filter_harmonics_claims(m);
  bind_uncertainty(m);
}
