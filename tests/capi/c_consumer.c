/* tests/capi/c_consumer.c — a plain C11 program using vcmm's C interface as embedding
 * software would (compiled as C with -Wall -Wextra -pedantic -Werror). Exits 0 when every
 * check holds, 1 naming the first that failed. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "vcmm/vcmm_c.h"

static int failures = 0;

#define CHECK(cond)                                                      \
  do {                                                                   \
    if (!(cond)) {                                                       \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                        \
    }                                                                    \
  } while (0)

static const double kPi = 3.14159265358979323846;

/* n points of r(θ) = radius + amplitude·cos(3θ) at θ_k = span·k/n (span 2π: a closed ring),
 * centred at (cx, cy). */
static void trilobe(double* xy, size_t n, double span, double radius, double amplitude,
                    double cx, double cy) {
  for (size_t k = 0; k < n; ++k) {
    const double t = span * (double)k / (double)n;
    const double r = radius + amplitude * cos(3.0 * t);
    xy[2 * k] = cx + r * cos(t);
    xy[2 * k + 1] = cy + r * sin(t);
  }
}

static double radial(const double* xy, size_t i, double cx, double cy) {
  return hypot(xy[2 * i] - cx, xy[2 * i + 1] - cy);
}

int main(void) {
  enum { n = 720 };
  static double xy[2 * n], filtered[2 * n];
  const double radius = 85.5, amplitude = 2e-4, cx = 600.0, cy = -250.0;
  char error[512];
  vcmm_roundness_options options;
  vcmm_roundness_result result;
  vcmm_status s;

  CHECK(strlen(vcmm_version()) > 0);
  CHECK(strcmp(vcmm_status_string(VCMM_ERROR_INVALID_INPUT), "invalid input") == 0);

  /* A closed three-lobed ring: MZ = 2a with 2 + 2 contacts on peaks and valleys, MI = R − a,
   * MC = R + a, all certified and verified. */
  trilobe(xy, n, 2.0 * kPi, radius, amplitude, cx, cy);
  vcmm_roundness_options_init(&options);
  result.struct_size = sizeof result;
  s = vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_OK);
  CHECK(error[0] == '\0');
  CHECK(result.n_points == n && result.n_defined == 4 && result.closed == 1);
  CHECK(fabs(result.covered_deg - 359.5) < 1e-9);
  CHECK(result.ls.defined && result.mz.defined && result.mi.defined && result.mc.defined);
  CHECK(fabs(result.mz.ront - 2.0 * amplitude) < 1e-10);
  CHECK(fabs(result.mz.outer_radius - (radius + amplitude)) < 1e-10);
  CHECK(fabs(result.mi.radius - (radius - amplitude)) < 1e-10);
  CHECK(fabs(result.mc.radius - (radius + amplitude)) < 1e-10);
  CHECK(fabs(result.ls.center_x - cx) < 1e-9 && fabs(result.ls.center_y - cy) < 1e-9);
  CHECK(result.mz.n_contacts == 4 && result.mz.n_outer_contacts == 2);
  for (size_t i = 0; i < result.mz.n_contacts; ++i) {
    const double want = i < 2 ? radius + amplitude : radius - amplitude;
    CHECK(result.mz.contacts[i] < n);
    CHECK(fabs(radial(xy, result.mz.contacts[i], cx, cy) - want) < 1e-10);
  }
  CHECK(result.mz.verified == 1 && result.mi.verified == 1 && result.mc.verified == 1);
  CHECK(result.ls.verified == -1);
  CHECK(result.mz.global_optimum == 1 && result.mc.global_optimum == 1);
  CHECK(result.mz.reason[0] == '\0' && result.mi.caution == 0);

  /* Defaults by NULL options; verification off. */
  s = vcmm_roundness(xy, n, NULL, &result, NULL, NULL, 0);
  CHECK(s == VCMM_OK && result.n_defined == 4);
  options.verify = 0;
  options.circles = VCMM_CIRCLE_MZ;
  s = vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_OK && result.n_defined == 1 && result.mz.verified == -1);
  CHECK(!result.ls.requested && !result.mi.requested && result.ls.radius == 0.0);

  /* Filtered at 50 UPR: the 3-lobe form passes (gain ~0.9989), the filtered profile is
   * returned and the contacts refer to it. */
  vcmm_roundness_options_init(&options);
  options.filter_cutoff_upr = 50.0;
  s = vcmm_roundness(xy, n, &options, &result, filtered, error, sizeof error);
  CHECK(s == VCMM_OK && result.filter_cutoff_upr == 50.0 && result.open_profile_filter == 0);
  CHECK(fabs(result.mz.ront - 2.0 * amplitude) < 2e-6);
  CHECK(result.mz.verified == 1);
  CHECK(fabs(radial(filtered, result.mz.contacts[0], result.mz.center_x, result.mz.center_y) -
             result.mz.outer_radius) < 1e-9);

  /* A 170° arc: MI does not exist (reason given), MC exists with a caution, status OK. */
  trilobe(xy, n, 170.0 * kPi / 180.0, radius, amplitude, cx, cy);
  vcmm_roundness_options_init(&options);
  s = vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_OK && result.closed == 0 && result.covered_deg < 171.0);
  CHECK(!result.mi.defined && strlen(result.mi.reason) > 0);
  CHECK(result.mc.defined && result.mc.caution == 1 && strstr(result.mc.reason, "180") != NULL);
  CHECK(result.n_defined == 3);

  /* Only MI on the arc: nothing defined → VCMM_ERROR_UNDEFINED, the reason in the result. */
  options.circles = VCMM_CIRCLE_MI;
  s = vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_ERROR_UNDEFINED && result.n_defined == 0 && strlen(error) > 0);
  CHECK(result.mi.requested && !result.mi.defined && strlen(result.mi.reason) > 0);

  /* Bad input: a NaN coordinate is named; too few points; collinear points. */
  trilobe(xy, n, 2.0 * kPi, radius, amplitude, cx, cy);
  xy[2 * 17 + 1] = nan("");
  vcmm_roundness_options_init(&options);
  s = vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_ERROR_INVALID_INPUT && strstr(error, "17") != NULL);
  s = vcmm_roundness(xy, 2, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_ERROR_INVALID_INPUT);
  for (size_t k = 0; k < 10; ++k) { xy[2 * k] = (double)k; xy[2 * k + 1] = 2.0 * (double)k; }
  s = vcmm_roundness(xy, 10, &options, &result, NULL, error, sizeof error);
  CHECK(s == VCMM_ERROR_INVALID_INPUT && strstr(error, "collinear") != NULL);

  /* Caller mistakes: null pointers, wrong sizes, bad options; a short error buffer is cut
   * and 0-terminated. */
  trilobe(xy, n, 2.0 * kPi, radius, amplitude, cx, cy);
  CHECK(vcmm_roundness(xy, n, &options, NULL, NULL, error, sizeof error) ==
        VCMM_ERROR_INVALID_ARGUMENT);
  CHECK(vcmm_roundness(NULL, n, &options, &result, NULL, error, sizeof error) ==
        VCMM_ERROR_INVALID_ARGUMENT);
  result.struct_size = 7;
  CHECK(vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error) ==
        VCMM_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(error, "struct_size") != NULL);
  result.struct_size = sizeof result;
  options.circles = 0;
  CHECK(vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error) ==
        VCMM_ERROR_INVALID_ARGUMENT);
  options.circles = VCMM_CIRCLE_ALL;
  options.filter_cutoff_upr = -1.0;
  CHECK(vcmm_roundness(xy, n, &options, &result, NULL, error, sizeof error) ==
        VCMM_ERROR_INVALID_ARGUMENT);
  options.filter_cutoff_upr = nan("");
  {
    char tiny[8];
    memset(tiny, 'x', sizeof tiny);
    CHECK(vcmm_roundness(xy, n, &options, &result, NULL, tiny, sizeof tiny) ==
          VCMM_ERROR_INVALID_ARGUMENT);
    CHECK(tiny[7] == '\0' && strlen(tiny) == 7);
  }

  if (failures == 0) printf("vcmm C interface: all checks passed (vcmm %s)\n", vcmm_version());
  return failures == 0 ? 0 : 1;
}
