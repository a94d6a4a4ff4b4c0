#!/usr/bin/env python3
"""Acceptance of the bias treatments on known truth (docs/demo.md, "Acceptance on known truth").

Runs `vcmm demo` over world seeds x form scales x reference circles and pools, per reference
circle, form scale, probing mode and measurand, the E_n of every bias treatment (share of
|E_n| <= 1, mean, RMS) and the error of the reported value against the truth (mean, RMS).
Writes a Markdown table (--markdown FILE) and a CSV (--csv FILE), and exits 1 when the default
treatment misses an acceptance criterion (--check):
  share |E_n| <= 1 >= 95 %,  RMS(E_n) in [0.4, 0.6],  |mean E_n| <= 0.25,
  RMS error of the corrected roundness < RMS error of the uncorrected one.

Standard library only: any python3 runs it.

  scripts/bias_acceptance.py --vcmm build/cli/vcmm --out out/acceptance \\
      --seeds 1-20 --form-scales 1,5,20 --references MI,MZ --trials 1000 \\
      --markdown out/acceptance/table.md --csv out/acceptance/table.csv --check

Each demo run goes to OUT/<reference>-f<scale>-s<seed>/ and is skipped when its results.csv
exists (delete the folder to rerun it), so an interrupted sweep resumes.
"""
import argparse
import csv
import math
import os
import subprocess
import sys
import time

TREATMENTS = (("uncorrected", "En", "estimate"),
              ("corrected", "En_corrected", "corrected"),
              ("paper", "En_paper", "corrected_paper"),
              ("inflated", "En_inflated", "estimate"))
CRITERIA = "share |E_n| <= 1 >= 0.95, RMS(E_n) in [0.4, 0.6], |mean E_n| <= 0.25"


def parse_range(text):
    out = []
    for part in text.split(","):
        if "-" in part:
            a, b = part.split("-")
            out.extend(range(int(a), int(b) + 1))
        else:
            out.append(int(part))
    return out


def run_one(args, reference, scale, seed):
    folder = os.path.join(args.out, f"{reference}-f{scale:g}-s{seed}")
    results = os.path.join(folder, "results.csv")
    if os.path.exists(results):
        return results, 0.0
    cmd = [args.vcmm, "demo", "-o", folder, "--world-seed", str(seed), "--form-scale",
           f"{scale:g}", "--reference", reference, "--trials", str(args.trials),
           "--progress", "never"]
    if args.threads:
        cmd += ["--threads", str(args.threads)]
    start = time.time()
    done = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if done.returncode != 0:
        sys.exit(f"bias_acceptance: {' '.join(cmd)} failed ({done.returncode}):\n{done.stderr}")
    return results, time.time() - start


def number(text):
    return float(text) if text not in ("", None) else math.nan


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--vcmm", default="build/cli/vcmm")
    p.add_argument("--out", default="out/acceptance")
    p.add_argument("--seeds", default="1-20")
    p.add_argument("--form-scales", default="1,5,20")
    p.add_argument("--references", default="MI,MZ")
    p.add_argument("--trials", type=int, default=1000)
    p.add_argument("--threads", type=int, default=0)
    p.add_argument("--markdown")
    p.add_argument("--csv")
    p.add_argument("--check", action="store_true",
                   help="exit 1 if the default treatment misses a criterion")
    args = p.parse_args()
    seeds = parse_range(args.seeds)
    scales = [float(s) for s in args.form_scales.split(",")]
    references = args.references.split(",")

    # cells[(reference, scale, mode, measurand, treatment)] = list of (En, error)
    cells = {}
    per_seed = {}
    wall = 0.0
    for reference in references:
        for scale in scales:
            for seed in seeds:
                path, seconds = run_one(args, reference, scale, seed)
                wall += seconds
                with open(path, newline="") as f:
                    for row in csv.DictReader(f):
                        for name, en_col, value_col in TREATMENTS:
                            en = number(row[en_col])
                            err = number(row[value_col]) - number(row["true_value"])
                            key = (reference, scale, row["mode"], row["measurand"], name)
                            cells.setdefault(key, []).append((en, err))
                            skey = (reference, scale, seed, row["measurand"], name)
                            per_seed.setdefault(skey, []).append(en)
                print(f"{reference} form x{scale:g} seed {seed}: done"
                      + (f" in {seconds:.0f} s" if seconds else " (kept)"), file=sys.stderr)

    rows = []
    for key in sorted(cells, key=lambda k: (references.index(k[0]), k[1], k[2], k[3],
                                            [t[0] for t in TREATMENTS].index(k[4]))):
        values = cells[key]
        en = [e for e, _ in values if math.isfinite(e)]
        err = [x for _, x in values if math.isfinite(x)]
        n = len(en)
        share = sum(1 for e in en if abs(e) <= 1.0) / n
        mean = sum(en) / n
        rms = math.sqrt(sum(e * e for e in en) / n)
        mean_err = sum(err) / len(err)
        rms_err = math.sqrt(sum(x * x for x in err) / len(err))
        rows.append(key + (n, share, mean, rms, mean_err, rms_err))

    failures = []
    by_key = {r[:5]: r for r in rows}
    for r in rows:
        reference, scale, mode, measurand, treatment, n, share, mean, rms, _, rms_err = r
        if treatment != "corrected":
            continue
        what = f"{reference} x{scale:g} {mode} {measurand}"
        if share < 0.95:
            failures.append(f"{what}: share {share:.3f} < 0.95")
        if not 0.4 <= rms <= 0.6:
            failures.append(f"{what}: RMS E_n {rms:.3f} outside [0.4, 0.6]")
        if abs(mean) > 0.25:
            failures.append(f"{what}: |mean E_n| {abs(mean):.3f} > 0.25")
        if measurand == "roundness":
            unc = by_key[(reference, scale, mode, measurand, "uncorrected")]
            if not rms_err < unc[10]:
                failures.append(f"{what}: RMS error {rms_err:.3f} not below uncorrected "
                                f"{unc[10]:.3f}")

    header = ("reference", "form_scale", "mode", "measurand", "treatment", "n",
              "share_abs_En_le_1", "mean_En", "rms_En", "mean_error", "rms_error", "error_unit")
    if args.csv:
        with open(args.csv, "w", newline="") as f:
            w = csv.writer(f)
            w.writerow(header)
            for r in rows:
                w.writerow(list(r) + ["mm" if r[3] == "diameter" else "um"])
    lines = [f"Seeds {args.seeds}, {args.trials} trials per Monte Carlo run, "
             f"{len(seeds) * len(scales) * len(references)} demo runs; criteria for the "
             f"default treatment ('corrected'): {CRITERIA}.", "",
             "| reference | form | mode | measurand | treatment | n | \\|E_n\\| ≤ 1 | mean E_n "
             "| RMS E_n | mean error | RMS error |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        reference, scale, mode, measurand, treatment, n, share, mean, rms, me, rmse = r
        unit, s = ("µm", 1000.0) if measurand == "diameter" else ("µm", 1.0)
        mark = "**" if treatment == "corrected" else ""
        lines.append(f"| {reference} | ×{scale:g} | {mode} | {measurand} | {mark}{treatment}{mark}"
                     f" | {n} | {100 * share:.1f} % | {mean:+.2f} | {rms:.2f} | "
                     f"{me * s:+.3f} {unit} | {rmse * s:.3f} {unit} |")
    lines.append("")
    lines.append("Default treatment: " + ("meets every criterion." if not failures else
                                          "misses: " + "; ".join(failures) + "."))
    text = "\n".join(lines) + "\n"
    if args.markdown:
        with open(args.markdown, "w") as f:
            f.write(text)
    print(text)
    if wall:
        print(f"(computed in {wall:.0f} s)", file=sys.stderr)
    if args.check and failures:
        sys.exit(1)


if __name__ == "__main__":
    main()
