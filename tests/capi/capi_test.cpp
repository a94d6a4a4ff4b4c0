// tests/capi/capi_test.cpp — the C interface gives exactly what the C++ engine gives
// (same doubles, same contacts, same outcomes) on noisy, lobed, filtered and partial
// profiles, whatever the point order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "support/test_profiles.h"
#include "vcmm/geometry/roundness.h"
#include "vcmm/vcmm_c.h"

namespace g = vcmm::geometry;
namespace {

std::vector<double> interleave(const std::vector<g::Point2>& points) {
  std::vector<double> xy;
  for (const g::Point2& p : points) {
    xy.push_back(p.x);
    xy.push_back(p.y);
  }
  return xy;
}

vcmm_roundness_result call(const std::vector<g::Point2>& points, double cutoff,
                           std::vector<double>* filtered = nullptr) {
  const std::vector<double> xy = interleave(points);
  vcmm_roundness_options options;
  vcmm_roundness_options_init(&options);
  options.filter_cutoff_upr = cutoff;
  vcmm_roundness_result result{};
  result.struct_size = sizeof result;
  char error[256];
  if (filtered) filtered->assign(xy.size(), 0.0);
  const vcmm_status s = vcmm_roundness(xy.data(), points.size(), &options, &result,
                                       filtered ? filtered->data() : nullptr, error,
                                       sizeof error);
  EXPECT_EQ(s, VCMM_OK) << error;
  return result;
}

void expect_same(const vcmm_circle& c, const g::Point2& center, double radius,
                 const g::RoundnessParameters& ron, const std::vector<std::size_t>& contacts) {
  ASSERT_EQ(c.defined, 1);
  EXPECT_EQ(c.center_x, center.x);
  EXPECT_EQ(c.center_y, center.y);
  EXPECT_EQ(c.radius, radius);
  EXPECT_EQ(c.ront, ron.ront);
  EXPECT_EQ(c.ronp, ron.ronp);
  EXPECT_EQ(c.ronv, ron.ronv);
  EXPECT_EQ(c.ronq, ron.ronq);
  ASSERT_EQ(c.n_contacts, contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i) EXPECT_EQ(c.contacts[i], contacts[i]);
}

void expect_same(const vcmm_roundness_result& r, const g::RoundnessEvaluation& e) {
  EXPECT_EQ(r.n_points, e.n_points);
  EXPECT_EQ(r.n_defined, e.defined_count());
  const auto& ls = *e.least_squares;
  expect_same(r.ls, ls.center, ls.radius, ls.ron, ls.contacts);
  const auto& mz = *e.minimum_zone;
  std::vector<std::size_t> mz_contacts = mz.outer_contacts;
  mz_contacts.insert(mz_contacts.end(), mz.inner_contacts.begin(), mz.inner_contacts.end());
  expect_same(r.mz, mz.center, 0.5 * (mz.inner_radius + mz.outer_radius), mz.ron, mz_contacts);
  EXPECT_EQ(r.mz.inner_radius, mz.inner_radius);
  EXPECT_EQ(r.mz.outer_radius, mz.outer_radius);
  EXPECT_EQ(r.mz.n_outer_contacts, mz.outer_contacts.size());
  const auto& mi = *e.maximum_inscribed;
  expect_same(r.mi, mi.center, mi.radius, mi.ron, mi.contacts);
  const auto& mc = *e.minimum_circumscribed;
  expect_same(r.mc, mc.center, mc.radius, mc.ron, mc.contacts);
  EXPECT_EQ(r.mz.verified, 1);
  EXPECT_EQ(r.mi.verified, 1);
  EXPECT_EQ(r.mc.verified, 1);
}

g::RoundnessEvaluation engine(const std::vector<g::Point2>& points, double cutoff) {
  g::RoundnessRequest request;
  if (cutoff > 0.0) request.filter_cutoff_upr = cutoff;
  return g::evaluate_roundness(points, request);
}

TEST(CApi, SameAsTheEngineOnNoisyLobedRings) {
  for (std::uint64_t seed = 1; seed <= 6; ++seed) {
    const auto points = vcmm::test::lobed_noisy_ring(500 + 300 * seed, seed);
    for (double cutoff : {0.0, 50.0, 150.0}) {
      SCOPED_TRACE("seed " + std::to_string(seed) + ", cut-off " + std::to_string(cutoff));
      std::vector<double> filtered;
      const vcmm_roundness_result r = call(points, cutoff, &filtered);
      const g::RoundnessEvaluation e = engine(points, cutoff);
      expect_same(r, e);
      const std::vector<g::Point2>& profile = cutoff > 0.0 ? e.filtered_points : points;
      ASSERT_EQ(filtered.size(), 2 * profile.size());
      for (std::size_t i = 0; i < profile.size(); ++i) {
        EXPECT_EQ(filtered[2 * i], profile[i].x);
        EXPECT_EQ(filtered[2 * i + 1], profile[i].y);
      }
    }
  }
}

TEST(CApi, InvariantUnderPermutationOfThePoints) {
  auto points = vcmm::test::lobed_noisy_ring(900, 42);
  const vcmm_roundness_result a = call(points, 50.0);
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::shuffle(order.begin(), order.end(), std::mt19937_64(7));
  std::vector<g::Point2> shuffled(points.size());
  for (std::size_t i = 0; i < order.size(); ++i) shuffled[i] = points[order[i]];
  const vcmm_roundness_result b = call(shuffled, 50.0);
  // The exact circles agree to a few ulps (the filter's and the LS fit's sums run in another
  // order) and touch the same points; MZ's outer and inner contact sets are compared apart.
  const double ulp = std::nextafter(85.5, 100.0) - 85.5;
  for (auto [x, y] : {std::pair{&a.mz, &b.mz}, {&a.mi, &b.mi}, {&a.mc, &b.mc}, {&a.ls, &b.ls}}) {
    EXPECT_NEAR(x->ront, y->ront, 32 * ulp);
    EXPECT_NEAR(x->center_x, y->center_x, 12 * ulp);
    EXPECT_NEAR(x->center_y, y->center_y, 12 * ulp);
    EXPECT_NEAR(x->radius, y->radius, 16 * ulp);
    ASSERT_EQ(x->n_contacts, y->n_contacts);
    ASSERT_EQ(x->n_outer_contacts, y->n_outer_contacts);
    auto set = [&](const vcmm_circle* c, std::size_t from, std::size_t to, bool remap) {
      std::vector<std::size_t> v;
      for (std::size_t i = from; i < to; ++i) v.push_back(remap ? order[c->contacts[i]] : c->contacts[i]);
      std::sort(v.begin(), v.end());
      return v;
    };
    const std::size_t k = x->n_outer_contacts;
    EXPECT_EQ(set(x, 0, k, false), set(y, 0, k, true));
    EXPECT_EQ(set(x, k, x->n_contacts, false), set(y, k, y->n_contacts, true));
  }
}

TEST(CApi, PartialArcReportsEachCircleOnItsOwn) {
  std::vector<g::Point2> arc;
  for (int k = 0; k < 200; ++k) {
    const double t = 1.2 * k / 200.0;  // ~69°
    arc.push_back({10.0 * std::cos(t), 10.0 * std::sin(t)});
  }
  const std::vector<double> xy = interleave(arc);
  vcmm_roundness_result r{};
  r.struct_size = sizeof r;
  char error[256];
  ASSERT_EQ(vcmm_roundness(xy.data(), arc.size(), nullptr, &r, nullptr, error, sizeof error),
            VCMM_OK)
      << error;
  const g::RoundnessEvaluation e = engine(arc, 0.0);
  EXPECT_EQ(r.n_defined, e.defined_count());
  EXPECT_EQ(r.closed, 0);
  EXPECT_NEAR(r.covered_deg, 1.2 * 199.0 / 200.0 * 180.0 / M_PI, 1e-9);
  EXPECT_EQ(r.mi.defined, 0);
  EXPECT_EQ(std::string(r.mi.reason), e.undefined.at(g::ReferenceCircle::maximum_inscribed)
                                          .substr(0, VCMM_REASON_SIZE - 1));
  EXPECT_EQ(r.mc.caution, 1);
}

}  // namespace
