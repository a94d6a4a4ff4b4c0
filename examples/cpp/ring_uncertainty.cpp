// Example: the uncertainty of one ring-gauge measurement (vcmm::validation) — simulate what the
// CMM of examples/cmm_model.json reports for the 171 mm ring, then evaluate diameter and
// roundness by Monte Carlo with the bias and the bias-corrected estimates (the roundness by the
// default shrinkage treatment and by the seed study's), and compare with the truth by E_n.
// Usage: ring_uncertainty [MODEL.json]
#include <cstdio>
#include <string>

#include <vcmm/errormodel/digital_model.h>
#include <vcmm/errormodel/ring_gauge.h>
#include <vcmm/errormodel/virtual_cmm.h>
#include <vcmm/validation/comparison.h>
#include <vcmm/validation/ring_experiment.h>

int main(int argc, char** argv) {
  namespace em = vcmm::errormodel;
  namespace va = vcmm::validation;
  const std::string model_file = argc > 1 ? argv[1] : VCMM_EXAMPLE_MODEL;
  const em::DigitalModel model = em::read_digital_model_file(model_file);

  // A measured ring: the true surface, and one draw of the CMM's errors applied to it.
  em::RingGauge ring;
  ring.form = em::seed_study_ring_form();
  em::RingSampling sampling;  // 3600 scanning points
  sampling.placement.location_mm = {600.0, 500.0, 250.0};
  sampling.stylus_offset_mm = {0.0, 0.0, -100.0};
  sampling.temperature_c = 20.4;
  const em::Measurement truth = em::ring_gauge_measurement(ring, sampling);
  em::SeededRandomSource rng(7);
  const em::Measurement measured = em::simulate(truth, model, em::draw_errors(model, truth, rng));

  va::RingUncertaintyOptions options;  // MZ reference, 50 UPR Gaussian filter
  options.monte_carlo.trials = 2000;
  options.monte_carlo.seed = 1;
  const va::RingUncertaintyResult r = va::evaluate_ring_uncertainty(model, measured, options);
  const auto& d = r.monte_carlo.summaries[va::diameter];
  const auto& q = r.monte_carlo.summaries[va::roundness];
  std::printf("diameter  %.5f mm, u %.3f um, bias %+.3f um\n", r.estimate.diameter_mm,
              d.standard_uncertainty * 1e3, r.diameter.bias * 1e3);
  std::printf("roundness %.3f um, u %.3f um\n", r.estimate.roundness_mm * 1e3,
              q.standard_uncertainty * 1e3);
  std::printf("  shrinkage (default): bias %+.3f um (its own u %.3f um), corrected %.3f um, "
              "u %.3f um\n",
              r.roundness.bias * 1e3, r.roundness.bias_uncertainty * 1e3,
              r.roundness.corrected * 1e3, r.roundness.standard_uncertainty * 1e3);
  std::printf("  seed study:          bias %+.3f um, corrected %.3f um (%s), u %.3f um\n",
              r.roundness_paper.bias * 1e3, r.roundness_paper.corrected * 1e3,
              r.roundness_paper.applied ? "applied" : "refused",
              r.roundness_paper.standard_uncertainty * 1e3);
  const va::RingMeasurands t = va::evaluate_ring(truth, options.evaluation);
  // Treat the true value as a reference with u = 10 nm.
  std::printf("true roundness %.3f um; E_n: uncorrected %.2f, shrinkage %.2f, seed study %.2f\n",
              t.roundness_mm * 1e3,
              va::en_score(t.roundness_mm, 1e-5, r.estimate.roundness_mm, q.standard_uncertainty),
              va::en_score(t.roundness_mm, 1e-5, r.roundness.corrected,
                           r.roundness.standard_uncertainty),
              va::en_score(t.roundness_mm, 1e-5, r.roundness_paper.corrected,
                           r.roundness_paper.standard_uncertainty));
  return 0;
}
