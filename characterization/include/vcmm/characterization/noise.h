// vcmm/characterization/noise.h — the random noise of the CMM (by probing mode) and the
// workpiece roughness, from CMM measurements of a calibrated artefact (a ring gauge or any
// round section) and its reference profile from a roundness instrument
// (docs/characterization.md, "Noise and roughness").
//
// Notation. A CMM profile of n points p_i (machine XY, mm) about its least-squares centre c:
// angle θ_i, radial deviation e_i = |p_i − c| − R. Reference profile g(α) (roundness-meter CSV
// `angle_deg,deviation_um`, equiangular; deviation = radius minus mean radius, positive away
// from the centre on inner and outer surfaces alike). The reference angle of machine angle θ
// is α = θ − φ (φ: the machine angle of the reference's 0°, the *phase*). Model:
//   e_i = g(θ_i − φ) + s(θ_i) + r_i + ε_i,
// s the CMM's systematic error (kinematic, probe: low-order in θ), r_i roughness (fixed on the
// track), ε_i noise. The model's noise is isotropic 3D with σ per Cartesian component; its
// radial projection u·ε has exactly the same σ (u a unit vector: var(u·ε) = uᵀσ²Iu = σ²), and
// the tangential part changes the deviation only at second order (σ²/2R ≈ 1e-12 mm).
//
// Scanning (dense, equiangular). d_i = e_i − g(θ_i − φ) holds s + r + ε; the Gaussian low-pass
// L (ISO 16610-21, cut-off f_c, transmission H(k) = 2^−(k/f_c)²) keeps s, the residual
// h = (I − L) d keeps the white part. For white noise w of variance σ² on n equiangular points
// the filter is circulant: in the real Fourier basis (orthonormal, n functions) each harmonic k
// is multiplied by 1 − H(k) (H at min(k, n − k), as geometry::gaussian_filter_closed does), and
// the least-squares circle has already removed harmonics 0 and 1. So
//   Σ h_i² = σ² Σ_j λ_j χ²_1,j,   λ_j = (1 − H(k_j))² (0 for k_j ∈ {0, 1}),
//   E[Σ h_i²] = σ² Λ,  Λ = Σ_j λ_j = Σ_{k=0}^{n−1} (1 − H(min(k, n−k)))²  (k ∉ {0, ±1}),
// i.e. E[(1/n) Σ h²] = σ² (1/n) Σ_k (1 − H(k))²: the estimate is σ̂² = Σ h_i² / Λ. Its
// distribution is a weighted χ²; Satterthwaite's effective degrees of freedom
// ν = (Σ λ_j)² / Σ λ_j² give var(σ̂²) = 2σ⁴/ν and sd(σ̂) ≈ σ/√(2ν) (delta method).
//
// Uncertainty of σ̂. Reported as u(σ̂) = k(ν) σ̂/√(2ν). Because σ̂ is skewed (σ̂²ν/σ² ~ χ²_ν)
// and u is computed from σ̂ itself, the plain k = 1 gives ±2u intervals that cover σ less
// often than a normal ±2u (95.45 %): 91.6 % at ν = 13 (16 touch points). k(ν) ≥ 1 is the
// factor for which P(|σ̂ − σ| ≤ 2u) = 95.45 % exactly under the χ² model
// (sigma_coverage_factor: 1.281 at ν = 13, 1.027 at 100, 1.0007 at 3500), so that
// |error|/u ≤ 2 in about 95 % of calibrations at any ν.
//
// Phase. Given, or estimated on the scan as the φ that minimises the high-pass residual
// energy Σ h² — the only φ the scanning σ needs. Harmonic by harmonic (equiangular points),
//   Σ h²(φ) = Σ((I − L)e)² + Σ((I − L)g_φ)² − 2 C_w(φ),
//   C_w(φ) = Σ_k (1 − H(k))² Re(G_k e^{−ikφ}),  G_k = R_k e^{−ikα_0} F_k,
// with g(α) = Σ_k Re(R_k e^{ik(α−α_0)}), R_k = a_k − i b_k, F_k = Σ_i e_i e^{ikθ_i}; the middle
// term does not depend on φ. C_w is maximised on a grid of 4K steps (a quarter of the
// shortest period, K the highest harmonic), then by golden section within ±1 step. The low orders,
// where the CMM's own systematic errors are as large as the form (and inseparable from it in one
// set-up: that needs reversal), get no weight. Reliability: the correlation peak stands above the
// noise when √E/σ̂ ≥ kPhaseSnr, E = Σ (high-pass of g at the scan angles)²: a noise-only peak
// over the ~4K candidate phases reaches √(2 ln 4K) ≈ 4.3 noise sd; 8 leaves a margin of ~3.7 sd.
// Below it the phase is not determined by the data — and then it hardly matters for the
// scanning σ (the reference has little content above the cut-off); a touch-trigger
// evaluation, which has no filter, then needs it given — unless the scan's systematic profile
// is subtracted as well (next paragraph), which cancels it below the cut-off.
//
// Touch-trigger (sparse, any angles). No filter can act on 16 points: subtract the reference
// radially, fit the least-squares circle (3 parameters) and take σ̂² = Σ ρ_i²/(n − 3),
// ν = n − 3, u(σ̂) = k(ν) σ̂/√(2ν) as above. Alone, the CMM's systematic errors beyond centre
// and radius stay in the residual (with the example model ~0.3 µm: σ̂ ≈ 20 % high). With a scan
// of the same set-up its low-pass part s = L(e − g_φ) — the systematic errors — is subtracted
// too (periodic linear interpolation at the touch angles; s varies over ≳ 2π/(2 f_c), about 36
// steps of a 3600-point scan at 50 UPR). This assumes the low-frequency systematic errors are
// common to both modes (geometry, probe lobing; not scanning dynamics). It also makes the phase
// uncritical below the cut-off: a misaligned reference leaves the same low-order residual in s,
// which cancels,
//   e_t − g_φ − L(e − g_φ) ≈ (I − L)(form + systematic − g_φ),
// so the scan's φ (which minimises exactly the high-pass mismatch) is the right one to use.
// The scan's noise passes into s with per-point variance v = σ̂_scan² (1/n) Σ_k H(k)²
// (k ∉ {0, ±1}), independent between touch points (the filter's kernel, ~2·0.47/f_c turns
// wide, is far narrower than their spacing), so E[Σρ²] = (n − 3)(σ_t² + v) and
// σ̂_t² = Σρ²/(n − 3) − v (v ≈ 0.010 µm² for σ_scan = 0.7 µm, n = 3600, f_c = 50).
//
// Roughness. One scan cannot tell r from ε (both white): σ̂² estimates σ_noise² + σ_rough².
// Two scans of the same track (same angles) can: with d¹, d² as above,
//   the high-pass of d¹ − d² estimates 2σ_noise² (r, s and the reference cancel),
//   the high-pass of (d¹ + d²)/2 estimates σ_rough² + σ_noise²/2,
// and the two are independent (for Gaussian ε of equal variance, ε¹ − ε² ⟂ ε¹ + ε²). So
//   σ̂_noise² = S₋/2,  σ̂_rough² = S₊ − S₋/4,
//   var(σ̂_rough²) = 2 S₊²/ν + 2 (S₋/4)²/ν,  u(σ̂_rough) = u(σ̂_rough²)/(2 σ̂_rough).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <istream>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "vcmm/characterization/consistency.h"
#include "vcmm/geometry/point.h"
#include "vcmm/geometry/roundness_profile.h"

namespace vcmm::characterization {

// ---- the reference profile ----------------------------------------------------------------

/// The roundness-instrument profile of the artefact: a geometry::RoundnessProfile
/// (vcmm/geometry/roundness_profile.h; file format in docs/formats.md) — angles α_j (rad) in
/// [0, 2π), strictly increasing, deviations (mm) = radius minus mean radius, positive away from
/// the centre, source lines for messages. The noise code requires it equiangular on top:
/// α_j = α_0 + 2πj/M for any α_0 ∈ [0, 2π/M).
using ReferenceProfile = geometry::RoundnessProfile;

/// Checks a reference profile (every build): geometry::validate_roundness_profile (sizes, M ≥
/// 8, finite, strictly increasing in [0, 2π), closed), then equiangular: every angle within
/// 1e-3 of a step of the grid α_0 + 2πj/M (a 3600-point trace written with 4 decimals of a
/// degree is within 5e-4 of a step). Throws InvalidInput naming "`caller`: reference", the
/// sample (its file line when the profile was read) and the rule, e.g. "scanning_noise:
/// reference: sample 3: the reference must be equiangular over one turn (8 samples, step 45
/// deg); angle 91 deg, expected 90 deg". O(M).
void validate_reference_profile(const ReferenceProfile& profile, const char* caller);

/// Reads the roundness-meter CSV `angle_deg,deviation_um` with
/// geometry::read_roundness_profile_csv (all its rules: header naming the units, angles in
/// [0, 360), a closing 360° repeat of the 0° sample dropped, messages "source:line: …"), then
/// checks that it is equiangular (validate_reference_profile's rule, messages naming the file
/// line: "ref.csv:3: the reference must be equiangular over one turn …"). Throws InvalidInput.
/// O(M).
ReferenceProfile read_reference_profile_csv(std::istream& in, const std::string& source_name);
/// Opens `path` and reads it as read_reference_profile_csv; an unreadable file is InvalidInput
/// naming the path.
ReferenceProfile read_reference_profile_csv_file(const std::string& path);

/// The reference's trigonometric interpolant at reference angles α (mm), using harmonics
/// 2 … min(⌊(M−1)/2⌋, max_order) (0 and 1, the reference's own centre and radius, carry no
/// form). Exact at the samples up to those harmonics. O(M·K + |α|·K).
std::vector<double> reference_deviation_mm(const ReferenceProfile& profile,
                                           std::span<const double> angle_rad,
                                           int max_order = 1 << 30);

// ---- the variance the low-pass removes -----------------------------------------------------

struct HighPassNoiseFactor {
  double variance_factor = 0.0;           ///< Λ/n = (1/n) Σ_k (1 − H(k))², k ∉ {0, ±1}
  double degrees_of_freedom = 0.0;        ///< ν = (Σ λ)² / Σ λ²
  double low_pass_variance_factor = 0.0;  ///< (1/n) Σ_k H(k)², k ∉ {0, ±1}: white noise in L d
};

/// Λ/n, ν and (1/n) Σ H² of the file comment for n equiangular points and cut-off f_c (UPR).
/// Preconditions (InvalidInput): n ≥ 8, f_c finite in (0, n/2]. O(n).
HighPassNoiseFactor high_pass_noise_factor(std::size_t n, double cutoff_upr);

// ---- estimates ---------------------------------------------------------------------------

/// A standard deviation estimated from a χ²-type sum.
struct SigmaEstimate {
  double sigma_mm = 0.0;
  double u_mm = 0.0;                ///< k(ν) σ̂/√(2ν) (file comment)
  double degrees_of_freedom = 0.0;  ///< ν
};

/// k(ν) of the file comment: the k ≥ 1 with P(|σ̂ − σ| ≤ 2kσ̂/√(2ν)) = erf(√2) (95.45 %) when
/// νσ̂²/σ² ~ χ²_ν, i.e. P(ν/(1+a)² ≤ χ²_ν ≤ ν/(1−a)²) with a = 2k/√(2ν) (upper limit ∞ for
/// a ≥ 1). Solved by bisection on the regularised incomplete gamma function (series /
/// continued fraction, relative accuracy ~1e-12); k to 1e-9. Precondition: ν finite ≥ 1
/// (InvalidInput). Values: 3.634 at ν = 2, 1.281 at 13, 1.027 at 100, 1.0007 at 3500.
/// O(√ν) per evaluation, ~60 evaluations.
double sigma_coverage_factor(double degrees_of_freedom);

/// Threshold of the phase signal-to-noise ratio √E/σ̂ (file comment, "Phase").
inline constexpr double kPhaseSnr = 8.0;

struct ScanNoiseOptions {
  double cutoff_upr = 50.0;         ///< low-pass cut-off f_c (UPR), 0 < f_c ≤ n/2
  std::optional<double> phase_rad;  ///< φ; nullopt: estimated by cross-correlation
};

/// The CMM's low-frequency systematic error profile s = L(e − g_φ) seen in a scan (file
/// comment, "Touch-trigger"), for the touch-trigger evaluation of the same set-up.
struct SystematicProfile {
  std::vector<double> angle_rad;     ///< increasing, within one turn (machine angle)
  std::vector<double> deviation_mm;  ///< s at those angles
  double noise_variance_mm2 = 0.0;   ///< v: variance of the scan noise left in s, per point
};

/// The family-wise level of each outlier test of the noise characterisation. The whole
/// false-refusal level goes to outliers (σ is what is estimated: there is no χ² test), split
/// over the at most three data sets of one characterisation (scan, repeat difference, touch).
inline constexpr double kNoiseOutlierLevel = kFalseRefusalLevel / 3.0;

struct ScanNoiseResult {
  SigmaEstimate sigma;  ///< radial white-noise σ (noise and roughness together: one scan)
  std::size_t points = 0;
  double cutoff_upr = 0.0;
  HighPassNoiseFactor factor;
  double phase_rad = 0.0;  ///< φ used
  bool phase_estimated = false;
  double phase_snr = 0.0;         ///< √E/σ̂ (file comment, "Phase")
  bool phase_determined = false;  ///< given, or estimated with phase_snr ≥ kPhaseSnr
  geometry::Point2 center_mm;     ///< least-squares centre
  double radius_mm = 0.0;
  double raw_rms_mm = 0.0;        ///< rms of e (form + systematic + noise)
  double reference_rms_mm = 0.0;  ///< rms of the reference at the scan angles
  double low_pass_rms_mm = 0.0;   ///< rms of L d: the CMM's systematic part (and drift)
  double high_pass_rms_mm = 0.0;  ///< rms of h (before the Λ/n correction)
  SystematicProfile systematic;   ///< L d: for touch_trigger_noise on the same set-up
  /// Outliers of the high-pass residual h = (I − L)(e − g): each h_i has the variance σ²Λ/n
  /// (circulant filter), tested studentized against the scale of all points, Bonferroni over
  /// the n points at kNoiseOutlierLevel; named "point i (at θ deg)", i 1-based in file order
  /// (consistency.h; a dust particle or a probe bounce would otherwise raise σ̂).
  ConsistencyTest consistency;
};

/// The noise σ of a dense equiangular scan (file comment). `scan`: the profile in machine XY
/// (mm), equiangular about its least-squares centre (every direction within a quarter step of
/// the grid θ_0 ± 2πi/n; a repeated closing point is dropped). The reference is interpolated at
/// θ_i − φ with harmonics up to the scan's ⌊(n−1)/2⌋. The phase, when not given, is the one
/// minimising the high-pass residual (file comment, "Phase"); check phase_determined before
/// reusing it elsewhere. Throws
/// InvalidInput: < 16 points, non-finite, collinear, cut-off outside (0, n/2], not equiangular,
/// invalid reference. Complexity O(n·K) (K reference harmonics), + O(K²) with phase estimation:
/// n = 3600, M = 3600: ~23 ms, ~55 ms with phase estimation; M = 360: ~2 ms / ~4 ms.
ScanNoiseResult scanning_noise(std::span<const geometry::Point2> scan,
                               const ReferenceProfile& reference,
                               const ScanNoiseOptions& options = {});

struct TouchNoiseResult {
  SigmaEstimate sigma;
  std::size_t points = 0;
  double phase_rad = 0.0;
  bool scan_systematics_removed = false;  ///< a scan's SystematicProfile was subtracted
  double scan_noise_variance_mm2 = 0.0;   ///< v subtracted from σ̂² (0 without a profile)
  geometry::Point2 center_mm;
  double radius_mm = 0.0;
  std::vector<double> residuals_mm;  ///< after the reference (and profile) and the circle fit
  /// Outliers of the residuals (studentized with the circle fit's leverages, ν = n − 3,
  /// Bonferroni at kNoiseOutlierLevel), named "point i (at θ deg)" (consistency.h).
  ConsistencyTest consistency;
};

/// The noise σ of sparse touch-trigger points (file comment, "Touch-trigger"): the reference
/// at θ_i − φ and, when given, the systematic profile of a scan of the same set-up at θ_i are
/// subtracted along the radius, the least-squares circle is fitted,
/// σ̂² = max(Σρ²/(n − 3) − v, 0), ν = n − 3. The phase: the scan's when a profile is used,
/// else known from the set-up. Throws InvalidInput: fewer than 5 points (ν ≥ 2), non-finite
/// or collinear points, non-finite phase, invalid reference, a profile with fewer than 8
/// samples, unsorted or non-finite. O(n·K + n log m).
TouchNoiseResult touch_trigger_noise(std::span<const geometry::Point2> points,
                                     const ReferenceProfile& reference, double phase_rad,
                                     const SystematicProfile* scan_systematics = nullptr);

enum class RoughnessStatus {
  identified,       ///< σ̂_rough² ≥ 2 u(σ̂_rough²)
  not_significant,  ///< below that: σ given as the clamped estimate, with an upper bound
};
std::string_view to_string(RoughnessStatus status);

struct RepeatedScanResult {
  SigmaEstimate noise;  ///< from the difference of the scans: free of roughness
  /// σ̂_rough = √max(σ̂_rough², 0); u = u(σ̂²)/(2σ̂) when identified, else √u(σ̂²) (the
  /// delta method fails near 0; √u(σ̂²) is the σ at which one u of variance shows).
  SigmaEstimate roughness;
  RoughnessStatus roughness_status = RoughnessStatus::not_significant;
  double roughness_variance_mm2 = 0.0;    ///< σ̂_rough² (may be negative)
  double roughness_variance_u_mm2 = 0.0;  ///< u(σ̂_rough²)
  double roughness_upper_bound_mm = 0.0;  ///< √max(σ̂_rough² + 2u, 0): ~97.5 % one-sided
  ScanNoiseResult first;                  ///< the first scan alone (σ of noise + roughness)
  /// L of the mean of the two scans minus the reference (v = S₊ (1/n) Σ H²): for touch data.
  SystematicProfile systematic;
  /// Outliers of the high-pass difference of the scans (variance 2σ_n²Λ/n per point), as
  /// ScanNoiseResult::consistency: the point named is in one of the two scans.
  ConsistencyTest difference_consistency;
};

/// Noise and roughness from two scans of the same track (file comment). Both scans must have
/// the same number of points at the same angles about their own centres (within a quarter
/// step; same direction of travel). The phase is estimated on the first scan unless given.
/// Throws as scanning_noise, and InvalidInput when the scans do not match. O(n·K).
RepeatedScanResult repeated_scan_noise(std::span<const geometry::Point2> scan,
                                       std::span<const geometry::Point2> repeat,
                                       const ReferenceProfile& reference,
                                       const ScanNoiseOptions& options = {});

// ---- model sections ------------------------------------------------------------------------

/// What a noise characterisation found, for the model file.
struct NoiseCharacterization {
  std::optional<ScanNoiseResult> scan;         ///< a single scan
  std::optional<RepeatedScanResult> repeated;  ///< a scan and its repeat (then `scan` unset)
  std::optional<TouchNoiseResult> touch;
  std::string scan_source, repeat_source, touch_source, reference_source;  ///< file names
};

/// The model's "noise" section as JSON text: {"source", "scanning_sigma_um",
/// "touch_trigger_sigma_um"} (docs/errormodel.md) from the estimates present; the source
/// string records files, method, ν and u(σ). A mode without data is taken from `fallback`
/// (σ in mm, e.g. the current model's value) and marked so in the source; without data and
/// without fallback the key is left out and a "comment" says the section must be completed
/// (it then does not load on its own). Scanning σ comes from the repeat pair when present
/// (roughness-free), else from the single scan (noise and roughness together: the source says
/// so). Throws InvalidInput if neither scan nor touch data were characterised.
std::string noise_section_json(const NoiseCharacterization& c,
                               std::optional<double> fallback_scanning_sigma_mm = std::nullopt,
                               std::optional<double> fallback_touch_sigma_mm = std::nullopt);

/// The model's "roughness" section {"source", "sigma_um"} when a repeat pair was given;
/// nullopt otherwise (roughness is not identifiable from a single scan).
std::optional<std::string> roughness_section_json(const NoiseCharacterization& c);

/// The whole output of `vcmm characterize noise`: {"noise": …, "roughness": … (repeat pair
/// only), "characterization": {per-data diagnostics: σ, u, ν, phase, centre, rms of the
/// parts; the roughness status or "not identifiable from a single scan"}}.
std::string noise_characterization_json(
    const NoiseCharacterization& c, std::optional<double> fallback_scanning_sigma_mm = std::nullopt,
    std::optional<double> fallback_touch_sigma_mm = std::nullopt,
    bool accepted_inconsistent = false);

}  // namespace vcmm::characterization
