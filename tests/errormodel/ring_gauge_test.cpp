// Ring-gauge generator: geometry by hand (radius, form, normals towards the axis), placement
// carried through, bad input rejected.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "vcmm/errormodel/errors.h"
#include "vcmm/errormodel/ring_gauge.h"

namespace {

using namespace vcmm::errormodel;

TEST(RingGauge, PerfectRingHasRadiusHalfDiameterAndNormalsTowardsTheAxis) {
  RingSampling s;
  s.points = 360;
  s.height_mm = 7.0;
  const Measurement m = ring_gauge_measurement(RingGauge{}, s);
  ASSERT_EQ(m.size(), 360);
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    const Eigen::Vector3d p = m.points_mm.col(i);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 85.5, 1e-13);
    EXPECT_EQ(p.z(), 7.0);
    const Eigen::Vector3d radial(p.x(), p.y(), 0.0);
    EXPECT_NEAR((m.normals.col(i) + radial.normalized()).norm(), 0.0, 1e-15);
  }
  const double step = std::atan2(m.points_mm(1, 1), m.points_mm(0, 1));
  EXPECT_NEAR(step, 2.0 * std::numbers::pi / 360.0, 1e-15);
}

TEST(RingGauge, FormDeviationIsTheHarmonicSumAndNormalsArePerpendicularToTheProfile) {
  RingGauge ring;
  ring.form = {{3, 0.002, 0.5}};  // exaggerated 2 µm 3-lobe form
  RingSampling s;
  s.points = 720;
  s.start_angle_rad = 0.1;
  const Measurement m = ring_gauge_measurement(ring, s);
  for (Eigen::Index i = 0; i < m.size(); ++i) {
    const double theta = 0.1 + 2.0 * std::numbers::pi * static_cast<double>(i) / 720.0;
    const Eigen::Vector3d p = m.points_mm.col(i);
    EXPECT_NEAR(std::hypot(p.x(), p.y()), 85.5 + 0.002 * std::cos(3 * theta + 0.5), 1e-13);
    // Tangent by a central difference of the closed-form profile; normal ⟂ tangent.
    auto at = [&](double t) {
      const double r = 85.5 + 0.002 * std::cos(3 * t + 0.5);
      return Eigen::Vector3d(r * std::cos(t), r * std::sin(t), 0.0);
    };
    const Eigen::Vector3d tangent = (at(theta + 1e-5) - at(theta - 1e-5)).normalized();
    EXPECT_NEAR(m.normals.col(i).dot(tangent), 0.0, 1e-9);
    EXPECT_LT(m.normals.col(i).dot(p), 0.0);  // towards the axis
  }
}

TEST(RingGauge, SeedStudyFormIsAbout200nmPeakToValley) {
  RingGauge ring;
  ring.form = seed_study_ring_form();
  RingSampling s;
  s.points = 36000;
  const Measurement m = ring_gauge_measurement(ring, s);
  const Eigen::ArrayXd r = m.points_mm.topRows<2>().colwise().norm().transpose().array();
  const double pv_um = (r.maxCoeff() - r.minCoeff()) * 1e3;
  EXPECT_GT(pv_um, 0.15);
  EXPECT_LT(pv_um, 0.25);
}

TEST(RingGauge, SamplingMetadataIsCarried) {
  RingSampling s;
  s.mode = ProbingMode::touch_trigger;
  s.points = 16;
  s.placement.location_mm = {1, 2, 3};
  s.placement.orientation_rad = 0.25;
  s.temperature_c = 21.0;
  s.stylus_offset_mm = {0, 0, -150};
  const Measurement m = ring_gauge_measurement(RingGauge{}, s);
  EXPECT_EQ(m.mode, ProbingMode::touch_trigger);
  EXPECT_EQ(m.size(), 16);
  EXPECT_EQ(m.placement.location_mm, Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(m.placement.orientation_rad, 0.25);
  EXPECT_EQ(m.temperature_c, 21.0);
  EXPECT_EQ(m.stylus_offset_mm, Eigen::Vector3d(0, 0, -150));
}

TEST(RingGauge, BadInputIsRejectedWithTheRule) {
  RingSampling s;
  RingGauge ring;
  ring.diameter_mm = -1.0;
  EXPECT_THROW(ring_gauge_measurement(ring, s), InvalidInput);
  ring.diameter_mm = NAN;
  EXPECT_THROW(ring_gauge_measurement(ring, s), InvalidInput);
  ring = RingGauge{};
  s.points = 2;
  EXPECT_THROW(ring_gauge_measurement(ring, s), InvalidInput);
  s.points = 16;
  ring.form = {{0, 1e-4, 0.0}};
  EXPECT_THROW(ring_gauge_measurement(ring, s), InvalidInput);
  ring.form = {{4, 20.0, 0.0}};  // 4·20 mm ≥ D/4: self-intersecting
  try {
    ring_gauge_measurement(ring, s);
    FAIL() << "no exception";
  } catch (const InvalidInput& e) {
    EXPECT_NE(std::string(e.what()).find("form deviation too large"), std::string::npos);
  }
}

}  // namespace
