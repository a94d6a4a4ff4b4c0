#!/usr/bin/python3
"""Writes a small synthetic output directory in the format of `vcmm validate` / `vcmm demo`
(agreed format v1, see docs/report.md), so that python/vcmm_report.py can be developed and
tested without the C++ programs.

Usage:  /usr/bin/python3 python/make_report_fixture.py OUTDIR [--seed S] [--validate]
        [--locations C,L1,...] [--trials M]

The numbers are random but plausible for a 171 mm ring gauge on a high-accuracy CMM; they
are NOT the output of any model of vcmm and prove nothing about it.  What the fixture does
honour are the relations between the columns that a reader may check:
- mc_mean, u and the 95 % probabilistically symmetric coverage interval are the mean, the
  standard deviation and the 2.5 %/97.5 % quantiles of the samples file written beside them;
- bias = mc_mean - estimate; corrected = estimate - bias (treatment a), refused where it
  would make the roundness negative (correction_applied = false);
- E_n = (value - reference) / sqrt((k u)^2 + (k u_reference)^2) with k = 2, zeta the same
  with standard uncertainties, E_n of treatment (c) with U = k u + |bias|;
- summary.csv and treatments.csv are computed from results.csv;
- the residual profiles are harmonic forms (ring lobing rotating with the orientation, a
  location-dependent 2-lobe machine error) plus noise, with the filtered column produced by
  the ISO 16610-21 Gaussian transmission H(k) = exp(-pi (alpha k / f_c)^2) applied by FFT.
  The roundness estimate is the peak-to-valley of the filtered profile.

`--validate` writes what `vcmm validate` on real data would: no true values, no treatment
(b), no treatments.csv, and empty corrected/En_corrected where the correction was refused.

Everything is written atomically (temporary file in the same directory, then os.replace).
"""

import argparse
import json
import math
import os
import sys
import tempfile

import numpy as np

K = 2.0                      # coverage factor of E_n, as in the campaign file's default
D_TRUE_MM = 171.000120       # true diameter of the synthetic ring
FILTER_UPR = 50.0            # Gaussian filter cut-off of the residual profiles
ALPHA = math.sqrt(math.log(2.0) / math.pi)   # ISO 16610-21 constant

RESULTS_COLUMNS = (
    "id", "location", "orientation_deg", "height", "mode", "measurand", "unit", "reference",
    "u_reference", "estimate", "u", "mc_mean", "bias", "corrected", "u_corrected",
    "correction_applied", "interval_low", "interval_high", "En", "En_corrected", "zeta",
    "zeta_corrected", "corrected_denoised", "En_denoised", "En_inflated", "true_value")
SUMMARY_COLUMNS = ("factor", "level", "measurand", "treatment", "n", "share_abs_En_le_1",
                   "mean_En", "rms_En")
TREATMENTS_COLUMNS = ("measurand", "treatment", "n", "mean_En", "rms_En", "share_abs_En_le_1",
                      "mean_error", "rms_error", "unit")
DEFAULT_LOCATIONS = ("C", "L1", "L2", "L3", "L4", "L5", "L6")


def write_text_atomically(path, text):
    """Writes text to path through a temporary file in the same directory and os.replace."""
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                               dir=directory)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="\n") as f:
            f.write(text)
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def fmt(value):
    """CSV text of a number; None -> empty field."""
    if value is None:
        return ""
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return repr(float(value))


def gaussian_filter(deviation_um):
    """ISO 16610-21 Gaussian filter of a closed equiangular profile, exact by FFT."""
    n = len(deviation_um)
    spectrum = np.fft.rfft(deviation_um)
    k = np.arange(len(spectrum))
    spectrum *= np.exp(-math.pi * (ALPHA * k / FILTER_UPR) ** 2)
    return np.fft.irfft(spectrum, n)


def remove_circle(deviation_um, angle_rad):
    """Removes harmonics 0 and 1 (least-squares circle) so the profile is about a circle."""
    basis = np.column_stack([np.ones_like(angle_rad), np.cos(angle_rad), np.sin(angle_rad)])
    coefficients, *_ = np.linalg.lstsq(basis, deviation_um, rcond=None)
    return deviation_um - basis @ coefficients


def ring_form_um(angle_rad):
    """The ring's own form in its own frame: 3- and 5-lobe, about 0.2 um peak-to-valley."""
    return 0.060 * np.cos(3 * angle_rad + 0.4) + 0.030 * np.cos(5 * angle_rad - 1.1)


def e_n(value, reference, u, u_reference):
    if value is None or u is None:
        return None
    return (value - reference) / math.hypot(K * u, K * u_reference)


def write_fixture(outdir, *, seed=20240605, locations=DEFAULT_LOCATIONS,
                  orientations_deg=(0, 90, 180, 270), heights=("middle",),
                  modes=("scanning", "touch_trigger"), trials=1000, validate=False):
    """Writes the synthetic output directory; returns the list of measurement ids."""
    rng = np.random.default_rng(seed)
    os.makedirs(outdir, exist_ok=True)
    dense = np.linspace(0.0, 2.0 * math.pi, 3600, endpoint=False)
    true_roundness_um = float(np.ptp(remove_circle(ring_form_um(dense), dense)))

    # Location effects: a diameter offset (um) and a 2-lobe machine error (amplitude, phase).
    # The location whose label is the centre gets small ones; some corners get large
    # diameter offsets so that a few |E_n| > 1 appear.
    location_effects = {}
    for i, location in enumerate(locations):
        centre = i == 0
        location_effects[location] = (
            0.0 if centre else float(rng.normal(0.0, 0.10)),
            0.01 if centre else float(rng.uniform(0.03, 0.10)),
            float(rng.uniform(0.0, math.pi)))
    reference = {
        "diameter": (D_TRUE_MM + float(rng.normal(0.0, 0.00002)), 0.00003),
        "roundness": (true_roundness_um + float(rng.normal(0.0, 0.004)), 0.008),
    }

    results = []
    ids = []
    for location in locations:
        d_offset_um, a2_um, phase2 = location_effects[location]
        for orientation in orientations_deg:
            for height in heights:
                for mode in modes:
                    scanning = mode == "scanning"
                    mid = (f"{location}-O{int(orientation):03d}-{height[:3]}-"
                           f"{'scan' if scanning else 'touch'}")
                    ids.append(mid)
                    n_points = 720 if scanning else 36
                    noise_um = 0.030 if scanning else 0.015
                    angle = np.arange(n_points) * (2.0 * math.pi / n_points)
                    profile = (ring_form_um(angle - math.radians(orientation))
                               + a2_um * np.cos(2.0 * (angle - phase2))
                               + rng.normal(0.0, noise_um, n_points))
                    profile = remove_circle(profile, angle)
                    filtered = gaussian_filter(profile)
                    lines = ["angle_deg,deviation_um,filtered_deviation_um"]
                    lines += [f"{math.degrees(a)!r},{float(d)!r},{float(f)!r}"
                              for a, d, f in zip(angle, profile, filtered)]
                    write_text_atomically(os.path.join(outdir, "residuals", mid + ".csv"),
                                          "\n".join(lines) + "\n")

                    estimate = {
                        "diameter": D_TRUE_MM + 1e-3 * (d_offset_um + float(
                            rng.normal(0.0, 2.0 * noise_um / math.sqrt(n_points) + 0.03))),
                        "roundness": float(np.ptp(filtered)),
                    }
                    # Monte Carlo samples: diameter normal about a small bias, roundness
                    # skewed (noise inflates the peak-to-valley): gamma-distributed bias.
                    d_bias_mm = 1e-3 * float(rng.normal(0.0, 0.005))
                    d_u_mm = 1e-3 * float(rng.uniform(0.05, 0.09))
                    d_samples = estimate["diameter"] + d_bias_mm + rng.normal(0.0, d_u_mm,
                                                                              trials)
                    r_bias_target = (0.05 if scanning else 0.12) * float(rng.uniform(0.6, 1.4))
                    if not scanning and rng.uniform() < 0.15:
                        # The model's noise exceeds the real one: the bias exceeds the
                        # estimate and the correction would go negative (refused).
                        r_bias_target = 1.3 * estimate["roundness"]
                    r_samples = (estimate["roundness"]
                                 + rng.gamma(6.0, r_bias_target / 6.0, trials)
                                 + rng.normal(0.0, 0.012, trials))
                    sample_lines = ["diameter_mm,roundness_um"]
                    sample_lines += [f"{float(d)!r},{float(r)!r}"
                                     for d, r in zip(d_samples, r_samples)]
                    write_text_atomically(os.path.join(outdir, "samples", mid + ".csv"),
                                          "\n".join(sample_lines) + "\n")

                    for measurand, samples, unit, true_value in (
                            ("diameter", d_samples, "mm", D_TRUE_MM),
                            ("roundness", r_samples, "um", true_roundness_um)):
                        ref, u_ref = reference[measurand]
                        est = estimate[measurand]
                        mc_mean = float(np.mean(samples))
                        u = float(np.std(samples, ddof=1))
                        low, high = (float(q) for q in np.quantile(samples, [0.025, 0.975]))
                        bias = mc_mean - est
                        corrected = est - bias
                        applied = not (measurand == "roundness" and corrected < 0.0)
                        if applied:
                            u_corrected = u
                        elif validate:
                            corrected, u_corrected = None, None
                        else:
                            corrected, u_corrected = est, u
                        # Treatment (b): bias from the denoised virtual truth, smaller.
                        bias_b = bias * (0.55 if measurand == "roundness" else 1.0)
                        denoised = None if validate else est - bias_b
                        en_inflated = (est - ref) / math.hypot(K * u_ref, K * u + abs(bias))
                        results.append({
                            "id": mid, "location": location, "orientation_deg": orientation,
                            "height": height, "mode": mode, "measurand": measurand,
                            "unit": unit, "reference": ref, "u_reference": u_ref,
                            "estimate": est, "u": u, "mc_mean": mc_mean, "bias": bias,
                            "corrected": corrected, "u_corrected": u_corrected,
                            "correction_applied": applied, "interval_low": low,
                            "interval_high": high,
                            "En": e_n(est, ref, u, u_ref),
                            "En_corrected": e_n(corrected, ref, u_corrected, u_ref),
                            "zeta": (est - ref) / math.hypot(u, u_ref),
                            "zeta_corrected": (None if corrected is None else
                                               (corrected - ref) / math.hypot(u_corrected,
                                                                              u_ref)),
                            "corrected_denoised": denoised,
                            "En_denoised": e_n(denoised, ref, u, u_ref),
                            "En_inflated": en_inflated,
                            "true_value": None if validate else true_value,
                        })

    lines = [",".join(RESULTS_COLUMNS)]
    lines += [",".join(row[c] if isinstance(row[c], str) else fmt(row[c])
                       for c in RESULTS_COLUMNS) for row in results]
    write_text_atomically(os.path.join(outdir, "results.csv"), "\n".join(lines) + "\n")
    write_text_atomically(os.path.join(outdir, "results.json"),
                          json.dumps({"schema": "vcmm.results", "schema_version": 1,
                                      "synthetic": True, "results": results}, indent=1))

    treatment_columns = {"uncorrected": ("En", "estimate"),
                         "corrected": ("En_corrected", "corrected"),
                         "inflated": ("En_inflated", "estimate")}
    if not validate:
        treatment_columns["denoised"] = ("En_denoised", "corrected_denoised")

    def statistics(rows, en_column):
        values = np.array([r[en_column] for r in rows if r[en_column] is not None])
        if len(values) == 0:
            return 0, None, None, None
        return (len(values), float(np.mean(np.abs(values) <= 1.0)), float(np.mean(values)),
                float(np.sqrt(np.mean(values ** 2))))

    summary = [",".join(SUMMARY_COLUMNS)]
    for factor in ("all", "location", "orientation_deg", "height", "mode"):
        levels = ["all"] if factor == "all" else list(dict.fromkeys(
            fmt(r[factor]) if not isinstance(r[factor], str) else r[factor] for r in results))
        for level in levels:
            for measurand in ("diameter", "roundness"):
                for treatment, (en_column, _) in treatment_columns.items():
                    rows = [r for r in results if r["measurand"] == measurand and (
                        factor == "all" or (fmt(r[factor]) if not isinstance(r[factor], str)
                                            else r[factor]) == level)]
                    n, share, mean, rms = statistics(rows, en_column)
                    summary.append(",".join([factor, level, measurand, treatment, fmt(n),
                                             fmt(share), fmt(mean), fmt(rms)]))
    write_text_atomically(os.path.join(outdir, "summary.csv"), "\n".join(summary) + "\n")
    write_text_atomically(os.path.join(outdir, "summary.json"),
                          json.dumps({"schema": "vcmm.summary", "schema_version": 1,
                                      "synthetic": True, "rows": summary[1:]}, indent=1))

    if not validate:
        lines = [",".join(TREATMENTS_COLUMNS)]
        for measurand in ("diameter", "roundness"):
            rows = [r for r in results if r["measurand"] == measurand]
            for treatment, (en_column, value_column) in treatment_columns.items():
                n, share, mean, rms = statistics(rows, en_column)
                errors = np.array([r[value_column] - r["true_value"] for r in rows
                                   if r[value_column] is not None])
                lines.append(",".join([
                    measurand, treatment, fmt(n), fmt(mean), fmt(rms), fmt(share),
                    fmt(float(np.mean(errors))), fmt(float(np.sqrt(np.mean(errors ** 2)))),
                    "mm" if measurand == "diameter" else "um"]))
        write_text_atomically(os.path.join(outdir, "treatments.csv"), "\n".join(lines) + "\n")

    run_info = {
        "generator": "python/make_report_fixture.py (synthetic numbers, not vcmm output)",
        "command": "vcmm " + ("validate" if validate else "demo") + " (simulated)",
        "seed": seed, "trials": trials, "k": K, "coverage_probability": 0.95,
        "reference_circle": "MZ", "filter_cutoff_upr": FILTER_UPR,
        "ring_diameter_mm": 171.0,
        "factors": {"locations": list(locations), "orientations_deg": list(orientations_deg),
                    "heights": list(heights), "modes": list(modes)},
    }
    write_text_atomically(os.path.join(outdir, "run_info.json"),
                          json.dumps(run_info, indent=2) + "\n")
    return ids


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="make_report_fixture.py",
        description="Write a synthetic vcmm validate/demo output directory.")
    parser.add_argument("outdir")
    parser.add_argument("--seed", type=int, default=20240605)
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--locations", default=",".join(DEFAULT_LOCATIONS),
                        help="comma-separated location labels (the first gets the small "
                             "centre errors)")
    parser.add_argument("--validate", action="store_true",
                        help="no truth, no treatment (b), no treatments.csv")
    args = parser.parse_args(argv)
    if args.trials < 10:
        parser.error(f"--trials must be >= 10; got {args.trials}")
    ids = write_fixture(args.outdir, seed=args.seed, trials=args.trials,
                        locations=tuple(args.locations.split(",")), validate=args.validate)
    print(f"wrote {len(ids)} synthetic measurements to {args.outdir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
