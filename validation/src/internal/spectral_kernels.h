// internal/spectral_kernels.h — the two per-trial numeric loops of the spectral trial
// (spectral_trial.cpp) that are neither the FFT nor a reference fit: the in-band harmonics
// from the drawn parameters (a matrix-vector product) and the LS reference's peak-to-valley.
// Each is compiled for AVX-512, AVX2 and the baseline (runtime dispatch) and rounds every
// operation in the same order on all of them (no FMA: the file is compiled with
// -ffp-contract=off, top-level CMakeLists.txt), so a trial's numbers do not depend on the
// machine. Not part of the public API.
#pragma once

#include <cstddef>

namespace vcmm::validation::internal {

/// y = A x for the column-major rows × cols matrix `a` (leading dimension rows), with each
/// y_i summed exactly as Eigen 3.4's column-major GEMV sums `y.noalias() = A * x`: over
/// blocks of columns (all of them when cols < 128, else 16, or 4 when a column exceeds
/// 32000 bytes), within a block in column order from 0, the block sums added to y (from 0),
/// and a single row as Eigen's dot product — so the result is bit for bit Eigen's (spectral_trial_test.cpp checks it), computed with
/// wider vectors where the machine has them.
void column_major_product(const double* a, std::size_t rows, std::size_t cols, const double* x,
                          double* y);

/// max_j (k f_j + s_j) − min_j (k f_j + s_j), each term rounded once (product, then sum).
/// Precondition: n ≥ 1.
double scaled_sum_peak_to_valley(double k, const double* f, const double* s, std::size_t n);

}  // namespace vcmm::validation::internal
