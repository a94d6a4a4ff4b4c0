// validation/src/demo_world.cpp — the demo's synthetic ground truth (see the header).
//
// Random numbers: one errormodel::SeededRandomSource per purpose, each seeded from the world
// seed and a purpose tag (splitmix64 of seed ⊕ tag), so adding a measurement or changing one
// purpose does not shift the numbers of another.
#include "vcmm/validation/demo_world.h"

#include <array>
#include <cstdio>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "internal/number_text.h"
#include "vcmm/errormodel/atomic_file.h"
#include "vcmm/errormodel/random_source.h"

namespace vcmm::validation {
namespace {

namespace em = vcmm::errormodel;

constexpr double kPi = std::numbers::pi;

std::uint64_t purpose_seed(std::uint64_t seed, std::uint64_t tag) {
  // splitmix64 finaliser of seed + tag·golden: decorrelated seeds for distinct purposes.
  std::uint64_t z = seed + (tag + 1) * 0x9E3779B97F4A7C15ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

struct Location {
  const char* name;
  Eigen::Vector3d position_mm;
};

const std::array<Location, 7>& locations() {
  static const std::array<Location, 7> kLocations = {{
      {"C", {600.0, 500.0, 250.0}},
      {"L1", {200.0, 150.0, 150.0}},
      {"L2", {1000.0, 150.0, 150.0}},
      {"L3", {200.0, 850.0, 150.0}},
      {"L4", {1000.0, 850.0, 150.0}},
      {"E1", {600.0, 500.0, 600.0}},
      {"E2", {1000.0, 850.0, 600.0}},
  }};
  return kLocations;
}

constexpr std::array<const char*, 3> kHeights = {"top", "middle", "bottom"};
constexpr double kRingDiameterMm = 171.0;
constexpr double kTaperMmPerMm = 0.1e-3 / 16.0;  // 0.1 µm diameter change over 16 mm
constexpr double kStylusLengthMm = 100.0;

double form_deviation(const em::RingGauge& ring, double theta) {
  double d = 0.0;
  for (const auto& h : ring.form) d += h.amplitude_mm * std::cos(h.order * theta + h.phase_rad);
  return d;
}

}  // namespace

double demo_height_mm(const std::string& height) {
  if (height == "top") return 8.0;
  if (height == "middle") return 0.0;
  if (height == "bottom") return -8.0;
  throw std::invalid_argument("demo_height_mm: height must be top, middle or bottom; got '" +
                              height + "'");
}

DemoWorld make_demo_world(const em::DigitalModel& model, const DemoWorldOptions& options) {
  if (!(std::isfinite(options.form_scale) && options.form_scale >= 0.0))
    throw std::invalid_argument("make_demo_world: form_scale must be a finite number >= 0; got " +
                                internal::shortest(options.form_scale));
  if (options.scanning_points < 8 || options.touch_trigger_points < 8 ||
      options.roundness_meter_points < 8)
    throw std::invalid_argument("make_demo_world: every point count must be at least 8");
  DemoWorld world;
  world.options = options;

  // The ring: the seed study's form at the middle; other heights vary it.
  world.ring_middle.diameter_mm = kRingDiameterMm;
  world.ring_middle.form = em::seed_study_ring_form();
  for (auto& harmonic : world.ring_middle.form) harmonic.amplitude_mm *= options.form_scale;
  {
    em::SeededRandomSource rng(purpose_seed(options.seed, 1));
    for (const char* h : kHeights) {
      em::RingGauge g = world.ring_middle;
      const double z = demo_height_mm(h);
      g.diameter_mm = kRingDiameterMm + kTaperMmPerMm * z;
      if (z != 0.0) {
        for (auto& harmonic : g.form) {
          harmonic.amplitude_mm *= 1.0 + 0.2 * (2.0 * rng.uniform() - 1.0);
          harmonic.phase_rad += 0.3 * (2.0 * rng.uniform() - 1.0);
        }
      }
      world.ring_by_height.push_back(g);
    }
  }

  // The true CMM: one draw of every systematic error (α, kinematics, probe).
  {
    em::SeededRandomSource rng(purpose_seed(options.seed, 2));
    em::Measurement dummy;
    dummy.points_mm = Eigen::Matrix3Xd::Zero(3, 1);
    dummy.normals = Eigen::Matrix3Xd::Zero(3, 1);
    dummy.normals(0, 0) = 1.0;
    em::Stages systematic = em::Stages::none();
    systematic.set(em::ErrorSource::temperature, true)
        .set(em::ErrorSource::kinematic, true)
        .set(em::ErrorSource::probe, true);
    world.true_cmm = em::draw_errors(model, dummy, rng, systematic);
  }

  // The plan.
  struct Planned {
    std::size_t location;
    double orientation_deg;
    std::size_t height;
    bool orientation_series;
  };
  std::vector<Planned> plan;
  for (std::size_t l = 0; l < locations().size(); ++l)
    for (std::size_t h = 0; h < kHeights.size(); ++h) plan.push_back({l, 0.0, h, false});
  for (double o : {0.0, 90.0, 180.0, 270.0})
    for (std::size_t h = 0; h < kHeights.size(); ++h) plan.push_back({0, o, h, true});

  em::SeededRandomSource temperature_rng(purpose_seed(options.seed, 3));
  em::SeededRandomSource measurement_rng(purpose_seed(options.seed, 4));
  em::SeededRandomSource reference_rng(purpose_seed(options.seed, 5));

  // Reference measurements, one per height (the ring's own frame, independent of placement).
  struct Reference {
    std::vector<double> profile;
    double distance = 0.0;
  };
  std::array<Reference, 3> refs;
  for (std::size_t h = 0; h < kHeights.size(); ++h) {
    const em::RingGauge& g = world.ring_by_height[h];
    const Eigen::Index n = options.roundness_meter_points;
    refs[h].profile.resize(static_cast<std::size_t>(n));
    std::vector<double> noise(static_cast<std::size_t>(n));
    reference_rng.fill_standard_normal(noise);
    for (Eigen::Index i = 0; i < n; ++i) {
      const double theta = 2.0 * kPi * static_cast<double>(i) / static_cast<double>(n);
      refs[h].profile[static_cast<std::size_t>(i)] =
          form_deviation(g, theta) + options.roundness_meter_noise_mm * noise[static_cast<std::size_t>(i)];
    }
    refs[h].distance = g.diameter_mm + form_deviation(g, 0.0) + form_deviation(g, kPi) +
                       options.interferometer_u_mm * reference_rng.standard_normal();
  }

  for (const em::ProbingMode mode : {em::ProbingMode::scanning, em::ProbingMode::touch_trigger}) {
    for (const Planned& p : plan) {
      DemoMeasurement d;
      const Location& loc = locations()[p.location];
      d.location = loc.name;
      d.orientation_deg = p.orientation_deg;
      d.height = kHeights[p.height];
      d.mode = mode;
      char id[64];
      std::snprintf(id, sizeof id, "%s-%s%03d-%s-%s", loc.name, p.orientation_series ? "R" : "O",
                    static_cast<int>(p.orientation_deg), d.height.c_str(),
                    mode == em::ProbingMode::scanning ? "scan" : "touch");
      d.id = id;

      em::RingSampling s;
      s.mode = mode;
      s.points = mode == em::ProbingMode::scanning ? options.scanning_points
                                                   : options.touch_trigger_points;
      s.height_mm = demo_height_mm(d.height);
      s.placement.location_mm = loc.position_mm;
      s.placement.orientation_rad = p.orientation_deg * kPi / 180.0;
      s.temperature_c = options.lab_temperature_c +
                        options.lab_temperature_spread_k * (2.0 * temperature_rng.uniform() - 1.0);
      s.stylus_offset_mm = {0.0, 0.0, -kStylusLengthMm};
      d.truth = em::ring_gauge_measurement(world.ring_by_height[p.height], s);

      // This measurement's random part (true temperature, roughness, noise) with the world's
      // fixed systematic errors.
      em::ErrorDraw draw = em::draw_errors(model, d.truth, measurement_rng);
      draw.expansion_coefficient_per_k = world.true_cmm.expansion_coefficient_per_k;
      draw.kinematic = world.true_cmm.kinematic;
      draw.probe = world.true_cmm.probe;
      d.true_temperature_c = draw.temperature_c;
      d.measured = em::simulate(d.truth, model, draw);

      d.reference_profile_deviation_mm = refs[p.height].profile;
      d.interferometer_distance_mm = refs[p.height].distance;
      world.measurements.push_back(std::move(d));
    }
  }
  return world;
}

std::map<std::string, RingMeasurands> write_demo_campaign(const DemoWorld& world,
                                                          const std::string& model_json_text,
                                                          const EvaluationSettings& evaluation,
                                                          const std::filesystem::path& dir) {
  namespace fs = std::filesystem;
  using internal::shortest;
  std::error_code ec;
  fs::create_directories(dir / "measurements", ec);
  if (!ec) fs::create_directories(dir / "reference", ec);
  if (ec) throw em::OutputError(dir.string() + ": cannot create the demo directory: " + ec.message());
  em::OutputTransaction files;  // the demo's inputs appear together or not at all
  files.stage((dir / "model.json").string(), model_json_text);

  // Roundness-meter profiles, one per height (equiangular from 0°).
  for (std::size_t h = 0; h < kHeights.size(); ++h) {
    const DemoMeasurement* any = nullptr;
    for (const auto& d : world.measurements)
      if (d.height == kHeights[h]) { any = &d; break; }
    if (!any) continue;
    const auto& dev = any->reference_profile_deviation_mm;
    std::string text = "# roundness-meter profile of the demo ring, height " +
                       std::string(kHeights[h]) + " (synthetic; vcmm demo, seed " +
                       std::to_string(world.options.seed) + ")\nangle_deg,deviation_um\n";
    for (std::size_t i = 0; i < dev.size(); ++i) {
      text += shortest(360.0 * static_cast<double>(i) / static_cast<double>(dev.size())) + "," +
              shortest(dev[i] * 1000.0) + "\n";
    }
    files.stage((dir / "reference" / (std::string(kHeights[h]) + ".csv")).string(), text);
  }

  Campaign c;
  c.description =
      "vcmm demo: synthetic ground-truth world (171 mm ring, ~200 nm form; a CMM whose true "
      "errors are one draw of the digital model; 7 locations, 4 orientations, 3 heights, "
      "scanning and touch-trigger), seed " + std::to_string(world.options.seed);
  c.model = "model.json";
  c.model_path = dir / "model.json";
  c.evaluation = evaluation;
  RingEvaluationOptions eval;
  eval.reference = evaluation.reference_circle;
  eval.filter_cutoff_upr = evaluation.filter_cutoff_upr;
  std::map<std::string, RingMeasurands> truth;
  std::string truth_json = "{\n \"schema\": \"vcmm.demo_truth\",\n \"schema_version\": 1,\n"
                           " \"measurements\": [\n";
  bool first = true;
  for (const DemoMeasurement& d : world.measurements) {
    const std::string rel = "measurements/" + d.id + ".csv";
    const std::vector<std::string> comments{"vcmm demo measurement " + d.id +
                                            " (synthetic ground truth, seed " +
                                            std::to_string(world.options.seed) + ")"};
    files.stage((dir / rel).string(), em::measurement_csv(d.measured, comments));
    CampaignMeasurement e;
    e.id = d.id;
    e.points = rel;
    e.points_path = dir / rel;
    e.setup.location = d.location;
    e.setup.location_mm = std::array<double, 3>{d.measured.placement.location_mm[0],
                                                d.measured.placement.location_mm[1],
                                                d.measured.placement.location_mm[2]};
    e.setup.orientation_deg = d.orientation_deg;
    e.setup.height = *height_from_string(d.height);
    e.setup.mode = d.mode;
    e.setup.temperature_c = d.measured.temperature_c;
    const std::string profile = "reference/" + d.height + ".csv";
    e.reference.roundness =
        ProfileRoundness{profile, dir / profile, world.options.reference_roundness_u_mm * 1000.0};
    e.reference.diameter = InterferometerDiameter{
        d.interferometer_distance_mm, world.options.interferometer_u_mm * 1000.0, profile,
        dir / profile, world.options.roundness_meter_noise_mm * 1000.0};
    c.measurements.push_back(std::move(e));

    const RingMeasurands t = evaluate_ring(d.truth, eval);
    truth[d.id] = t;
    truth_json += std::string(first ? "" : ",\n") + "  {\"id\": \"" + d.id +
                  "\", \"true_temperature_c\": " + shortest(d.true_temperature_c) +
                  ", \"diameter_mm\": " + shortest(t.diameter_mm) +
                  ", \"roundness_um\": " + shortest(t.roundness_mm * 1000.0) + "}";
    first = false;
  }
  truth_json += "\n ]\n}\n";
  files.stage((dir / "truth.json").string(), truth_json);
  files.stage((dir / "campaign.json").string(), campaign_json(c));
  files.commit();
  return truth;
}

}  // namespace vcmm::validation
