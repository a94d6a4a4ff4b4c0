/* vcmm/vcmm_c.h — the C interface of vcmm's roundness engine (docs/c_api.md).
 *
 * For form-inspection software written in C, C#, Delphi or anything that can call a C
 * function in a shared library (libvcmm_c.so). Plain arrays and structs in and out, no
 * allocation the caller must free, no exception ever crosses this interface: every function
 * returns a vcmm_status and, on failure, writes a message naming the problem into the
 * caller's buffer. The engine is the C++ one (vcmm::geometry::evaluate_roundness): exact
 * ISO 12181-2 reference circles (LS, MZ, MI, MC) with their contacts, optional ISO 16610-21
 * Gaussian filter, and an independent exact check (verify) of every MZ/MI/MC certificate.
 *
 * Units: coordinates in millimetres (any consistent length unit; outputs carry the input's).
 * Thread safety: every function is reentrant; calls on different threads need no locking.
 */
#ifndef VCMM_VCMM_C_H
#define VCMM_VCMM_C_H

#include <stddef.h>

#if defined(_WIN32)
#  if defined(VCMM_C_BUILDING)
#    define VCMM_C_EXPORT __declspec(dllexport)
#  else
#    define VCMM_C_EXPORT __declspec(dllimport)
#  endif
#else
#  define VCMM_C_EXPORT __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/** Version of this interface (the struct layouts below); raised on any incompatible change. */
#define VCMM_C_API_VERSION 1

typedef enum vcmm_status {
  VCMM_OK = 0,
  /** A null pointer, a wrong struct_size or an option value out of range. */
  VCMM_ERROR_INVALID_ARGUMENT = 1,
  /** Points no circle can be fitted to: too few, NaN/inf, all identical or collinear, an arc
   *  with an inner gap wider than half the filter cut-off wavelength. */
  VCMM_ERROR_INVALID_INPUT = 2,
  /** Valid points, but none of the requested circles exists (e.g. only MI on a partial arc);
   *  each circle's reason is in the result. */
  VCMM_ERROR_UNDEFINED = 3,
  VCMM_ERROR_OUT_OF_MEMORY = 4,
  /** A bug in vcmm: please report it with the input. */
  VCMM_ERROR_INTERNAL = 5
} vcmm_status;

/** Bits of vcmm_roundness_options.circles. */
#define VCMM_CIRCLE_LS 1u /* least-squares (LSCI) */
#define VCMM_CIRCLE_MZ 2u /* minimum zone (MZCI) */
#define VCMM_CIRCLE_MI 4u /* maximum inscribed (MICI) */
#define VCMM_CIRCLE_MC 8u /* minimum circumscribed (MCCI) */
#define VCMM_CIRCLE_ALL 15u

/** Most contact points one circle reports (MZ: 2 outer + 2 inner; MI, MC: 2 or 3). */
#define VCMM_MAX_CONTACTS 8
/** Size of the text buffers in vcmm_circle (messages longer than this are cut, 0-terminated). */
#define VCMM_REASON_SIZE 256

typedef struct vcmm_roundness_options {
  /** sizeof(vcmm_roundness_options): set by vcmm_roundness_options_init. */
  size_t struct_size;
  /** Which reference circles to evaluate (VCMM_CIRCLE_* bits); default VCMM_CIRCLE_ALL. */
  unsigned int circles;
  /** Gaussian filter cut-off in undulations per revolution (> 0), or 0 for unfiltered
   *  (default 0). A closed profile takes the closed filter, a partial arc the open one. */
  double filter_cutoff_upr;
  /** 1 (default): re-check every MZ/MI/MC certificate with the independent exact verify(). */
  int verify;
} vcmm_roundness_options;

typedef struct vcmm_circle {
  /** 1 when this circle was requested, else the rest of the struct is zero. */
  int requested;
  /** 1 when the circle exists for this profile; 0 with the reason in `reason` otherwise. */
  int defined;
  double center_x, center_y;
  /** LS, MI, MC: the circle's radius. MZ: the mean radius (r + R) / 2. */
  double radius;
  /** MZ: the inner (r) and outer (R) radii of the zone; other circles: both equal radius. */
  double inner_radius, outer_radius;
  /** ISO 12181-1 roundness parameters about this circle (input length unit). */
  double ront, ronp, ronv, ronq;
  /** Contact indices (0-based, into the input points). MZ: the outer contacts first
   *  (n_outer_contacts of them), then the inner ones. LS: the highest peak and the deepest
   *  valley. */
  size_t contacts[VCMM_MAX_CONTACTS];
  size_t n_contacts;
  size_t n_outer_contacts;
  /** 1 when global optimality is proven (MC, MI and MZ certificates; always 1 for LS). */
  int global_optimum;
  /** Independent exact check of the certificate: 1 passed, 0 failed (reason in `reason`),
   *  -1 not run (LS has no certificate, or options.verify = 0). */
  int verified;
  /** 1 when the circle exists but is not a roundness reference for this profile (MI and MC of
   *  an arc covering less than 180°); the caution is in `reason`. */
  int caution;
  /** Why the circle is undefined, the caution, or why verification failed; "" otherwise. */
  char reason[VCMM_REASON_SIZE];
} vcmm_circle;

typedef struct vcmm_roundness_result {
  /** sizeof(vcmm_roundness_result): set it before the call. */
  size_t struct_size;
  size_t n_points;
  /** The cut-off used (UPR), 0 when unfiltered; 1 when the open-profile filter was used. */
  double filter_cutoff_upr;
  int open_profile_filter;
  /** Angle the profile spans about the first defined centre (degrees, (0, 360]) and whether
   *  it is closed (1) or a partial arc (0). */
  double covered_deg;
  int closed;
  /** How many requested circles exist. */
  size_t n_defined;
  vcmm_circle ls, mz, mi, mc;
} vcmm_roundness_result;

/** The library version, e.g. "0.1.0" (static storage). */
VCMM_C_EXPORT const char* vcmm_version(void);

/** A short English name of a status, e.g. "invalid input" (static storage). */
VCMM_C_EXPORT const char* vcmm_status_string(vcmm_status status);

/** Fills `options` with the defaults: all four circles, unfiltered, verify on. */
VCMM_C_EXPORT void vcmm_roundness_options_init(vcmm_roundness_options* options);

/** Evaluates a roundness profile.
 *  xy: n points interleaved x0, y0, x1, y1, … (2n doubles, mm).
 *  options: NULL for the defaults.
 *  result: caller's struct with struct_size set; filled on VCMM_OK and VCMM_ERROR_UNDEFINED.
 *  filtered_xy: NULL, or room for 2n doubles that receive the filtered profile the circles
 *    were fitted to (the input itself when unfiltered); contact indices refer to it.
 *  error, error_size: NULL/0, or a buffer that receives a 0-terminated message on failure
 *    ("" on success); longer messages are cut.
 *  Returns VCMM_OK when at least one requested circle exists. */
VCMM_C_EXPORT vcmm_status vcmm_roundness(const double* xy, size_t n,
                                         const vcmm_roundness_options* options,
                                         vcmm_roundness_result* result, double* filtered_xy,
                                         char* error, size_t error_size);

#ifdef __cplusplus
}
#endif

#endif /* VCMM_VCMM_C_H */
