// tests/geometry/oracle_crosscheck_test.cpp — the fitters against the exhaustive exact
// oracle on thousands of small point sets (n = 3…12) over regimes that include the hard
// cases: uniform random, points on a circle perturbed by ±1e-12 relative, small integer
// grids (duplicates and many co-circular quadruples), duplicated points, nearly collinear
// points, points far from the origin (~1e3) with 1e-6 structure, sparse lobed rings.
//
// Agreement is exact: the fitter's contact set (duplicates mapped to their lowest index)
// must be one of the oracle's optimal sets, which fixes the exact centre and radii; and the
// certificate must pass verify(). Where the oracle finds no optimum of the documented form
// the fitter must throw UndefinedResult. Every failure prints the regime, n, seed and the
// points as exact hexadecimal literals, so it can be replayed.
//
// A first suite needs no fitter: it checks verify() against the oracle (independently
// coded predicates) — every oracle local optimum verifies as local; as global exactly when
// it is the oracle's optimum.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "support/exhaustive_oracle.h"
#include "support/test_profiles.h"
#include "vcmm/geometry/certificate.h"
#include "vcmm/geometry/maximum_inscribed.h"
#include "vcmm/geometry/minimum_circumscribed.h"
#include "vcmm/geometry/minimum_zone.h"

namespace vcmm::test {
namespace {

using namespace vcmm::geometry;

// ---- regimes -----------------------------------------------------------------------------

enum class Regime {
  uniform,
  perturbed_circle,
  integer_grid,
  duplicated,
  nearly_collinear,
  far_from_origin,
  sparse_ring,
};
constexpr Regime kRegimes[] = {Regime::uniform,          Regime::perturbed_circle,
                               Regime::integer_grid,     Regime::duplicated,
                               Regime::nearly_collinear, Regime::far_from_origin,
                               Regime::sparse_ring};

const char* name(Regime r) {
  switch (r) {
    case Regime::uniform: return "uniform";
    case Regime::perturbed_circle: return "perturbed_circle";
    case Regime::integer_grid: return "integer_grid";
    case Regime::duplicated: return "duplicated";
    case Regime::nearly_collinear: return "nearly_collinear";
    case Regime::far_from_origin: return "far_from_origin";
    case Regime::sparse_ring: return "sparse_ring";
  }
  return "?";
}

bool all_collinear(const std::vector<Point2>& p) {
  // Exact enough for generation: the sets are rejected by the fitters' exact test anyway;
  // here a set is regenerated when its distinct points are fewer than 3 or collinear.
  std::vector<Point2> d;
  for (const Point2& q : p)
    if (std::find(d.begin(), d.end(), q) == d.end()) d.push_back(q);
  if (d.size() < 3) return true;
  for (std::size_t k = 2; k < d.size(); ++k) {
    const long double v = (static_cast<long double>(d[1].x) - d[0].x) * (d[k].y - d[0].y) -
                          (static_cast<long double>(d[1].y) - d[0].y) * (d[k].x - d[0].x);
    if (v != 0) return false;
  }
  return true;
}

std::vector<Point2> generate(Regime regime, std::size_t n, std::uint64_t seed) {
  std::uint64_t s = seed * 0xD1B54A32D192ED03ULL + static_cast<std::uint64_t>(regime) * 977 + n;
  std::vector<Point2> p;
  for (int attempt = 0; attempt < 100; ++attempt) {
    p.clear();
    switch (regime) {
      case Regime::uniform:
        p = random_points(n, seed * 131 + n);
        break;
      case Regime::perturbed_circle: {
        const Point2 c{0.25 * uniform01(s), -0.5 * uniform01(s)};
        for (std::size_t i = 0; i < n; ++i) {
          const double t = 2 * std::numbers::pi * uniform01(s);
          const double r = 1.0 + 1e-12 * (2 * uniform01(s) - 1);
          p.push_back({c.x + r * std::cos(t), c.y + r * std::sin(t)});
        }
        break;
      }
      case Regime::integer_grid: {
        // 5×5 and (odd seeds) 4×3 grids: duplicates, co-circular quadruples, and sets
        // whose zone width only tends to its infimum (no finite MZ).
        const double w = seed % 2 ? 4 : 5, h = seed % 2 ? 3 : 5;
        for (std::size_t i = 0; i < n; ++i)
          p.push_back({std::floor(w * uniform01(s)) - 2, std::floor(h * uniform01(s)) - 2});
        break;
      }
      case Regime::duplicated: {
        const std::size_t m = std::max<std::size_t>(3, n - n / 3);
        auto base = random_points(m, seed * 7 + n);
        for (std::size_t i = 0; i < n; ++i) {
          const std::size_t pick = i < m ? i : static_cast<std::size_t>(uniform01(s) * static_cast<double>(m));
          p.push_back(base[std::min(pick, m - 1)]);
        }
        for (std::size_t i = n; i > 1; --i)  // deterministic shuffle
          std::swap(p[i - 1], p[static_cast<std::size_t>(uniform01(s) * static_cast<double>(i)) % i]);
        break;
      }
      case Regime::nearly_collinear:
        for (std::size_t i = 0; i < n; ++i) {
          const double x = uniform01(s);
          p.push_back({x, 0.3 * x + 1e-9 * (2 * uniform01(s) - 1)});
        }
        break;
      case Regime::far_from_origin:
        for (std::size_t i = 0; i < n; ++i)
          p.push_back({1000 + 1e-6 * uniform01(s), -1000 + 1e-6 * uniform01(s)});
        break;
      case Regime::sparse_ring: {
        RingSpec spec;
        spec.radius = 10;
        spec.n = n;
        spec.harmonics = {{2, 0.02, 0.3}, {3, 0.01, 1.1}};
        spec.noise_sigma = 0.002;
        spec.angle_jitter = 0.5;
        spec.seed = seed * 31 + n;
        p = ring_profile(spec);
        break;
      }
    }
    if (!all_collinear(p)) return p;
    seed += 1000003;
  }
  return p;
}

struct Case {
  Regime regime;
  std::size_t n;
  std::uint64_t seed;
  std::vector<Point2> pts;
};

std::string describe(const Case& c) {
  std::ostringstream os;
  os << "regime=" << name(c.regime) << " n=" << c.n << " seed=" << c.seed
     << " points=" << cpp_literal(c.pts);
  return os.str();
}

/// seeds_per_size seeds for every regime and n = 3…12.
std::vector<Case> all_cases(std::uint64_t seeds_per_size) {
  std::vector<Case> cases;
  for (Regime r : kRegimes)
    for (std::size_t n = 3; n <= 12; ++n)
      for (std::uint64_t seed = 1; seed <= seeds_per_size; ++seed)
        cases.push_back({r, n, seed, generate(r, n, seed)});
  return cases;
}

// Counts per suite: 560 sets for the self-check, 2800 per fitter; the three suite files
// together take ~6 s of CPU (Release), within the 20 s budget.
constexpr std::uint64_t kSeedsSelfCheck = 8;
constexpr std::uint64_t kSeedsFitters = 40;
/// Failures printed in full per suite: 12, or VCMM_ORACLE_MAX_REPORTED from the environment.
int max_reported() {
  const char* env = std::getenv("VCMM_ORACLE_MAX_REPORTED");
  return env ? std::atoi(env) : 12;
}

// ---- certificates from exact values --------------------------------------------------------

Point2 to_point(const RationalPoint& p) { return {CGAL::to_double(p.x), CGAL::to_double(p.y)}; }
double root(const Rational& q) { return std::sqrt(CGAL::to_double(q)); }

MinimumZoneCircle zone_certificate(const ZoneSupport& z, bool global) {
  MinimumZoneCircle mz;
  mz.center = to_point(z.center);
  mz.outer_radius = root(z.outer2);
  mz.inner_radius = root(z.inner2);
  mz.outer_contacts = {z.outer[0], z.outer[1]};
  mz.inner_contacts = {z.inner[0], z.inner[1]};
  const double t = mz.outer_radius - mz.inner_radius;
  mz.ron = {t, t / 2, t / 2, t / 4};
  mz.certificate.optimality = global ? Optimality::global : Optimality::local;
  return mz;
}

RoundnessParameters about(const std::vector<Point2>& pts, Point2 c, double ref) {
  double lo = 1e300, hi = -1e300;
  for (const Point2& p : pts) {
    const double d = std::hypot(p.x - c.x, p.y - c.y) - ref;
    lo = std::min(lo, d);
    hi = std::max(hi, d);
  }
  return {hi - lo, std::max(0.0, hi), std::max(0.0, -lo), 0.0};
}

std::vector<std::size_t> representatives(std::span<const Point2> pts,
                                         std::vector<std::size_t> idx) {
  for (auto& i : idx)
    if (i < pts.size()) i = representative(pts, i);
  std::sort(idx.begin(), idx.end());
  return idx;
}

class Failures {
 public:
  explicit Failures(const char* suite) : suite_(suite) {}
  void add(const Case& c, const std::string& what) {
    ++count_;
    if (count_ <= max_reported()) ADD_FAILURE() << suite_ << ": " << what << "\n  " << describe(c);
  }
  int count() const { return count_; }
  ~Failures() {
    if (count_ > max_reported())
      ADD_FAILURE() << suite_ << ": " << count_ << " failures in all (first " << max_reported()
                    << " shown)";
  }

 private:
  const char* suite_;
  int count_ = 0;
};

// ---- verify() against the oracle (no fitter needed) ------------------------------------------

TEST(OracleSelfCheck, VerifyAcceptsExactlyTheOracleOptima) {
  Failures fail("self-check");
  std::size_t mz_locals = 0, mi_locals = 0, undefined_mz = 0;
  for (const Case& c : all_cases(kSeedsSelfCheck)) {
    const auto mz = oracle_minimum_zone(c.pts);
    if (mz.zero_width) {
      // Any 3 distinct points of the circle make the certificate.
      std::vector<std::size_t> three;
      for (std::size_t i = 0; i < c.pts.size() && three.size() < 3; ++i)
        if (representative(c.pts, i) == i) three.push_back(i);
      MinimumZoneCircle cert;
      cert.center = to_point(mz.center);
      cert.outer_radius = cert.inner_radius = root(mz.outer2);
      cert.outer_contacts = cert.inner_contacts = three;
      cert.certificate.optimality = Optimality::global;
      if (auto v = verify(c.pts, cert); !v) fail.add(c, "zero-width certificate rejected: " + v.reason);
    }
    if (mz.status == OracleStatus::undefined) ++undefined_mz;
    for (const ZoneSupport& z : mz.locals) {
      ++mz_locals;
      const bool optimal =
          mz.status == OracleStatus::defined && !mz.zero_width &&
          compare_sqrt_differences(z.outer2, z.inner2, mz.outer2, mz.inner2) == 0;
      if (auto v = verify(c.pts, zone_certificate(z, false)); !v)
        fail.add(c, "MZ local minimum rejected as local: " + v.reason);
      const auto g = verify(c.pts, zone_certificate(z, true));
      if (g.valid != optimal)
        fail.add(c, std::string("MZ global claim ") + (g.valid ? "accepted" : "rejected") +
                        " for a local minimum that is " + (optimal ? "" : "not ") +
                        "the oracle's optimum: " + g.reason);
    }
    const auto mc = oracle_minimum_circumscribed(c.pts);
    for (const auto& s : mc.supports) {
      MinimumCircumscribedCircle cert;
      cert.center = to_point(mc.center);
      cert.radius = root(mc.radius2);
      cert.contacts = s;
      cert.ron = about(c.pts, cert.center, cert.radius);
      cert.certificate.optimality = Optimality::global;
      if (auto v = verify(c.pts, cert); !v) fail.add(c, "MC support rejected: " + v.reason);
    }
    if (mc.supports.empty()) fail.add(c, "oracle found no MC support");
    const auto mi = oracle_maximum_inscribed(c.pts);
    for (const auto& l : mi.locals) {
      ++mi_locals;
      MaximumInscribedCircle cert;
      cert.center = to_point(l.center);
      cert.radius = root(l.radius2);
      cert.contacts = l.contacts;
      cert.ron = about(c.pts, cert.center, cert.radius);
      cert.ron.ronv = 0;
      if (auto v = verify(c.pts, cert); !v) fail.add(c, "MI local maximum rejected: " + v.reason);
      cert.certificate.optimality = Optimality::global;
      const bool optimal = mi.status == OracleStatus::defined && l.radius2 == mi.radius2;
      const auto g = verify(c.pts, cert);
      if (g.valid != optimal)
        fail.add(c, std::string("MI global claim ") + (g.valid ? "accepted" : "rejected") +
                        " for a local maximum that is " + (optimal ? "" : "not ") +
                        "the oracle's optimum: " + g.reason);
    }
  }
  std::cout << "[ self-check ] MZ local minima " << mz_locals << " (sets without a finite MZ: "
            << undefined_mz << "), MI local maxima " << mi_locals << "\n";
}

// ---- the fitters against the oracle -----------------------------------------------------------

TEST(OracleCrosscheck, MinimumZone) {
  Failures fail("minimum_zone_circle");
  std::size_t agreed = 0, undefined = 0, zero = 0;
  for (const Case& c : all_cases(kSeedsFitters)) {
    const auto oracle = oracle_minimum_zone(c.pts);
    MinimumZoneCircle mz;
    try {
      mz = minimum_zone_circle(c.pts);
    } catch (const UndefinedResult& e) {
      if (oracle.status == OracleStatus::undefined) {
        ++undefined;
        continue;
      }
      fail.add(c, std::string("threw UndefinedResult but the oracle has an optimum: ") + e.what());
      continue;
    } catch (const std::exception& e) {
      fail.add(c, std::string("threw: ") + e.what());
      continue;
    }
    if (oracle.status != OracleStatus::defined) {
      fail.add(c, "returned a zone but no finite minimum exists (" + oracle.explanation + ")");
      continue;
    }
    if (auto v = verify(c.pts, mz); !v) {
      fail.add(c, "certificate rejected: " + v.reason);
      continue;
    }
    if (oracle.zero_width) {
      if (mz.outer_contacts.size() != 3) fail.add(c, "oracle: zero width; fitter: a 2+2 zone");
      else ++zero;
      continue;
    }
    const auto outer = representatives(c.pts, mz.outer_contacts);
    const auto inner = representatives(c.pts, mz.inner_contacts);
    bool lowest = true;
    for (std::size_t i : mz.outer_contacts) lowest &= representative(c.pts, i) == i;
    for (std::size_t i : mz.inner_contacts) lowest &= representative(c.pts, i) == i;
    bool found = false;
    for (const ZoneSupport& z : oracle.optima)
      found |= outer == std::vector<std::size_t>{z.outer[0], z.outer[1]} &&
               inner == std::vector<std::size_t>{z.inner[0], z.inner[1]};
    if (!found) {
      std::ostringstream os;
      os << "contacts outer {" << outer[0] << "," << outer[1] << "} inner {" << inner[0] << ","
         << inner[1] << "} are not an optimal set; oracle width "
         << root(oracle.outer2) - root(oracle.inner2) << " with outer {"
         << oracle.optima[0].outer[0] << "," << oracle.optima[0].outer[1] << "} inner {"
         << oracle.optima[0].inner[0] << "," << oracle.optima[0].inner[1]
         << "}; fitter width " << mz.ron.ront;
      fail.add(c, os.str());
      continue;
    }
    if (!lowest) fail.add(c, "a duplicated contact is not reported by its lowest index");
    ++agreed;
  }
  std::cout << "[ MZ ] agreed " << agreed << " (zero width " << zero << "), undefined "
            << undefined << ", failures " << fail.count() << "\n";
}

// Sets found by searching small integer grids with the oracle: every local minimum is wider
// than the convex hull, so inf f = W is approached only as the centre goes to infinity (a
// numeric search confirms: best f found 0.7071071 > W = 0.7071068 at |c| ~ 6e5). Regression
// inputs for UndefinedResult.
TEST(OracleCrosscheck, MinimumZoneWithoutFiniteMinimumThrows) {
  const std::vector<std::vector<Point2>> sets = {
      {{1, 2}, {0, 2}, {3, 0}, {2, 1}, {1, 1}},
      {{3, 0}, {0, 2}, {2, 1}, {1, 1}},
      {{0, 0}, {2, 2}, {0, 1}, {1, 2}, {2, 2}, {1, 1}},
  };
  for (const auto& pts : sets) {
    SCOPED_TRACE(cpp_literal(pts));
    EXPECT_EQ(oracle_minimum_zone(pts).status, OracleStatus::undefined);
    try {
      const MinimumZoneCircle mz = minimum_zone_circle(pts);
      ADD_FAILURE() << "returned a zone of width " << mz.ron.ront << " (contacts outer "
                    << mz.outer_contacts[0] << ", " << mz.outer_contacts[1] << "); verify: "
                    << verify(pts, mz).reason;
    } catch (const UndefinedResult&) {
    } catch (const std::exception& e) {
      ADD_FAILURE() << "threw " << e.what();
    }
  }
}

TEST(OracleCrosscheck, MinimumCircumscribed) {
  Failures fail("minimum_circumscribed_circle");
  std::size_t agreed = 0;
  for (const Case& c : all_cases(kSeedsFitters)) {
    const auto oracle = oracle_minimum_circumscribed(c.pts);
    MinimumCircumscribedCircle mc;
    try {
      mc = minimum_circumscribed_circle(c.pts);
    } catch (const std::exception& e) {
      fail.add(c, std::string("threw: ") + e.what());
      continue;
    }
    if (auto v = verify(c.pts, mc); !v) {
      fail.add(c, "certificate rejected: " + v.reason);
      continue;
    }
    if (mc.certificate.optimality != Optimality::global)
      fail.add(c, "the MC certificate should always be global");
    const auto s = representatives(c.pts, mc.contacts);
    if (std::find(oracle.supports.begin(), oracle.supports.end(), s) == oracle.supports.end()) {
      fail.add(c, "contact set is not a support of the oracle's circle");
      continue;
    }
    ++agreed;
  }
  std::cout << "[ MC ] agreed " << agreed << ", failures " << fail.count() << "\n";
}

TEST(OracleCrosscheck, MaximumInscribed) {
  Failures fail("maximum_inscribed_circle");
  std::size_t agreed = 0, undefined = 0, global = 0;
  for (const Case& c : all_cases(kSeedsFitters)) {
    const auto oracle = oracle_maximum_inscribed(c.pts);
    MaximumInscribedCircle mi;
    try {
      mi = maximum_inscribed_circle(c.pts);
    } catch (const UndefinedResult& e) {
      if (oracle.status == OracleStatus::undefined) {
        ++undefined;
      } else {
        fail.add(c, std::string("threw UndefinedResult but the oracle has an optimum: ") +
                        e.what());
      }
      continue;
    } catch (const std::exception& e) {
      fail.add(c, std::string("threw: ") + e.what());
      continue;
    }
    if (oracle.status != OracleStatus::defined) {
      fail.add(c, std::string("returned a circle but the oracle says ") +
                      to_string(oracle.status) + " (" + oracle.explanation + ")");
      continue;
    }
    if (auto v = verify(c.pts, mi); !v) {
      fail.add(c, "certificate rejected: " + v.reason);
      continue;
    }
    const auto s = representatives(c.pts, mi.contacts);
    if (std::find(oracle.supports.begin(), oracle.supports.end(), s) == oracle.supports.end()) {
      std::ostringstream os;
      os << "contacts {" << s[0] << "," << s[1] << "," << s[2]
         << "} are not an optimal set; oracle radius " << root(oracle.radius2)
         << ", fitter radius " << mi.radius;
      fail.add(c, os.str());
      continue;
    }
    global += mi.certificate.optimality == Optimality::global;
    ++agreed;
  }
  std::cout << "[ MI ] agreed " << agreed << " (claimed global " << global << "), undefined "
            << undefined << ", failures " << fail.count() << "\n";
}

}  // namespace
}  // namespace vcmm::test
