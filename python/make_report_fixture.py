#!/usr/bin/python3
"""Writes a small synthetic output directory in the format of `vcmm validate` / `vcmm demo`
(format v2 with the bias-treatment columns, see docs/report.md and docs/validation.md "Output
directory"), so that python/vcmm_report.py can be developed and tested without the C++
programs.

Usage:  /usr/bin/python3 python/make_report_fixture.py OUTDIR [--seed S] [--trials M]
        [--validate] [--denoised] [--budget] [--bias-treatment shrinkage|paper]
        [--locations C,L1,... [--orientations 0,90,...]]

By default the plan is the demo's: 7 locations at 0° (C, L1-L4, E1, E2; ids like
L1-O000-top-scan) and the ring at the centre C in 4 orientations (C-R000 ... C-R270, so C at
0° is measured twice), x 3 heights x 2 modes = 66 measurements.  --locations (with
--orientations, default 0,90,180,270) gives a full grid instead.

The numbers are random but plausible for a 171 mm ring gauge on a high-accuracy CMM; they
are NOT the output of any model of vcmm and prove nothing about it.  What the fixture does
honour are the relations between the columns that a reader may check:
- mc_mean, u and the 95 % probabilistically symmetric coverage interval are the mean, the
  standard deviation and the 2.5 %/97.5 % quantiles of the samples file written beside them;
- the seed study's treatment (a): bias_paper = mc_mean - estimate, corrected_paper =
  estimate - bias_paper, u_corrected_paper = u sqrt(1 + 1/M); refused where it would make the
  roundness negative (paper_applied = false: the estimate itself, u sqrt-summed with b);
- the default treatment (column `treatment`): the study's for the diameter (u_bias = 0);
  for the roundness "shrinkage" (a bias near the true one, corrected = max(0, estimate -
  bias), u_corrected^2 = u^2 + u_bias^2 + u^2/M) or, with --bias-treatment paper, the study's;
- E_n = (reference - value) / sqrt((k u)^2 + (k u_reference)^2) with k = 2 (the runner's
  sign), zeta the same with standard uncertainties, E_n of treatment (c) with
  U = k u + |bias_paper|; treatment (b) only with --denoised (else its columns are empty);
- summary.csv and treatments.csv are computed from results.csv;
- with --budget, budget.csv: per measurement and error source u and share u_i^2 / sum u_j^2
  (the shares add up to 1), the quadrature sum and its ratio to the full run's u;
- the residual profiles are harmonic forms (ring lobing rotating with the orientation, a
  location-dependent 2-lobe machine error) plus noise, with the filtered column produced by
  the ISO 16610-21 Gaussian transmission H(k) = exp(-pi (alpha k / f_c)^2) applied by FFT.
  The roundness estimate is the peak-to-valley of the filtered profile.

`--validate` writes what `vcmm validate` on real data would: no true values, no
treatments.csv.  write_fixture(..., missing_reference=[(id, measurand), ...]) leaves those
rows without a reference (and so without E_n and zeta), as the runner does.

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
    "u_reference", "estimate", "u", "mc_mean", "interval_low", "interval_high", "treatment",
    "bias", "u_bias", "corrected", "u_corrected", "correction_applied", "bias_paper",
    "corrected_paper", "u_corrected_paper", "paper_applied", "En", "En_corrected", "En_paper",
    "zeta", "zeta_corrected", "corrected_denoised", "En_denoised", "En_inflated", "true_value")
SUMMARY_COLUMNS = ("factor", "level", "measurand", "treatment", "n", "share_abs_En_le_1",
                   "mean_En", "rms_En")
TREATMENTS_COLUMNS = ("measurand", "treatment", "n", "mean_En", "rms_En", "share_abs_En_le_1",
                      "mean_error", "rms_error", "unit")
DEMO_LOCATIONS = ("C", "L1", "L2", "L3", "L4", "E1", "E2")
DEMO_ORIENTATIONS_DEG = (0, 90, 180, 270)
DEMO_HEIGHTS = ("top", "middle", "bottom")


def demo_setups():
    """The demo's set-ups: (id prefix, location, orientation_deg)."""
    return ([(f"{location}-O000", location, 0) for location in DEMO_LOCATIONS]
            + [(f"C-R{o:03d}", "C", o) for o in DEMO_ORIENTATIONS_DEG])


def grid_setups(locations, orientations_deg):
    """Every location at every orientation: (id prefix, location, orientation_deg)."""
    return [(f"{location}-O{int(o):03d}", location, o)
            for location in locations for o in orientations_deg]


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
    """E_n with the runner's sign: (reference - value) / (k sqrt(u^2 + u_ref^2))."""
    if value is None or u is None or reference is None:
        return None
    return (reference - value) / math.hypot(K * u, K * u_reference)


def zeta(value, reference, u, u_reference):
    if value is None or u is None or reference is None:
        return None
    return (reference - value) / math.hypot(u, u_reference)


def treatments_of(measurand, est, u, bias_paper, trials, true_value, bias_treatment, rng,
                  scanning):
    """The seed study's correction (a) and the default treatment of one row: a dict of the
    results.csv columns treatment ... paper_applied."""
    u_mc = u / math.sqrt(trials)             # standard error of the Monte Carlo mean
    paper_applied = not (measurand == "roundness" and est - bias_paper < 0.0)
    if paper_applied:
        corrected_paper, u_paper = est - bias_paper, math.hypot(u, u_mc)
    else:                                    # refused: the estimate, u enlarged by |b|
        corrected_paper, u_paper = est, math.hypot(u, bias_paper)
    row = {"bias_paper": bias_paper, "corrected_paper": corrected_paper,
           "u_corrected_paper": u_paper, "paper_applied": paper_applied}
    if measurand == "diameter" or bias_treatment == "paper":
        row.update({"treatment": "paper", "bias": bias_paper, "u_bias": 0.0,
                    "corrected": corrected_paper, "u_corrected": u_paper,
                    "correction_applied": paper_applied})
    else:
        # Shrinkage: a bias near the true one (estimate - truth), known to within u_bias.
        u_bias = float(rng.uniform(0.02, 0.05) if scanning else rng.uniform(0.04, 0.09))
        bias = (est - true_value) + float(rng.normal(0.0, u_bias))
        row.update({"treatment": "shrinkage", "bias": bias, "u_bias": u_bias,
                    "corrected": max(0.0, est - bias),
                    "u_corrected": math.sqrt(u * u + u_bias * u_bias + u_mc * u_mc),
                    "correction_applied": True})
    return row


def write_fixture(outdir, *, seed=20240605, setups=None, locations=None,
                  orientations_deg=None, heights=DEMO_HEIGHTS,
                  modes=("scanning", "touch_trigger"), trials=1000, validate=False,
                  denoised=False, bias_treatment="shrinkage", missing_reference=(),
                  budget=False):
    """Writes the synthetic output directory; returns the list of measurement ids (in the
    order of results.csv).  setups: [(id prefix, location, orientation_deg)]; default the
    demo's plan, or the grid of `locations` x `orientations_deg` when either is given."""
    if bias_treatment not in ("shrinkage", "paper"):
        raise ValueError(f"write_fixture: bias_treatment must be shrinkage or paper; "
                         f"{bias_treatment!r}")
    if setups is None:
        if locations is None and orientations_deg is None:
            setups = demo_setups()
        else:
            setups = grid_setups(locations or DEMO_LOCATIONS,
                                 orientations_deg or DEMO_ORIENTATIONS_DEG)
    missing_reference = set(missing_reference)
    rng = np.random.default_rng(seed)
    os.makedirs(outdir, exist_ok=True)
    dense = np.linspace(0.0, 2.0 * math.pi, 3600, endpoint=False)
    true_roundness_um = float(np.ptp(remove_circle(ring_form_um(dense), dense)))

    # Location effects: a diameter offset (um) and a 2-lobe machine error (amplitude, phase).
    # The first location (the centre) gets small ones; some others get large diameter
    # offsets so that a few |E_n| > 1 appear.
    location_effects = {}
    for i, location in enumerate(dict.fromkeys(s[1] for s in setups)):
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
    for mode in modes:                       # as the runner writes them: mode, set-up, height
        scanning = mode == "scanning"
        for prefix, location, orientation in setups:
            d_offset_um, a2_um, phase2 = location_effects[location]
            for height in heights:
                mid = f"{prefix}-{height}-{'scan' if scanning else 'touch'}"
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
                # Monte Carlo samples: diameter normal about a small bias, roundness skewed
                # (noise inflates the peak-to-valley): gamma-distributed bias.
                d_bias_mm = 1e-3 * float(rng.normal(0.0, 0.005))
                d_u_mm = 1e-3 * float(rng.uniform(0.05, 0.09))
                d_samples = estimate["diameter"] + d_bias_mm + rng.normal(0.0, d_u_mm, trials)
                r_bias_target = (0.05 if scanning else 0.12) * float(rng.uniform(0.6, 1.4))
                if not scanning and rng.uniform() < 0.15:
                    # The model's noise exceeds the real one: the bias exceeds the estimate
                    # and the study's correction would go negative (refused).
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
                    ref, u_ref = ((None, None) if (mid, measurand) in missing_reference
                                  else reference[measurand])
                    est = estimate[measurand]
                    mc_mean = float(np.mean(samples))
                    u = float(np.std(samples, ddof=1))
                    low, high = (float(q) for q in np.quantile(samples, [0.025, 0.975]))
                    t = treatments_of(measurand, est, u, mc_mean - est, trials, true_value,
                                      bias_treatment, rng, scanning)
                    # Treatment (b): bias from the denoised virtual truth, smaller.
                    corrected_b = None
                    if denoised:
                        corrected_b = est - t["bias_paper"] * (
                            0.55 if measurand == "roundness" else 1.0)
                    results.append({
                        "id": mid, "location": location, "orientation_deg": orientation,
                        "height": height, "mode": mode, "measurand": measurand,
                        "unit": unit, "reference": ref, "u_reference": u_ref,
                        "estimate": est, "u": u, "mc_mean": mc_mean, "interval_low": low,
                        "interval_high": high, **t,
                        "En": e_n(est, ref, u, u_ref),
                        "En_corrected": e_n(t["corrected"], ref, t["u_corrected"], u_ref),
                        "En_paper": e_n(t["corrected_paper"], ref, t["u_corrected_paper"],
                                        u_ref),
                        "zeta": zeta(est, ref, u, u_ref),
                        "zeta_corrected": zeta(t["corrected"], ref, t["u_corrected"], u_ref),
                        "corrected_denoised": corrected_b,
                        "En_denoised": e_n(corrected_b, ref, u, u_ref),
                        "En_inflated": (None if ref is None else (ref - est) / math.hypot(
                            K * u_ref, K * u + abs(t["bias_paper"]))),
                        "true_value": None if validate else true_value,
                    })

    lines = [",".join(RESULTS_COLUMNS)]
    lines += [",".join(row[c] if isinstance(row[c], str) else fmt(row[c])
                       for c in RESULTS_COLUMNS) for row in results]
    write_text_atomically(os.path.join(outdir, "results.csv"), "\n".join(lines) + "\n")
    write_text_atomically(os.path.join(outdir, "results.json"),
                          json.dumps({"schema": "vcmm.results", "schema_version": 2,
                                      "synthetic": True, "results": results}, indent=1))

    # summary.csv / treatments.csv treatment -> (E_n column, reported-value column)
    treatment_columns = {"uncorrected": ("En", "estimate"),
                         "corrected": ("En_corrected", "corrected"),
                         "paper": ("En_paper", "corrected_paper")}
    if denoised:
        treatment_columns["denoised"] = ("En_denoised", "corrected_denoised")
    treatment_columns["inflated"] = ("En_inflated", "estimate")

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
                          json.dumps({"schema": "vcmm.summary", "schema_version": 2,
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

    command = ("vcmm " + ("validate" if validate else "demo") + " (simulated) --bias-treatment "
               + bias_treatment + (" --denoised" if denoised else ""))
    run_info = {
        "generator": "python/make_report_fixture.py (synthetic numbers, not vcmm output)",
        "command": command, "seed": seed, "trials_per_measurement": trials, "k": K,
        "coverage_probability": 0.95, "reference_circle": "MI",
        "filter_cutoff_upr": FILTER_UPR, "bias_treatment": bias_treatment,
        "kinematic_errors": "corrected", "denoised_treatment": denoised,
        "en_sign": "E_n = (reference - measured) / (k sqrt(u_ref^2 + u^2))",
        "measurements": len(ids),
        "factors": {"locations": list(location_effects),
                    "orientations_deg": list(dict.fromkeys(s[2] for s in setups)),
                    "heights": list(heights), "modes": list(modes)},
    }
    if budget:
        write_budget(outdir, [r for r in results if r["measurand"] == "diameter"], seed,
                     min(trials, 500))
        run_info["budget"] = True
        run_info["budget_trials"] = min(trials, 500)
        run_info["command"] += " --budget"
    if not validate:
        run_info["form_scale"] = "1"
    write_text_atomically(os.path.join(outdir, "run_info.json"),
                          json.dumps(run_info, indent=2) + "\n")
    return ids


# Typical one-at-a-time u (um) of each error source, per mode and measurand: (diameter,
# roundness).  Scanning: the numbers of docs/validation.md's budget example; touch-trigger: 36
# points, so the noise and the roughness weigh more.
BUDGET_SOURCES = ("roughness", "temperature", "kinematic", "probe", "noise")
BUDGET_U_UM = {
    "scanning": {"roughness": (0.002, 0.006), "temperature": (0.20, 4e-7),
                 "kinematic": (0.048, 0.036), "probe": (0.20, 0.27), "noise": (0.023, 0.059)},
    "touch_trigger": {"roughness": (0.015, 0.05), "temperature": (0.20, 1e-7),
                      "kinematic": (0.045, 0.03), "probe": (0.20, 0.15), "noise": (0.06, 0.10)},
}


def write_budget(outdir, rows, seed, trials):
    """budget.csv as `vcmm validate --budget` writes it, for the measurements of `rows` (one
    results row each): per source u (um) and share u_i^2 / sum u_j^2, the quadrature sum with
    its ratio to the full u (diameter ~1, roundness 1.02-1.12: RONt is not additive) and the
    full u.  Its own random stream (seed + 1), so the other files do not change."""
    rng = np.random.default_rng(seed + 1)
    lines = ["id,location,orientation_deg,height,mode,trials,source,evaluated,u_diameter_um,"
             "share_diameter,u_roundness_um,share_roundness,ratio_diameter,ratio_roundness"]
    for r in rows:
        head = (f"{r['id']},{r['location']},{fmt(r['orientation_deg'])},{r['height']},"
                f"{r['mode']},{trials},")
        u = {source: [value * float(rng.uniform(0.85, 1.15)) for value in
                      BUDGET_U_UM.get(r["mode"], BUDGET_U_UM["scanning"])[source]]
             for source in BUDGET_SOURCES}
        total = [sum(u[source][k] ** 2 for source in BUDGET_SOURCES) for k in (0, 1)]
        for source in BUDGET_SOURCES:
            lines.append(head + f"{source},true,{fmt(u[source][0])},"
                         f"{fmt(u[source][0] ** 2 / total[0])},{fmt(u[source][1])},"
                         f"{fmt(u[source][1] ** 2 / total[1])},,")
        quadrature = [math.sqrt(t) for t in total]
        ratio = [1.0 + float(rng.normal(0.0, 1.0 / math.sqrt(2.0 * trials))),
                 float(rng.uniform(1.02, 1.12))]
        lines.append(head + f"quadrature_sum,,{fmt(quadrature[0])},,{fmt(quadrature[1])},,"
                     f"{fmt(ratio[0])},{fmt(ratio[1])}")
        lines.append(head + f"full_run,,{fmt(quadrature[0] / ratio[0])},,"
                     f"{fmt(quadrature[1] / ratio[1])},,,")
    write_text_atomically(os.path.join(outdir, "budget.csv"), "\n".join(lines) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(
        prog="make_report_fixture.py",
        description="Write a synthetic vcmm validate/demo output directory.")
    parser.add_argument("outdir")
    parser.add_argument("--seed", type=int, default=20240605)
    parser.add_argument("--trials", type=int, default=1000)
    parser.add_argument("--locations", default=None,
                        help="comma-separated location labels for a full grid instead of the "
                             "demo's plan (the first gets the small centre errors)")
    parser.add_argument("--orientations", default=None,
                        help="comma-separated orientations (deg) of the grid; default "
                             "0,90,180,270")
    parser.add_argument("--validate", action="store_true",
                        help="no truth, no treatments.csv")
    parser.add_argument("--denoised", action="store_true",
                        help="fill treatment (b)'s columns (vcmm --denoised)")
    parser.add_argument("--budget", action="store_true",
                        help="write budget.csv (vcmm --budget: the uncertainty budget)")
    parser.add_argument("--bias-treatment", choices=("shrinkage", "paper"),
                        default="shrinkage", help="the roundness's default treatment")
    args = parser.parse_args(argv)
    if args.trials < 10:
        parser.error(f"--trials must be >= 10; got {args.trials}")
    orientations = None
    if args.orientations is not None:
        try:
            orientations = tuple(int(o) for o in args.orientations.split(","))
        except ValueError:
            parser.error(f"--orientations must be integers separated by commas; got "
                         f"{args.orientations!r}")
    ids = write_fixture(args.outdir, seed=args.seed, trials=args.trials,
                        locations=(None if args.locations is None
                                   else tuple(args.locations.split(","))),
                        orientations_deg=orientations, validate=args.validate,
                        denoised=args.denoised, bias_treatment=args.bias_treatment,
                        budget=args.budget)
    print(f"wrote {len(ids)} synthetic measurements to {args.outdir}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
