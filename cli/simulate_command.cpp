// `vcmm simulate --model MODEL.json --ring DIAMETER_MM [--points N] [--mode scanning|touch]
//                --location X,Y,Z [--orientation DEG] [--height MM] [--temperature C]
//                [--stylus-offset X,Y,Z] [--seed S] [--only SOURCE ...] [--no-form]
//                [--formula first_order|exact] [--corrected] -o OUT.csv`
// Generates the nominal ring-gauge measurement, draws one realisation of every error source
// of the digital model and writes what the CMM would report (docs/errormodel.md, docs/cli.md).
#include <charconv>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "atomic_file.h"
#include "commands.h"
#include "option_values.h"
#include "run_control.h"
#include "vcmm/errormodel/digital_model.h"
#include "vcmm/errormodel/measurement.h"
#include "vcmm/errormodel/random_source.h"
#include "vcmm/errormodel/ring_gauge.h"
#include "vcmm/errormodel/virtual_cmm.h"

namespace vcmm::cli {
namespace {

namespace em = vcmm::errormodel;

struct SimulateOptions {
  std::string model;
  double ring_mm = 0.0;
  long long points = 0;  // 0: the mode's default
  std::string mode = "scanning";
  std::string location;
  double orientation_deg = 0.0;
  double height_mm = 0.0;
  double temperature_c = em::reference_temperature_c;
  std::string stylus_offset = "0,0,0";
  std::uint64_t seed = 1;
  std::vector<std::string> only;
  bool no_form = false;
  std::string formula = "first_order";
  bool corrected = false;
  std::string output;
};

/// The options as a canonical command line, for the provenance comment of the output.
std::string canonical_command(const SimulateOptions& o, Eigen::Index points) {
  auto num = [](double v) {
    char buf[32];
    const auto r = std::to_chars(buf, buf + sizeof buf, v);
    return std::string(buf, r.ptr);
  };
  std::string s = "vcmm simulate --model " + o.model + " --ring " + num(o.ring_mm) +
                  " --points " + std::to_string(points) + " --mode " + o.mode + " --location " +
                  o.location + " --orientation " + num(o.orientation_deg) + " --height " +
                  num(o.height_mm) + " --temperature " + num(o.temperature_c) +
                  " --stylus-offset " + o.stylus_offset + " --seed " + std::to_string(o.seed) +
                  " --formula " + o.formula;
  for (const std::string& src : o.only) s += " --only " + src;
  if (o.no_form) s += " --no-form";
  if (o.corrected) s += " --corrected";
  return s;
}


int run_simulate(const SimulateOptions& o) {
  // 1. Options that CLI11 cannot check alone → exit 2.
  em::RingSampling sampling;
  em::Stages stages = em::Stages::all();
  em::Formula formula = em::Formula::first_order;
  try {
    sampling.mode = *em::probing_mode_from_string(o.mode);  // IsMember-checked
    sampling.points = o.points > 0 ? static_cast<Eigen::Index>(o.points)
                      : sampling.mode == em::ProbingMode::scanning ? 3600
                                                                   : 16;
    sampling.placement.location_mm = parse_triple(o.location, "--location");
    sampling.placement.orientation_rad = o.orientation_deg * std::numbers::pi / 180.0;
    sampling.height_mm = o.height_mm;
    sampling.temperature_c = o.temperature_c;
    sampling.stylus_offset_mm = parse_triple(o.stylus_offset, "--stylus-offset");
    if (!o.only.empty()) {
      stages = em::Stages::none();
      for (const std::string& s : o.only) stages.set(*em::error_source_from_string(s), true);
    }
    formula = o.formula == "exact" ? em::Formula::exact : em::Formula::first_order;
  } catch (const std::invalid_argument& ex) {
    std::cerr << "vcmm simulate: error: " << ex.what() << "\n";
    return kUsage;
  }
  // 2. The model file and the simulation → exit 3 on invalid input.
  try {
    const em::DigitalModel model = em::read_digital_model_file(o.model);
    em::RingGauge ring;
    ring.diameter_mm = o.ring_mm;
    if (!o.no_form) ring.form = em::seed_study_ring_form();
    const em::Measurement nominal = em::ring_gauge_measurement(ring, sampling);
    em::SeededRandomSource rng(o.seed);
    const em::ErrorDraw draw = em::draw_errors(model, nominal, rng, stages);
    em::Measurement result = em::simulate(nominal, model, draw, stages, formula);
    if (o.corrected) result = em::correct(result, model, stages, formula);

    std::string sources;
    for (em::ErrorSource s : em::all_error_sources)
      if (stages.is_enabled(s)) sources += (sources.empty() ? "" : ",") + std::string(to_string(s));
    const std::vector<std::string> comments = {
        canonical_command(o, sampling.points),
        "model file " + o.model + ", seed " + std::to_string(o.seed) + ", sources " +
            (sources.empty() ? "none" : sources) + ", " +
            (formula == em::Formula::exact ? "exact" : "first-order") + " kinematics" +
            (o.corrected ? ", corrected (known systematic errors removed)" : ", as reported"),
        "true workpiece temperature of this draw " + std::to_string(draw.temperature_c) + " C"};
    write_file_atomically(o.output, em::measurement_csv(result, comments));
    return kOk;
  } catch (const std::exception&) {  // 3 for the model, the ring or the output path
    return report_current_exception("simulate");
  }
}

}  // namespace

void add_simulate_command(CLI::App& app, int* exit_code) {
  auto opts = std::make_shared<SimulateOptions>();
  CLI::App* cmd = app.add_subcommand(
      "simulate",
      "simulate a ring-gauge measurement on the virtual CMM and write it as a measurement CSV");
  cmd->add_option("--model", opts->model, "digital-model JSON (docs/errormodel.md)")
      ->required();
  cmd->add_option("--ring", opts->ring_mm, "inner diameter of the ring gauge (mm), e.g. 171")
      ->required()
      ->check(physical_value(em::physical_range::diameter_mm, /*open_below=*/true));
  cmd->add_option("--points", opts->points,
                  "number of equiangular points (default: 3600 scanning, 16 touch)")
      ->check(CLI::Range(3LL, 100000000LL));
  cmd->add_option("--mode", opts->mode, "probing mode: scanning or touch (touch-trigger)")
      ->check(CLI::IsMember({"scanning", "touch", "touch_trigger", "touch-trigger"}))
      ->default_val("scanning");
  cmd->add_option("--location", opts->location,
                  "ring centre in machine coordinates X,Y,Z (mm)")
      ->required();
  cmd->add_option("--orientation", opts->orientation_deg,
                  "rotation of the ring about its axis (machine Z), degrees")
      ->check(finite_number())
      ->default_val(0.0);
  cmd->add_option("--height", opts->height_mm,
                  "height of the scanned section in workpiece coordinates (mm)")
      ->check(physical_value(em::physical_range::coordinate_mm))
      ->default_val(0.0);
  cmd->add_option("--temperature", opts->temperature_c,
                  "workpiece temperature reading (°C)")
      ->check(physical_value(em::physical_range::temperature_c))
      ->default_val(em::reference_temperature_c);
  cmd->add_option("--stylus-offset", opts->stylus_offset,
                  "tip centre relative to the ram reference point X,Y,Z (mm)")
      ->default_val("0,0,0");
  cmd->add_option("--seed", opts->seed, "seed of the random draw (reproducible)")
      ->check(unsigned_64())
      ->default_val(1);
  cmd->add_option("--only", opts->only,
                  "keep only this error source (repeatable): roughness, temperature, "
                  "kinematic, probe, noise")
      ->check(CLI::IsMember({"roughness", "temperature", "kinematic", "probe", "noise"}));
  cmd->add_flag("--no-form", opts->no_form, "a perfect ring (no ~200 nm form deviation)");
  cmd->add_option("--formula", opts->formula, "rigid-body formula: first_order or exact")
      ->check(CLI::IsMember({"first_order", "exact"}))
      ->default_val("first_order");
  cmd->add_flag("--corrected", opts->corrected,
                "write the corrected points (known systematic errors removed)");
  cmd->add_option("-o,--output", opts->output, "output measurement CSV (written atomically)")
      ->required();
  cmd->callback([opts, exit_code] { *exit_code = run_simulate(*opts); });
}

}  // namespace vcmm::cli
