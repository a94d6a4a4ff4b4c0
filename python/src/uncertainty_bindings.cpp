// python/src/uncertainty_bindings.cpp — the virtual CMM and the Monte Carlo uncertainty of a
// ring measurement for Python: digital models, measurements (numpy in and out), the
// simulation of one measurement, and validation::evaluate_ring_uncertainty with its samples as
// numpy arrays, the GIL released while it runs, a progress callback and Ctrl-C; a validation
// campaign run (validation::run_campaign) with its tables as lists of dicts.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"
#include "vcmm/validation/campaign.h"
#include "vcmm/validation/campaign_run.h"
#include "vcmm/validation/demo_world.h"
#include "vcmm/validation/measurement_input.h"
#include "vcmm/validation/provenance.h"
#include "vcmm/validation/ring_experiment.h"
#include "vcmm/validation/ring_uncertainty_report.h"

namespace vcmm::python {

namespace g = vcmm::geometry;
namespace em = vcmm::errormodel;
namespace va = vcmm::validation;
namespace un = vcmm::uncertainty;
using namespace pybind11::literals;

namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

using Triple = std::tuple<double, double, double>;

Eigen::Vector3d vector_of(const Triple& t) {
  return {std::get<0>(t), std::get<1>(t), std::get<2>(t)};
}
Triple triple_of(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

/// A 3×N Eigen matrix as an (N, 3) float64 array.
py::array_t<double> columns_to_array(const Eigen::Matrix3Xd& m) {
  py::array_t<double> out({static_cast<py::ssize_t>(m.cols()), py::ssize_t{3}});
  auto view = out.mutable_unchecked<2>();
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (Eigen::Index r = 0; r < 3; ++r)
      view(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(r)) = m(r, i);
  return out;
}

/// An (N, 3) array-like as a 3×N matrix; InvalidInput naming `what` for another shape.
Eigen::Matrix3Xd array_to_columns(const py::handle& object, const char* what) {
  using Array = py::array_t<double, py::array::c_style | py::array::forcecast>;
  Array a;
  try {
    a = Array::ensure(object);
  } catch (const py::error_already_set&) {
  }
  if (!a || a.ndim() != 2 || a.shape(1) != 3)
    throw g::InvalidInput(std::string(what) + ": expected an (n, 3) array (mm)");
  Eigen::Matrix3Xd m(3, a.shape(0));
  const double* data = a.data();
  for (Eigen::Index i = 0; i < m.cols(); ++i)
    for (Eigen::Index r = 0; r < 3; ++r) m(r, i) = data[i * 3 + r];
  return m;
}

em::ProbingMode mode_of(const std::string& text, const char* what) {
  if (const auto mode = em::probing_mode_from_string(text)) return *mode;
  throw g::InvalidInput(std::string(what) + ": mode must be 'scanning' or 'touch'; got '" +
                        text + "'");
}

em::Stages stages_of(const std::optional<std::vector<std::string>>& sources, const char* what) {
  if (!sources) return em::Stages::all();
  em::Stages stages = em::Stages::none();
  for (const std::string& s : *sources) {
    const auto source = em::error_source_from_string(s);
    if (!source)
      throw g::InvalidInput(std::string(what) +
                            ": sources must be among roughness, temperature, kinematic, probe, "
                            "noise; got '" + s + "'");
    stages.set(*source, true);
  }
  return stages;
}

/// The metadata keywords of a plain point file or profile as the library's MeasurementSetup;
/// InvalidInput naming `what` for a frame or surface not in its set.
va::MeasurementSetup setup_of(const std::optional<std::string>& mode,
                              std::optional<double> temperature_c,
                              const std::optional<Triple>& location,
                              std::optional<double> orientation_deg,
                              const std::optional<Triple>& stylus_offset, const std::string& frame,
                              const std::string& surface, const char* what) {
  va::MeasurementSetup s;
  if (mode) s.mode = mode_of(*mode, what);
  s.temperature_c = temperature_c;
  if (location) s.location_mm = vector_of(*location);
  s.orientation_deg = orientation_deg;
  if (stylus_offset) s.stylus_offset_mm = vector_of(*stylus_offset);
  if (frame != "machine" && frame != "workpiece")
    throw g::InvalidInput(std::string(what) + ": frame must be 'machine' or 'workpiece'; got '" +
                          frame + "'");
  if (surface != "inner" && surface != "outer")
    throw g::InvalidInput(std::string(what) + ": surface must be 'inner' or 'outer'; got '" +
                          surface + "'");
  s.frame = frame == "workpiece" ? va::PointFrame::workpiece : va::PointFrame::machine;
  s.side = surface == "outer" ? va::SurfaceSide::outer : va::SurfaceSide::inner;
  return s;
}

/// The GIL back, Ctrl-C and the caller's progress callback (None: none): the progress hook of
/// the library's long runs, called from the calling thread while the workers run.
std::function<void(std::uint64_t, std::uint64_t)> python_progress(const py::object& progress) {
  return [&progress](std::uint64_t done, std::uint64_t planned) {
    py::gil_scoped_acquire acquire;
    if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    if (!progress.is_none()) progress(done, planned);
  };
}

/// One uncertainty evaluation with the options it ran with (the reports need both).
struct UncertaintyRun {
  va::RingUncertaintyResult result;
  va::RingUncertaintyOptions options;
};

py::array_t<double> samples_of(const un::MonteCarloResult& mc) {
  const auto q = static_cast<py::ssize_t>(mc.measurand_count);
  const auto m = static_cast<py::ssize_t>(mc.trials);
  py::array_t<double> out({m, q});
  std::copy(mc.samples.begin(), mc.samples.begin() + m * q, out.mutable_data());
  return out;
}

void bind_model_and_measurement(py::module_& m) {
  py::class_<em::DigitalModel>(m, "DigitalModel", "The CMM's digital model (docs/errormodel.md).")
      .def_readonly("description", &em::DigitalModel::description)
      .def("with_kinematics_uncorrected", &em::with_kinematics_uncorrected,
           "the same model with the kinematic errors left uncorrected");
  m.def("read_digital_model_file", &em::read_digital_model_file, "path"_a);
  m.def("parse_digital_model", &em::parse_digital_model, "json_text"_a, "source_name"_a);
  m.def("bundled_example_model_json",
        [] { return std::string(va::bundled_example_model_json()); });

  py::class_<em::Measurement>(m, "Measurement",
                              "One CMM measurement: points and normals in workpiece "
                              "coordinates (mm), placement, mode, temperature, stylus.")
      .def(py::init([](const py::handle& points, const py::handle& normals, const Triple& location,
                       double orientation_deg, const std::string& mode, double temperature_c,
                       const Triple& stylus_offset) {
             em::Measurement r;
             r.points_mm = array_to_columns(points, "Measurement: points");
             r.normals = array_to_columns(normals, "Measurement: normals");
             r.placement.location_mm = vector_of(location);
             r.placement.orientation_rad = orientation_deg * kRadPerDeg;
             r.mode = mode_of(mode, "Measurement");
             r.temperature_c = temperature_c;
             r.stylus_offset_mm = vector_of(stylus_offset);
             em::validate_measurement(r, "Measurement");
             return r;
           }),
           "points"_a, "normals"_a, "location"_a, "orientation_deg"_a = 0.0,
           "mode"_a = "scanning", "temperature_c"_a = em::reference_temperature_c,
           "stylus_offset"_a = Triple{0.0, 0.0, 0.0})
      .def_property_readonly("points", [](const em::Measurement& x) { return columns_to_array(x.points_mm); },
                             "(n, 3) surface points, workpiece coordinates (mm)")
      .def_property_readonly("normals", [](const em::Measurement& x) { return columns_to_array(x.normals); },
                             "(n, 3) unit normals, material → air")
      .def_property_readonly("machine_points",
                             [](const em::Measurement& x) {
                               return columns_to_array(em::machine_coordinates(x));
                             },
                             "(n, 3) points in machine coordinates (mm)")
      .def_property_readonly("location",
                             [](const em::Measurement& x) { return triple_of(x.placement.location_mm); })
      .def_property_readonly("orientation_deg",
                             [](const em::Measurement& x) { return x.placement.orientation_rad / kRadPerDeg; })
      .def_property_readonly("mode",
                             [](const em::Measurement& x) { return std::string(em::to_string(x.mode)); })
      .def_readonly("temperature_c", &em::Measurement::temperature_c)
      .def_property_readonly("stylus_offset",
                             [](const em::Measurement& x) { return triple_of(x.stylus_offset_mm); })
      .def("__len__", [](const em::Measurement& x) { return static_cast<std::size_t>(x.size()); })
      .def("csv",
           [](const em::Measurement& x, const std::vector<std::string>& comments) {
             return em::measurement_csv(x, comments);
           },
           "comments"_a = std::vector<std::string>{},
           "the measurement CSV (docs/errormodel.md) as text");

  m.def(
      "read_measurement_file",
      [](const std::string& path, std::optional<std::string> mode,
         std::optional<double> temperature_c, std::optional<Triple> location,
         std::optional<double> orientation_deg, std::optional<Triple> stylus_offset,
         const std::string& frame, const std::string& surface, std::optional<double> radius,
         double height) {
        va::MeasurementSetup s = setup_of(mode, temperature_c, location, orientation_deg,
                                          stylus_offset, frame, surface, "read_measurement");
        s.radius_mm = radius;
        s.height_mm = height;
        return va::read_measurement_file(path, s);
      },
      "path"_a, "mode"_a = py::none(), "temperature_c"_a = py::none(),
      "location"_a = py::none(), "orientation_deg"_a = py::none(),
      "stylus_offset"_a = py::none(), "frame"_a = "machine", "surface"_a = "inner",
      "radius"_a = py::none(), "height"_a = 0.0);

  m.def(
      "measurement_from_points",
      [](const py::handle& points, std::optional<std::string> mode,
         std::optional<double> temperature_c, std::optional<Triple> location,
         std::optional<double> orientation_deg, std::optional<Triple> stylus_offset,
         const std::string& frame, const std::string& surface) {
        g::PointTable table;
        table.points = points_from_array(points, "measurement_from_points", table.z);
        const auto a = py::array::ensure(points);
        if (a && a.ndim() == 2 && a.shape(1) == 2) table.z.clear();  // a two-column table
        return va::measurement_from_points(
            table,
            setup_of(mode, temperature_c, location, orientation_deg, stylus_offset, frame,
                     surface, "measurement_from_points"),
            "points");
      },
      "points"_a, "mode"_a = py::none(), "temperature_c"_a = py::none(),
      "location"_a = py::none(), "orientation_deg"_a = py::none(),
      "stylus_offset"_a = py::none(), "frame"_a = "machine", "surface"_a = "inner");
}

void bind_simulate(py::module_& m) {
  // The composition of `vcmm simulate` (cli/simulate_command.cpp): the nominal ring, one draw
  // of every enabled error source, what the CMM reports (optionally corrected).
  m.def(
      "simulate",
      [](const em::DigitalModel& model, double ring_diameter, std::optional<long long> points,
         const std::string& mode, const Triple& location, double orientation_deg, double height,
         double temperature_c, const Triple& stylus_offset, std::uint64_t seed,
         const std::optional<std::vector<std::string>>& sources, bool form,
         const std::string& formula, bool corrected) {
        em::RingSampling sampling;
        sampling.mode = mode_of(mode, "simulate");
        if (points && *points < 3)
          throw g::InvalidInput("simulate: points must be at least 3; got " +
                                std::to_string(*points));
        sampling.points = points ? static_cast<Eigen::Index>(*points)
                          : sampling.mode == em::ProbingMode::scanning ? 3600
                                                                       : 16;
        sampling.placement.location_mm = vector_of(location);
        sampling.placement.orientation_rad = orientation_deg * kRadPerDeg;
        sampling.height_mm = height;
        sampling.temperature_c = temperature_c;
        sampling.stylus_offset_mm = vector_of(stylus_offset);
        const em::Stages stages = stages_of(sources, "simulate");
        if (formula != "first_order" && formula != "exact")
          throw g::InvalidInput("simulate: formula must be 'first_order' or 'exact'; got '" +
                                formula + "'");
        const em::Formula f = formula == "exact" ? em::Formula::exact : em::Formula::first_order;
        py::gil_scoped_release release;
        em::RingGauge ring;
        ring.diameter_mm = ring_diameter;
        if (form) ring.form = em::seed_study_ring_form();
        const em::Measurement nominal = em::ring_gauge_measurement(ring, sampling);
        em::SeededRandomSource rng(seed);
        const em::ErrorDraw draw = em::draw_errors(model, nominal, rng, stages);
        em::Measurement result = em::simulate(nominal, model, draw, stages, f);
        if (corrected) result = em::correct(result, model, stages, f);
        return result;
      },
      "model"_a, "ring_diameter"_a, "points"_a = py::none(), "mode"_a = "scanning",
      "location"_a, "orientation_deg"_a = 0.0, "height"_a = 0.0,
      "temperature_c"_a = em::reference_temperature_c, "stylus_offset"_a = Triple{0.0, 0.0, 0.0},
      "seed"_a = 1, "sources"_a = py::none(), "form"_a = true, "formula"_a = "first_order",
      "corrected"_a = false);
}

void bind_results(py::module_& m) {
  py::class_<un::CoverageInterval>(m, "CoverageInterval")
      .def_readonly("low", &un::CoverageInterval::low)
      .def_readonly("high", &un::CoverageInterval::high)
      .def_readonly("probability", &un::CoverageInterval::probability)
      .def("__iter__", [](const un::CoverageInterval& c) {
        return py::iter(py::make_tuple(c.low, c.high));
      })
      .def("__repr__", [](const un::CoverageInterval& c) {
        return "<vcmm.CoverageInterval [" + std::to_string(c.low) + ", " +
               std::to_string(c.high) + "] p=" + std::to_string(c.probability) + ">";
      });

  py::class_<un::MeasurandSummary>(m, "MeasurandSummary")
      .def_readonly("count", &un::MeasurandSummary::count)
      .def_readonly("mean", &un::MeasurandSummary::mean)
      .def_readonly("standard_uncertainty", &un::MeasurandSummary::standard_uncertainty)
      .def_readonly("probabilistically_symmetric",
                    &un::MeasurandSummary::probabilistically_symmetric)
      .def_readonly("shortest", &un::MeasurandSummary::shortest);

  py::class_<un::BiasCorrection>(m, "BiasCorrection",
                                 "Estimate, bias and corrected value of one measurand (mm).")
      .def_readonly("estimate", &un::BiasCorrection::estimate)
      .def_readonly("monte_carlo_mean", &un::BiasCorrection::monte_carlo_mean)
      .def_readonly("bias", &un::BiasCorrection::bias)
      .def_readonly("bias_standard_error", &un::BiasCorrection::bias_standard_error)
      .def_readonly("corrected", &un::BiasCorrection::corrected)
      .def_readonly("standard_uncertainty", &un::BiasCorrection::standard_uncertainty)
      .def_readonly("interval", &un::BiasCorrection::interval)
      .def_readonly("applied", &un::BiasCorrection::applied)
      .def_readonly("refused", &un::BiasCorrection::refused)
      .def_readonly("bias_uncertainty", &un::BiasCorrection::bias_uncertainty)
      .def_readonly("clamped", &un::BiasCorrection::clamped)
      .def_readonly("note", &un::BiasCorrection::note);

  py::class_<un::MonteCarloResult>(m, "MonteCarloResult")
      .def_readonly("trials", &un::MonteCarloResult::trials)
      .def_property_readonly("status", [](const un::MonteCarloResult& r) {
        return std::string(un::to_string(r.status));
      })
      .def_readonly("message", &un::MonteCarloResult::message)
      .def_property_readonly("samples", &samples_of,
                             "(trials, measurands) array, trial-major (mm)")
      .def_readonly("summaries", &un::MonteCarloResult::summaries)
      .def_property_readonly("correlation", [](const un::MonteCarloResult& r) {
        const auto q = static_cast<py::ssize_t>(r.measurand_count);
        py::array_t<double> out({q, q});
        if (r.correlation.size() == static_cast<std::size_t>(q * q))
          std::copy(r.correlation.begin(), r.correlation.end(), out.mutable_data());
        else
          std::fill(out.mutable_data(), out.mutable_data() + q * q, std::nan(""));
        return out;
      })
      .def_readonly("wall_seconds", &un::MonteCarloResult::wall_seconds)
      .def_readonly("threads_used", &un::MonteCarloResult::threads_used)
      .def_readonly("ranks", &un::MonteCarloResult::ranks,
                    "processes the trials were spread over (1 from Python; docs/mpi.md)");

  py::class_<UncertaintyRun>(m, "RingUncertaintyResult")
      .def_property_readonly("best_estimate", [](const UncertaintyRun& r) { return r.result.best_estimate; })
      .def_property_readonly("estimate_diameter",
                             [](const UncertaintyRun& r) { return r.result.estimate.diameter_mm; })
      .def_property_readonly("estimate_roundness",
                             [](const UncertaintyRun& r) { return r.result.estimate.roundness_mm; })
      .def_property_readonly("monte_carlo", [](const UncertaintyRun& r) { return r.result.monte_carlo; })
      .def_property_readonly("trial",
                             [](const UncertaintyRun& r) {
                               return py::make_tuple(std::string(va::to_string(r.result.trial.kind)),
                                                     r.result.trial.reason);
                             },
                             "(kind, reason): the trial the first run used ('exact' or 'spectral')")
      .def_property_readonly("samples",
                             [](const UncertaintyRun& r) { return samples_of(r.result.monte_carlo); },
                             "(trials, 2) array: diameter (mm), roundness (mm) of every trial")
      .def_property_readonly("diameter", [](const UncertaintyRun& r) { return r.result.diameter; })
      .def_property_readonly("roundness", [](const UncertaintyRun& r) { return r.result.roundness; })
      .def_property_readonly("roundness_paper",
                             [](const UncertaintyRun& r) { return r.result.roundness_paper; })
      .def_property_readonly("roundness_treatment", [](const UncertaintyRun& r) {
        return std::string(va::to_string(r.result.roundness_treatment));
      })
      .def_property_readonly("surrogate_monte_carlo",
                             [](const UncertaintyRun& r) -> std::optional<un::MonteCarloResult> {
                               if (!r.result.surrogate) return std::nullopt;
                               return r.result.surrogate->monte_carlo;
                             })
      .def("json", [](const UncertaintyRun& r) { return va::ring_uncertainty_json(r.result, r.options); },
           "the JSON report of `vcmm uncertainty --json` (docs/formats.md)")
      .def("table", [](const UncertaintyRun& r) { return va::ring_uncertainty_text(r.result, r.options); },
           "the text table of `vcmm uncertainty`")
      .def("samples_csv",
           [](const UncertaintyRun& r) { return va::ring_samples_csv(r.result.monte_carlo); });
}

void bind_ring_uncertainty(py::module_& m) {
  m.def(
      "evaluate_ring_uncertainty",
      [](const em::DigitalModel& model, const em::Measurement& measured, std::uint64_t trials,
         std::optional<double> adaptive_tolerance, std::uint64_t seed, unsigned threads,
         const std::string& reference, std::optional<double> filter_upr, double coverage,
         const std::string& bias_treatment, std::optional<std::uint64_t> pilot_trials,
         std::optional<std::uint64_t> surrogate_trials,
         const std::optional<std::vector<std::string>>& sources, const py::object& progress,
         const std::string& trial) {
        UncertaintyRun run;
        va::RingUncertaintyOptions& o = run.options;
        const auto circle = g::reference_circle_from_string(reference);
        if (!circle)
          throw g::InvalidInput("uncertainty: reference must be MZ, MI, LS or MC; got '" +
                                reference + "'");
        o.evaluation.reference = *circle;
        o.evaluation.filter_cutoff_upr = filter_upr;
        o.stages = stages_of(sources, "uncertainty");
        o.monte_carlo.trials = trials;
        o.monte_carlo.seed = seed;
        o.monte_carlo.threads = threads;
        o.monte_carlo.coverage_probability = coverage;
        if (adaptive_tolerance) {
          un::AdaptiveOptions adaptive;
          adaptive.numerical_tolerance = *adaptive_tolerance;
          o.adaptive = adaptive;
        }
        const auto treatment = va::roundness_bias_treatment_from_string(bias_treatment);
        if (!treatment)
          throw g::InvalidInput("uncertainty: bias_treatment must be 'shrinkage' or 'paper'; "
                                "got '" + bias_treatment + "'");
        o.roundness_bias = *treatment;
        if (pilot_trials) o.shrinkage.pilot_trials = *pilot_trials;
        if (surrogate_trials) o.shrinkage.surrogate_trials = *surrogate_trials;
        const auto kind = va::trial_kind_from_string(trial);
        if (!kind)
          throw g::InvalidInput("uncertainty: trial must be 'auto', 'exact' or 'spectral'; got '" +
                                trial + "'");
        o.trial = *kind;
        o.provenance = {{"source", "python"}};
        // About every 100 ms: Ctrl-C (KeyboardInterrupt) and the caller's callback; either one
        // raising stops the run and the exception reaches the caller.
        o.monte_carlo.progress = python_progress(progress);
        {
          py::gil_scoped_release release;
          run.result = va::evaluate_ring_uncertainty(model, measured, o);
        }
        o.monte_carlo.progress = nullptr;  // refers to this call's frame
        return run;
      },
      "model"_a, "measurement"_a, "trials"_a = 100000, "adaptive_tolerance"_a = py::none(),
      "seed"_a = 1, "threads"_a = 0, "reference"_a = "MZ", "filter_upr"_a = 50.0,
      "coverage"_a = 0.95, "bias_treatment"_a = "shrinkage", "pilot_trials"_a = py::none(),
      "surrogate_trials"_a = py::none(), "sources"_a = py::none(),
      "progress"_a = py::none(), "trial"_a = "auto");

  m.def("version", [] { return std::string(va::vcmm_version()); });
  m.def("revision", [] { return std::string(va::vcmm_revision()); });
}

py::dict measurand_dict(const va::MeasurandOutcome& o) {
  py::dict d;
  d["has_reference"] = o.has_reference;
  d["reference_mm"] = o.reference_mm;
  d["u_reference_mm"] = o.u_reference_mm;
  d["reference_method"] = o.reference_method;
  d["estimate_mm"] = o.estimate_mm;
  d["u_mm"] = o.u_mm;
  d["mc_mean_mm"] = o.mc_mean_mm;
  d["interval_low_mm"] = o.interval_low_mm;
  d["interval_high_mm"] = o.interval_high_mm;
  d["treatment"] = o.treatment;
  d["bias_mm"] = o.bias_mm;
  d["bias_standard_error_mm"] = o.bias_standard_error_mm;
  d["bias_uncertainty_mm"] = o.bias_uncertainty_mm;
  d["corrected_mm"] = o.corrected_mm;
  d["u_corrected_mm"] = o.u_corrected_mm;
  d["correction_applied"] = o.correction_applied;
  d["note"] = o.note;
  d["bias_paper_mm"] = o.bias_paper_mm;
  d["corrected_paper_mm"] = o.corrected_paper_mm;
  d["u_corrected_paper_mm"] = o.u_corrected_paper_mm;
  d["paper_applied"] = o.paper_applied;
  d["corrected_denoised_mm"] = o.corrected_denoised_mm;
  d["u_denoised_mm"] = o.u_denoised_mm;
  d["denoised_applied"] = o.denoised_applied;
  d["en"] = o.en;
  d["en_corrected"] = o.en_corrected;
  d["en_paper"] = o.en_paper;
  d["en_denoised"] = o.en_denoised;
  d["en_inflated"] = o.en_inflated;
  d["zeta"] = o.zeta;
  d["zeta_corrected"] = o.zeta_corrected;
  d["true_mm"] = o.true_mm;
  return d;
}

/// A measurement's uncertainty budget (ring_uncertainty_budget.h) as plain data, mm.
py::dict budget_dict(const va::UncertaintyBudget& b) {
  py::list sources;
  for (const va::SourceContribution& c : b.sources)
    sources.append(py::dict("source"_a = std::string(em::to_string(c.source)),
                            "evaluated"_a = c.evaluated, "diameter_u_mm"_a = c.diameter_u_mm,
                            "diameter_share"_a = c.diameter_share,
                            "roundness_u_mm"_a = c.roundness_u_mm,
                            "roundness_share"_a = c.roundness_share));
  return py::dict("trials"_a = b.trials, "sources"_a = sources,
                  "diameter_quadrature_mm"_a = b.diameter_quadrature_mm,
                  "diameter_full_u_mm"_a = b.diameter_full_u_mm,
                  "roundness_quadrature_mm"_a = b.roundness_quadrature_mm,
                  "roundness_full_u_mm"_a = b.roundness_full_u_mm);
}

void bind_campaign(py::module_& m) {
  m.def(
      "run_campaign",
      [](const std::string& campaign_path, const std::string& output_dir, unsigned threads,
         bool denoised, const py::object& progress, std::optional<bool> budget,
         std::uint64_t budget_trials) {
        va::Campaign campaign = va::read_campaign_file(campaign_path);
        // As `vcmm validate --budget [--budget-trials N]`: overrides the campaign's setting.
        if (budget) campaign.evaluation.budget = *budget;
        if (budget_trials != 0) {
          if (!campaign.evaluation.budget)
            throw py::value_error("budget_trials needs budget=True (or \"budget\": true in "
                                  "the campaign)");
          if (budget_trials < va::min_campaign_trials || budget_trials > campaign.evaluation.trials)
            throw py::value_error("budget_trials must be from " +
                                  std::to_string(va::min_campaign_trials) + " to the campaign's " +
                                  std::to_string(campaign.evaluation.trials) + " trials; got " +
                                  std::to_string(budget_trials));
          campaign.evaluation.budget_trials = budget_trials;
        }
        va::CampaignRunOptions o;
        o.threads = threads;
        o.denoised_treatment = denoised;
        o.progress = python_progress(progress);
        o.provenance = {{"source", "python"}};
        va::CampaignOutcome outcome;
        {
          py::gil_scoped_release release;
          outcome = va::run_campaign(campaign, output_dir, o);
        }
        py::list measurements, summary, treatments;
        for (const va::MeasurementOutcome& x : outcome.measurements) {
          py::dict d;
          d["id"] = x.id;
          d["location"] = x.location;
          d["orientation_deg"] = x.orientation_deg;
          d["height"] = std::string(va::to_string(x.height));
          d["mode"] = std::string(em::to_string(x.mode));
          d["points"] = x.points;
          d["seed"] = x.seed;
          d["trials"] = x.trials;
          d["diameter"] = measurand_dict(x.diameter);
          d["roundness"] = measurand_dict(x.roundness);
          d["trial"] = x.trial;
          d["budget"] = x.budget ? py::object(budget_dict(*x.budget)) : py::object(py::none());
          d["wall_seconds"] = x.wall_seconds;
          d["resumed"] = x.resumed;
          measurements.append(d);
        }
        for (const va::SummaryRow& r : outcome.summary)
          summary.append(py::dict("factor"_a = r.factor, "level"_a = r.level,
                                  "measurand"_a = r.measurand, "treatment"_a = r.treatment,
                                  "n"_a = r.n, "share_within_1"_a = r.share_within_1,
                                  "mean_en"_a = r.mean_en, "rms_en"_a = r.rms_en));
        for (const va::TreatmentRow& r : outcome.treatments)
          treatments.append(py::dict("measurand"_a = r.measurand, "treatment"_a = r.treatment,
                                     "n"_a = r.n, "mean_en"_a = r.mean_en, "rms_en"_a = r.rms_en,
                                     "share_within_1"_a = r.share_within_1,
                                     "mean_error_mm"_a = r.mean_error_mm,
                                     "rms_error_mm"_a = r.rms_error_mm));
        return py::dict("measurements"_a = measurements, "summary"_a = summary,
                        "treatments"_a = treatments, "computed"_a = outcome.computed,
                        "resumed"_a = outcome.resumed, "cancelled"_a = outcome.cancelled,
                        "wall_seconds"_a = outcome.wall_seconds);
      },
      "campaign"_a, "output_dir"_a, "threads"_a = 0, "denoised"_a = false,
      "progress"_a = py::none(), "budget"_a = py::none(), "budget_trials"_a = 0);
}

}  // namespace

void bind_uncertainty(py::module_& m) {
  bind_model_and_measurement(m);
  bind_simulate(m);
  bind_results(m);
  bind_ring_uncertainty(m);
  bind_campaign(m);
}

}  // namespace vcmm::python
