// vcmm/uncertainty/statistics.h — the summary of Monte Carlo samples of a measurand (JCGM 101
// 7.6, 7.7) and the correlation of several measurands (JCGM 102 7.6).
//
// Notation (JCGM 101:2008, GUM Supplement 1): M samples y_1 … y_M of the output quantity Y,
// sorted into y_(1) ≤ … ≤ y_(M) (1-based order statistics); p the coverage probability.
//   estimate             ỹ = (1/M) Σ y_r                                         (7.6)
//   standard uncertainty u(ỹ)² = 1/(M − 1) Σ (y_r − ỹ)²                          (7.6)
//   q                    q = pM if pM is an integer, else the integer part of pM + ½  (7.7.1)
//   probabilistically symmetric interval  [y_(r), y_(r+q)] with r = (M − q)/2 if (M − q)/2 is an
//                        integer, else the integer part of (M − q + 1)/2           (7.7.1)
//   shortest interval    [y_(r*), y_(r*+q)], r* the r in 1 … M − q minimising
//                        y_(r+q) − y_(r); ties go to the smallest r               (7.7.2)
// Both intervals contain q + 1 order statistics; they need 1 ≤ q ≤ M − 1, i.e. enough
// samples for p (M ≥ 11 for p = 0.95, M ≥ 51 for p = 0.99; JCGM 101 7.2 asks for M ≫ 1/(1 − p),
// e.g. 10⁶ for p = 0.95).
//
// Numerics: ỹ by compensated (Neumaier) summation in index order; u by the corrected
// two-pass formula Σ(y − ỹ)² − (Σ(y − ỹ))²/M (Björck; Chan, Golub & LeVeque 1983), also
// compensated. The result is a function of the samples in index order only — the same bits
// for any thread count that produced them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

namespace vcmm::uncertainty {

/// A coverage interval [low, high] for the coverage probability `probability`.
struct CoverageInterval {
  double low = 0, high = 0;
  double probability = 0.95;
};

/// The JCGM 101 summary of the samples of one measurand (notation in the file comment).
struct MeasurandSummary {
  std::uint64_t count = 0;                 ///< M
  double mean = 0;                         ///< ỹ (7.6)
  double standard_uncertainty = 0;         ///< u(ỹ), the sample sd with M − 1 (7.6)
  CoverageInterval probabilistically_symmetric;  ///< JCGM 101 7.7.1
  CoverageInterval shortest;                     ///< JCGM 101 7.7.2
};

/// Summarises `samples` (one measurand, any order) per JCGM 101 7.6–7.7 (file comment).
/// Throws InvalidInput ("summarize: …") if samples is empty, a sample is NaN or ±inf (naming
/// its index), coverage_probability is not in (0, 1), or M is too small for p (q < 1 or
/// q > M − 1; the message gives the least M). Accuracy: mean and u to a few ulp (compensated
/// sums); interval ends are sample values. O(M log M) time (one sort of a copy), O(M) memory.
MeasurandSummary summarize(std::span<const double> samples, double coverage_probability = 0.95);

/// As summarize(), for measurand `measurand` of samples stored trial-major with `q`
/// measurands a trial (trial t, measurand j at samples[t·q + j]). Throws as summarize(), and
/// InvalidInput if q = 0, measurand ≥ q or samples.size() is not a multiple of q.
MeasurandSummary summarize_measurand(std::span<const double> samples, std::size_t q,
                                     std::size_t measurand, double coverage_probability = 0.95);

/// Correlation matrix (row-major q×q) of samples stored trial-major (trial t, measurand j at
/// samples[t*q + j]); JCGM 102 / JCGM 101 style:
///   r_jk = Σ_t (y_tj − ỹ_j)(y_tk − ỹ_k) / √(Σ_t (y_tj − ỹ_j)² · Σ_t (y_tk − ỹ_k)²),
/// two-pass in index order, clamped to [−1, 1]; r_jj = 1. A measurand with zero spread (all
/// samples equal) has no defined correlation: its off-diagonal entries are reported as 0.
/// Throws InvalidInput if q = 0, samples.size() is not a positive multiple of q, there are
/// fewer than 2 trials, or a sample is NaN/±inf (naming trial and measurand). O(M q²).
std::vector<double> correlation_matrix(std::span<const double> samples, std::size_t q);

/// The JCGM 101 7.7.1 index q for M samples and coverage probability p: pM if that is an
/// integer, else ⌊pM + ½⌋ (pM evaluated in double precision). Throws InvalidInput if p is
/// not in (0, 1).
std::uint64_t coverage_index(std::uint64_t sample_count, double coverage_probability);

/// The least M for which summarize() can form both intervals at probability p (1 ≤ q ≤ M − 1).
/// Throws InvalidInput if p is not in (0, 1) or the least M exceeds 2⁶² (p below ~1e-19; no
/// double p < 1 is close enough to 1 for that), naming the count p would need.
std::uint64_t minimum_sample_count(double coverage_probability);

}  // namespace vcmm::uncertainty
