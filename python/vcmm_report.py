#!/usr/bin/python3
"""Validation figures and a self-contained HTML report for a vcmm validation run.

Usage:  vcmm report OUTDIR [--title T]       (finds a Python with matplotlib; docs/cli.md)
        /usr/bin/python3 python/vcmm_report.py OUTDIR [--title T]

OUTDIR is the output directory of `vcmm validate CAMPAIGN.json -o OUTDIR` or
`vcmm demo -o OUTDIR` (format v2, with the bias-treatment columns; described in docs/report.md
and docs/validation.md "Output directory"):
  results.csv, summary.csv                 required
  treatments.csv, run_info.json            optional (demo / provenance)
  budget.csv                               optional (--budget: the uncertainty budget)
  samples/<id>.csv, residuals/<id>.csv     optional; read only for the measurements shown
  results.json, summary.json               only linked from the report
Writes every figure as OUTDIR/figures/NAME.svg, NAME.pdf and NAME.png (matplotlib, Agg backend,
200 dpi) and OUTDIR/report.html, a single
self-contained file (inline CSS, images embedded as base64 data URIs, no script, no external
URL) that can be mailed.  Every file is written atomically: a temporary file in the same
directory, then os.replace, so an interrupted run never leaves a half-written file that looks
whole.

Bias treatments shown (docs/validation.md, "Bias treatments"): uncorrected; "corrected", the
run's default treatment (column `treatment`: shrinkage for the roundness by default, the seed
study's for the diameter; its u_corrected includes u_bias, the bias estimate's own
uncertainty); (a) the seed study's correction (`*_paper` columns), always shown beside the
default; (b) the bias from the denoised profile (only when the run used --denoised); (c) no
correction, U = k u + |b_paper|.

Input checks: every required column present, the field count of every line equal to the
header's, numbers finite (NaN/inf rejected), categorical columns from the agreed sets, E_n
shares in [0, 1], residual angles in 0..360 and in order; one default treatment per
measurand, agreeing with run_info.json's bias_treatment; E_n and zeta present exactly where
the row has a reference.  A failed check prints one line
"vcmm_report.py: error: FILE: line N: what is wrong; offending value" and exits with code 3,
never a traceback.

Exit codes: 0 success; 1 internal error (a bug, with a traceback) or matplotlib missing;
2 command-line error; 3 invalid input (missing or malformed file) or an output that cannot
be written.

Cost: linear in the size of results.csv and summary.csv plus the few samples/residuals files
shown; about 20 s of CPU for 66 measurements, dominated by matplotlib's rendering of the three
formats.

Number style (docs/report.md): u with two significant digits and values to the same decimal
place (GUM 7.2.6), U = k u labelled "U (k = 2)", E_n typeset as $E_n$ with its sign
convention (reference − measured) stated beside the numbers.

Runs with Debian's /usr/bin/python3 (python3-matplotlib 3.6, python3-numpy 1.24); the
`python3` first on PATH may be another interpreter without matplotlib.
"""

import argparse
import base64
import dataclasses
import datetime
import html
import json
import math
import os
import re
import sys
import tempfile
import traceback
import urllib.parse

PROG = "vcmm_report.py"
# PNG resolution (dpi); every figure is written as SVG and PDF (vector) beside its PNG.
DPI = 200
FIGURE_FORMATS = ("png", "svg", "pdf")

RESULTS_COLUMNS = (
    "id", "location", "orientation_deg", "height", "mode", "measurand", "unit", "reference",
    "u_reference", "estimate", "u", "mc_mean", "interval_low", "interval_high", "treatment",
    "bias", "u_bias", "corrected", "u_corrected", "correction_applied", "bias_paper",
    "corrected_paper", "u_corrected_paper", "paper_applied", "En", "En_corrected", "En_paper",
    "zeta", "zeta_corrected", "corrected_denoised", "En_denoised", "En_inflated", "true_value")
# Numbers every row must carry (the C++ runner always writes them; a refused correction
# reports the estimate itself).  The others may be empty: no reference (then no E_n or zeta),
# no treatment (b) (off by default), no truth (real data).
RESULTS_REQUIRED_NUMBERS = ("orientation_deg", "estimate", "u", "mc_mean", "interval_low",
                            "interval_high", "bias", "u_bias", "corrected", "u_corrected",
                            "bias_paper", "corrected_paper", "u_corrected_paper")
RESULTS_OPTIONAL_NUMBERS = ("reference", "u_reference", "En", "En_corrected", "En_paper",
                            "zeta", "zeta_corrected", "corrected_denoised", "En_denoised",
                            "En_inflated", "true_value")
RESULTS_NONNEGATIVE = ("u", "u_reference", "u_bias", "u_corrected", "u_corrected_paper")
RESULTS_FLAGS = ("correction_applied", "paper_applied")
# Scores that exist exactly when the row has a reference (docs/validation.md: score()).
SCORES_WITH_REFERENCE = ("En", "En_corrected", "En_paper", "En_inflated", "zeta",
                         "zeta_corrected")
EN_COLUMNS = ("En", "En_corrected", "En_paper", "En_denoised", "En_inflated")
SUMMARY_COLUMNS = ("factor", "level", "measurand", "treatment", "n", "share_abs_En_le_1",
                   "mean_En", "rms_En")
TREATMENTS_COLUMNS = ("measurand", "treatment", "n", "mean_En", "rms_En", "share_abs_En_le_1",
                      "mean_error", "rms_error", "unit")
BUDGET_COLUMNS = ("id", "mode", "trials", "source", "evaluated", "u_diameter_um",
                  "share_diameter", "u_roundness_um", "share_roundness", "ratio_diameter",
                  "ratio_roundness")
# Rows of budget.csv after a measurement's error sources: √Σu_i² (with its ratio to the full
# u) and the full run's u over the same trials.
BUDGET_SUM_ROWS = ("quadrature_sum", "full_run")
# Bar colour of each probing mode in the budget figure.
MODE_COLORS = {"scanning": "C0", "touch_trigger": "C3"}
SAMPLES_COLUMNS = ("diameter_mm", "roundness_um")
RESIDUALS_COLUMNS = ("angle_deg", "deviation_um", "filtered_deviation_um")

MEASURANDS = ("diameter", "roundness")
MEASURAND_UNITS = {"diameter": ("mm",), "roundness": ("um", "µm")}
FACTORS = ("all", "location", "orientation_deg", "height", "mode")
# Treatments of summary.csv / treatments.csv, in display order.  "corrected" is the run's
# default treatment (results.csv column `treatment`), "paper" the seed study's.
TREATMENTS = ("uncorrected", "corrected", "paper", "denoised", "inflated")
# Values of results.csv `treatment` and run_info.json `bias_treatment`.
BIAS_TREATMENTS = ("shrinkage", "paper")
BIAS_TREATMENT_DESCRIPTIONS = {
    "shrinkage": "bias evaluated at a shrinkage surrogate of the true profile; u_corrected "
                 "includes u_bias, the bias estimate's own uncertainty",
    "paper": "bias = Monte Carlo mean − estimate of the virtual experiment on the measured "
             "profile",
}
FIXED_TREATMENT_LABELS = {
    "uncorrected": "uncorrected",
    "paper": "(a) seed study",
    "denoised": "(b) denoised",
    "inflated": "(c) U + |b|",
}
# One colour per treatment in every figure; fill tells the series of one panel apart too.
TREATMENT_COLORS = {"uncorrected": "C0", "corrected": "C1", "paper": "C5", "denoised": "C2",
                    "inflated": "C4"}
HEIGHT_ORDER = ("top", "middle", "bottom")
HEIGHT_PREFERENCE = ("middle", "top", "bottom")   # which height to show first
MODE_ORDER = ("scanning", "touch_trigger")
MODE_MARKERS = {"scanning": "o", "touch_trigger": "^"}
EXTRA_MARKERS = ("s", "D", "v", "P", "X")
ID_PATTERN = re.compile(r"[A-Za-z0-9_.-]+\Z")

# Honest uncertainties: E_n = d / (k sqrt(u^2 + u_ref^2)) ~ N(0, (1/k)^2), hence mean 0,
# RMS 1/k and P(|E_n| <= 1) = P(|z| <= k) = erf(k / sqrt 2); for k = 2: 0.5 and 95.4 %
# (NOTES.md: "|E_n| > 1 happens 4.6 % of the time").  See Run.expected_rms/expected_share.
EXPECTED_MEAN_EN = 0.0
# The sign convention of E_n (the study's: reference − measured), written next to the numbers.
EN_DEFINITION = "E_n = (reference − measured) / √(U_ref² + U²), U = k·u"
EN_DEFINITION_TEX = (r"$E_n = (y_\mathrm{ref} - y)\,/\,\sqrt{U_\mathrm{ref}^2 + U^2}$ "
                     "(reference − measured), U = k·u")

# E_n axes: values beyond this are drawn at the edge with their value written beside them,
# so that one wild point does not flatten the +-1 band of the others.
EN_AXIS_CAP = 5.0
# Series sharing a panel of a per-measurement figure are spread over this fraction of the
# distance between two measurements, so that none hides another.
SERIES_SPREAD = 0.5
# Angles of residual profiles: 0..360 deg within this slack (printing round-off).
ANGLE_SLACK_DEG = 1e-6


class InputError(Exception):
    """A missing or malformed input file (exit code 3)."""


class OutputError(Exception):
    """An output that cannot be written (exit code 3)."""


class MissingDependency(Exception):
    """matplotlib or numpy cannot be imported (exit code 1)."""


# --------------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------------

def read_csv_table(path, columns):
    """Reads a comma-separated table with a header line.

    Returns a list of (line_number, {column: text}) for the data lines (blank lines skipped,
    fields stripped).  Every column of `columns` must appear in the header; extra columns are
    allowed and ignored (forward compatibility).  Raises InputError naming the file and line.
    """
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except FileNotFoundError:
        raise InputError(f"{path}: file not found") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a directory, expected a CSV file") from None
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as e:
        line = raw[:e.start].count(b"\n") + 1
        raise InputError(f"{path}: line {line}: not UTF-8 text (byte 0x{raw[e.start]:02x})") \
            from None
    if text.startswith("\ufeff"):
        text = text[1:]
    lines = text.splitlines()
    if not lines or not lines[0].strip():
        raise InputError(f"{path}: line 1: empty; expected the header "
                         f"'{','.join(columns)}'")
    header = [h.strip() for h in lines[0].split(",")]
    seen = set()
    for h in header:
        if h in seen:
            raise InputError(f"{path}: line 1: column '{h}' appears twice in the header")
        seen.add(h)
    missing = [c for c in columns if c not in seen]
    if missing:
        raise InputError(f"{path}: line 1: header lacks column(s) {', '.join(missing)}; "
                         f"header is '{lines[0].strip()}'")
    rows = []
    for number, line in enumerate(lines[1:], start=2):
        if not line.strip():
            continue
        fields = [f.strip() for f in line.split(",")]
        if len(fields) != len(header):
            raise InputError(f"{path}: line {number}: {len(fields)} fields, the header has "
                             f"{len(header)}")
        rows.append((number, dict(zip(header, fields))))
    if not rows:
        raise InputError(f"{path}: no data lines after the header")
    return rows


def parse_number(text, path, line, column, *, optional=False):
    """A finite float from a CSV field; empty -> None if optional."""
    if text == "":
        if optional:
            return None
        raise InputError(f"{path}: line {line}: column '{column}' is empty; a number is "
                         "required")
    try:
        value = float(text)
    except ValueError:
        raise InputError(f"{path}: line {line}: column '{column}' is not a number; "
                         f"'{text}'") from None
    if not math.isfinite(value):
        raise InputError(f"{path}: line {line}: column '{column}' is not finite (NaN and "
                         f"infinity are rejected); '{text}'")
    return value


def parse_count(text, path, line, column):
    try:
        value = int(text)
    except ValueError:
        raise InputError(f"{path}: line {line}: column '{column}' is not a non-negative "
                         f"integer; '{text}'") from None
    if value < 0:
        raise InputError(f"{path}: line {line}: column '{column}' must be >= 0; '{text}'")
    return value


def require_choice(text, choices, path, line, column):
    if text not in choices:
        raise InputError(f"{path}: line {line}: column '{column}' must be one of "
                         f"{', '.join(choices)}; '{text}'")
    return text


def require_label(text, path, line, column):
    if not text:
        raise InputError(f"{path}: line {line}: column '{column}' is empty")
    return text


@dataclasses.dataclass
class ResultRow:
    line: int
    id: str
    measurand: str
    unit: str
    treatment: str        # the default treatment of this row: shrinkage or paper
    correction_applied: bool    # the default treatment's correction applied
    paper_applied: bool         # the seed study's correction applied
    values: dict          # column -> float or None (numeric columns)
    text: dict            # column -> text as in the file

    def applied(self, column):
        """Whether the correction behind an E_n or value column was applied (False: refused
        because it would have made the roundness negative)."""
        if column in ("En_corrected", "corrected", "u_corrected"):
            return self.correction_applied
        if column in ("En_paper", "corrected_paper", "u_corrected_paper"):
            return self.paper_applied
        return True


@dataclasses.dataclass
class Measurement:
    id: str
    location: str
    orientation_deg: float
    height: str
    mode: str
    rows: dict            # measurand -> ResultRow
    # 0 for the first measurement of its (location, orientation, height, mode) in
    # results.csv, 1 for a repeat (the demo measures C at 0° twice: in the location series
    # C-O000 and in the orientation series C-R000), ...
    repeat: int = 0

    @property
    def line(self):
        """The first line of the measurement in results.csv."""
        return min(row.line for row in self.rows.values())

    def value(self, measurand, column):
        row = self.rows.get(measurand)
        return None if row is None else row.values.get(column)


@dataclasses.dataclass
class SummaryRow:
    line: int
    factor: str
    level: str
    measurand: str
    treatment: str
    n: int
    share: float
    mean: float
    rms: float


@dataclasses.dataclass
class TreatmentRow:
    line: int
    measurand: str
    treatment: str
    n: int
    mean: float
    rms: float
    share: float
    mean_error: float
    rms_error: float
    unit: str


@dataclasses.dataclass
class Residuals:
    angle_deg: list
    deviation_um: list
    filtered_um: list


@dataclasses.dataclass
class Run:
    outdir: str
    measurements: list    # ordered: location, orientation, height, mode
    locations: list       # ordered, centre first
    centre: str
    centre_found: bool
    result_columns: list  # header of results.csv
    result_rows: list     # ResultRow in file order
    summary: list
    treatments: list      # [] when treatments.csv is absent
    run_info: dict        # None when run_info.json is absent
    coverage_factor: float
    coverage_factor_source: str
    coverage_probability: float   # None when run_info.json does not state it
    default_treatments: dict      # measurand -> results.csv `treatment` (shrinkage, paper)
    budgets: dict = dataclasses.field(default_factory=dict)   # id -> Budget (budget.csv)

    def default_treatment(self, measurand="roundness"):
        """The default bias treatment of a measurand ('shrinkage' or 'paper'), from the
        results.csv column `treatment`, else run_info.json `bias_treatment` for the roundness
        (the diameter always uses the study's)."""
        if measurand in self.default_treatments:
            return self.default_treatments[measurand]
        if measurand == "roundness":
            value = (self.run_info or {}).get("bias_treatment")
            if value in BIAS_TREATMENTS:
                return value
            return "shrinkage"
        return "paper"

    def default_is_paper(self, measurand):
        return self.default_treatment(measurand) == "paper"

    def label(self, treatment, measurand=None, *, wrap=False):
        """Display label of a summary/treatments treatment.  'corrected' names the default
        treatment of the measurand (of the roundness when measurand is None, adding the
        diameter's when it differs)."""
        if treatment != "corrected":
            return FIXED_TREATMENT_LABELS.get(treatment, treatment)
        sep = "\n" if wrap else " "
        if measurand is not None:
            name = self.default_treatment(measurand)
            return f"corrected{sep}(default: {name}" + (
                " = (a)" if name == "paper" else "") + ")"
        roundness = self.default_treatment("roundness")
        diameter = self.default_treatment("diameter")
        if roundness == diameter or "diameter" not in self.default_treatments:
            return f"corrected{sep}(default: {roundness}" + (
                " = (a)" if roundness == "paper" else "") + ")"
        return f"corrected{sep}(default: {roundness};{sep}diameter: {diameter})"

    @property
    def expected_rms(self):
        """RMS of E_n with honest uncertainties: 1/k."""
        return 1.0 / self.coverage_factor

    @property
    def expected_share(self):
        """P(|E_n| <= 1) with honest uncertainties: erf(k / sqrt 2)."""
        return math.erf(self.coverage_factor / math.sqrt(2.0))

    def honest(self):
        """'mean 0, RMS 0.5, share |E_n| <= 1 of 95.4 %' for the run's k."""
        return (f"E_n ~ N(0, {self.expected_rms:.3g}²): mean 0, RMS {self.expected_rms:.3g}, "
                f"share |E_n| ≤ 1 of {100 * self.expected_share:.1f} %")


def rank(value, order):
    """Sort key: the position in a known order, unknown values after it, alphabetically."""
    return (order.index(value), "") if value in order else (len(order), value)


def is_centre_label(label):
    lowered = label.lower()
    return lowered == "c" or "centre" in lowered or "center" in lowered


def read_results(path):
    rows = []
    columns = None
    first_of_measurand = {}   # measurand -> first ResultRow (for the treatment check)
    for line, fields in read_csv_table(path, RESULTS_COLUMNS):
        if columns is None:
            columns = list(fields.keys())
        mid = fields["id"]
        if not ID_PATTERN.match(mid):
            raise InputError(f"{path}: line {line}: column 'id' must match [A-Za-z0-9_.-]+; "
                             f"'{mid}'")
        for column in ("location", "height", "mode"):
            require_label(fields[column], path, line, column)
        measurand = require_choice(fields["measurand"], MEASURANDS, path, line, "measurand")
        unit = require_choice(fields["unit"], MEASURAND_UNITS[measurand], path, line, "unit")
        treatment = require_choice(fields["treatment"], BIAS_TREATMENTS, path, line,
                                   "treatment")
        applied, paper_applied = (
            require_choice(fields[c], ("true", "false"), path, line, c) == "true"
            for c in RESULTS_FLAGS)
        values = {c: parse_number(fields[c], path, line, c) for c in RESULTS_REQUIRED_NUMBERS}
        values.update({c: parse_number(fields[c], path, line, c, optional=True)
                       for c in RESULTS_OPTIONAL_NUMBERS})
        for column in RESULTS_NONNEGATIVE:
            if values[column] is not None and values[column] < 0.0:
                raise InputError(f"{path}: line {line}: column '{column}' must be >= 0; "
                                 f"'{fields[column]}'")
        if values["interval_low"] > values["interval_high"]:
            raise InputError(f"{path}: line {line}: interval_low > interval_high; "
                             f"'{fields['interval_low']}' > '{fields['interval_high']}'")
        has_reference = values["reference"] is not None
        if (values["u_reference"] is not None) != has_reference:
            raise InputError(f"{path}: line {line}: columns 'reference' and 'u_reference' "
                             "must be both given or both empty; "
                             f"'{fields['reference']}', '{fields['u_reference']}'")
        for column in SCORES_WITH_REFERENCE:
            if (values[column] is not None) != has_reference:
                raise InputError(
                    f"{path}: line {line}: column '{column}' is "
                    + ("empty although the row has a reference; a number is required"
                       if has_reference else
                       f"given although the row has no reference; '{fields[column]}'"))
        if values["En_denoised"] is not None and (values["corrected_denoised"] is None
                                                   or not has_reference):
            raise InputError(f"{path}: line {line}: column 'En_denoised' is given without "
                             "'corrected_denoised' and a reference; "
                             f"'{fields['En_denoised']}'")
        row = ResultRow(line, mid, measurand, unit, treatment, applied, paper_applied, values,
                        fields)
        first = first_of_measurand.setdefault(measurand, row)
        if treatment != first.treatment:
            raise InputError(f"{path}: line {line}: column 'treatment' is '{treatment}' but "
                             f"'{first.treatment}' for the {measurand} at line {first.line}; "
                             "one run has one default treatment per measurand")
        rows.append(row)

    measurements = {}
    repeats = {}              # (location, orientation, height, mode) -> count so far
    for row in rows:
        f = row.text
        m = measurements.get(row.id)
        if m is None:
            cell = (f["location"], row.values["orientation_deg"], f["height"], f["mode"])
            repeat = repeats.get(cell, 0)
            repeats[cell] = repeat + 1
            measurements[row.id] = Measurement(row.id, f["location"],
                                               row.values["orientation_deg"], f["height"],
                                               f["mode"], {row.measurand: row}, repeat)
            continue
        if row.measurand in m.rows:
            raise InputError(f"{path}: line {row.line}: measurement '{row.id}' has a second "
                             f"'{row.measurand}' row (first at line "
                             f"{m.rows[row.measurand].line})")
        first = next(iter(m.rows.values()))
        for column, value in (("location", m.location), ("height", m.height),
                              ("mode", m.mode)):
            if f[column] != value:
                raise InputError(f"{path}: line {row.line}: measurement '{row.id}' has "
                                 f"{column} '{f[column]}' but '{value}' at line {first.line}")
        if row.values["orientation_deg"] != m.orientation_deg:
            raise InputError(f"{path}: line {row.line}: measurement '{row.id}' has "
                             f"orientation_deg {f['orientation_deg']} but "
                             f"{m.orientation_deg:g} at line {first.line}")
        m.rows[row.measurand] = row
    defaults = {measurand: row.treatment for measurand, row in first_of_measurand.items()}
    return columns, rows, list(measurements.values()), defaults


def read_summary(path):
    result = []
    for line, f in read_csv_table(path, SUMMARY_COLUMNS):
        factor = require_choice(f["factor"], FACTORS, path, line, "factor")
        level = require_label(f["level"], path, line, "level")
        if factor == "all" and level != "all":
            raise InputError(f"{path}: line {line}: factor 'all' needs level 'all'; '{level}'")
        measurand = require_choice(f["measurand"], MEASURANDS, path, line, "measurand")
        treatment = require_choice(f["treatment"], TREATMENTS, path, line, "treatment")
        n = parse_count(f["n"], path, line, "n")
        stats = parse_statistics(f, path, line, optional=n == 0)
        result.append(SummaryRow(line, factor, level, measurand, treatment, n, *stats))
    return result


def parse_statistics(f, path, line, *, optional):
    share = parse_number(f["share_abs_En_le_1"], path, line, "share_abs_En_le_1",
                         optional=optional)
    if share is not None and not 0.0 <= share <= 1.0:
        raise InputError(f"{path}: line {line}: column 'share_abs_En_le_1' must be a fraction "
                         f"in [0, 1]; '{f['share_abs_En_le_1']}'")
    mean = parse_number(f["mean_En"], path, line, "mean_En", optional=optional)
    rms = parse_number(f["rms_En"], path, line, "rms_En", optional=optional)
    if rms is not None and rms < 0.0:
        raise InputError(f"{path}: line {line}: column 'rms_En' must be >= 0; '{f['rms_En']}'")
    return share, mean, rms


def read_treatments(path):
    result = []
    for line, f in read_csv_table(path, TREATMENTS_COLUMNS):
        measurand = require_choice(f["measurand"], MEASURANDS, path, line, "measurand")
        treatment = require_choice(f["treatment"], TREATMENTS, path, line, "treatment")
        unit = require_choice(f["unit"], MEASURAND_UNITS[measurand], path, line, "unit")
        n = parse_count(f["n"], path, line, "n")
        share, mean, rms = parse_statistics(f, path, line, optional=n == 0)
        mean_error = parse_number(f["mean_error"], path, line, "mean_error", optional=True)
        rms_error = parse_number(f["rms_error"], path, line, "rms_error", optional=True)
        if rms_error is not None and rms_error < 0.0:
            raise InputError(f"{path}: line {line}: column 'rms_error' must be >= 0; "
                             f"'{f['rms_error']}'")
        result.append(TreatmentRow(line, measurand, treatment, n, mean, rms, share,
                                   mean_error, rms_error, unit))
    return result


def read_samples(path):
    """Monte Carlo samples: ({'diameter': [...mm], 'roundness': [...um]})."""
    diameter, roundness = [], []
    for line, f in read_csv_table(path, SAMPLES_COLUMNS):
        diameter.append(parse_number(f["diameter_mm"], path, line, "diameter_mm"))
        roundness.append(parse_number(f["roundness_um"], path, line, "roundness_um"))
    if len(diameter) < 2:
        raise InputError(f"{path}: {len(diameter)} sample line(s); a histogram needs >= 2")
    return {"diameter": diameter, "roundness": roundness}


def read_residuals(path):
    angle, deviation, filtered = [], [], []
    previous = None
    for line, f in read_csv_table(path, RESIDUALS_COLUMNS):
        a = parse_number(f["angle_deg"], path, line, "angle_deg")
        if not -ANGLE_SLACK_DEG <= a <= 360.0 + ANGLE_SLACK_DEG:
            raise InputError(f"{path}: line {line}: column 'angle_deg' must lie in 0..360; "
                             f"'{f['angle_deg']}'")
        if previous is not None and a < previous:
            raise InputError(f"{path}: line {line}: angles must be in increasing order; "
                             f"{f['angle_deg']} follows {previous:g}")
        previous = a
        angle.append(a)
        deviation.append(parse_number(f["deviation_um"], path, line, "deviation_um"))
        filtered.append(parse_number(f["filtered_deviation_um"], path, line,
                                     "filtered_deviation_um"))
    if len(angle) < 3:
        raise InputError(f"{path}: {len(angle)} point(s); a profile needs >= 3")
    return Residuals(angle, deviation, filtered)


@dataclasses.dataclass
class Budget:
    """One measurement's rows of budget.csv: per error source (in file order) its u (µm) and
    share of Σu_j² for each measurand, and the ratio √Σu_i² / u of each measurand (None
    where the full u is 0)."""
    id: str
    mode: str
    trials: int
    line: int
    sources: dict = dataclasses.field(default_factory=dict)   # source -> {column: float}
    ratio: dict = dataclasses.field(default_factory=dict)     # measurand -> float or None


def read_budget(path, measurements):
    """budget.csv of a run with --budget: id -> Budget.  Every id must be a measurement of
    results.csv with the same mode; every measurement listed has its sources and both sum
    rows, once each; u >= 0, shares in [0, 1]."""
    by_id = {m.id: m for m in measurements}
    budgets = {}
    seen = {}                 # (id, source) -> line
    for line, f in read_csv_table(path, BUDGET_COLUMNS):
        mid = f["id"]
        if mid not in by_id:
            raise InputError(f"{path}: line {line}: measurement '{mid}' is not in "
                             "results.csv")
        mode = f["mode"]
        if mode != by_id[mid].mode:
            raise InputError(f"{path}: line {line}: measurement '{mid}' has mode '{mode}' but "
                             f"'{by_id[mid].mode}' in results.csv")
        source = require_label(f["source"], path, line, "source")
        if (mid, source) in seen:
            raise InputError(f"{path}: line {line}: source '{source}' of measurement '{mid}' "
                             f"appears twice (first at line {seen[(mid, source)]})")
        seen[(mid, source)] = line
        trials = parse_count(f["trials"], path, line, "trials")
        if trials < 2:
            raise InputError(f"{path}: line {line}: column 'trials' must be >= 2 (a standard "
                             f"deviation needs two samples); '{f['trials']}'")
        b = budgets.setdefault(mid, Budget(mid, mode, trials, line))
        if trials != b.trials:
            raise InputError(f"{path}: line {line}: measurement '{mid}' has trials {trials} "
                             f"but {b.trials} at line {b.line}")
        if source in BUDGET_SUM_ROWS:
            for column in ("u_diameter_um", "u_roundness_um"):
                value = parse_number(f[column], path, line, column)
                if value < 0.0:
                    raise InputError(f"{path}: line {line}: column '{column}' must be >= 0; "
                                     f"'{f[column]}'")
            if source == "quadrature_sum":
                for measurand in MEASURANDS:
                    column = "ratio_" + measurand
                    value = parse_number(f[column], path, line, column, optional=True)
                    if value is not None and value < 0.0:
                        raise InputError(f"{path}: line {line}: column '{column}' must be "
                                         f">= 0; '{f[column]}'")
                    b.ratio[measurand] = value
            continue
        require_choice(f["evaluated"], ("true", "false"), path, line, "evaluated")
        values = {}
        for column in ("u_diameter_um", "share_diameter", "u_roundness_um", "share_roundness"):
            values[column] = parse_number(f[column], path, line, column)
            if column.startswith("u_") and values[column] < 0.0:
                raise InputError(f"{path}: line {line}: column '{column}' must be >= 0; "
                                 f"'{f[column]}'")
            if column.startswith("share_") and not 0.0 <= values[column] <= 1.0:
                raise InputError(f"{path}: line {line}: column '{column}' must be a fraction "
                                 f"in [0, 1]; '{f[column]}'")
        b.sources[source] = values
    for mid, b in budgets.items():
        missing = [name for name in BUDGET_SUM_ROWS if (mid, name) not in seen]
        if not b.sources or missing:
            raise InputError(f"{path}: line {b.line}: measurement '{mid}' lacks "
                             + (f"the row(s) {', '.join(missing)}" if missing else
                                "its error-source rows"))
        if list(b.sources) != list(next(iter(budgets.values())).sources):
            raise InputError(f"{path}: line {b.line}: measurement '{mid}' has the sources "
                             f"{', '.join(b.sources)}, the first measurement "
                             f"{', '.join(next(iter(budgets.values())).sources)}")
    return budgets


def read_run_info(path):
    try:
        with open(path, encoding="utf-8") as f:
            text = f.read()
    except UnicodeDecodeError:
        raise InputError(f"{path}: not UTF-8 text") from None
    except OSError as e:
        raise InputError(f"{path}: cannot read: {e.strerror}") from None
    try:
        info = json.loads(text)
    except json.JSONDecodeError as e:
        raise InputError(f"{path}: line {e.lineno}, column {e.colno}: invalid JSON: {e.msg}") \
            from None
    if not isinstance(info, dict):
        raise InputError(f"{path}: line 1: expected a JSON object; found "
                         f"{type(info).__name__}")
    return info


def run_info_number(run_info, keys, accept):
    """(value, key) of the first of keys (top level, then under 'evaluation') that holds a
    finite number accepted by accept(value); (None, None) if none does."""
    if not run_info:
        return None, None
    places = [("", run_info)]
    if isinstance(run_info.get("evaluation"), dict):
        places.append(("evaluation.", run_info["evaluation"]))
    for prefix, place in places:
        for key in keys:
            value = place.get(key)
            if isinstance(value, (int, float)) and not isinstance(value, bool) \
                    and math.isfinite(value) and accept(value):
                return float(value), prefix + key
    return None, None


def coverage_factor_of(run_info):
    """k of E_n: run_info.json's k / coverage_factor (or evaluation.k), else 2."""
    k, key = run_info_number(run_info, ("k", "coverage_factor"), lambda v: v > 0)
    if k is None:
        return 2.0, "default k = 2: run_info.json does not state k"
    return k, f"run_info.json {key}"


def coverage_probability_of(run_info):
    """p of the Monte Carlo coverage interval from run_info.json, or None."""
    p, _ = run_info_number(run_info, ("coverage_probability",), lambda v: 0 < v < 1)
    return p


def check_bias_treatment(run_info, info_path, rows, results_path):
    """run_info.json's bias_treatment (top level or under 'evaluation'), when present, must be
    a known treatment and agree with the roundness rows' `treatment` column."""
    if not run_info:
        return
    places = [("", run_info)]
    if isinstance(run_info.get("evaluation"), dict):
        places.append(("evaluation.", run_info["evaluation"]))
    for prefix, place in places:
        if "bias_treatment" not in place:
            continue
        value = place["bias_treatment"]
        if value not in BIAS_TREATMENTS:
            raise InputError(f"{info_path}: key '{prefix}bias_treatment' must be one of "
                             f"{', '.join(BIAS_TREATMENTS)}; {json.dumps(value)}")
        row = next((r for r in rows if r.measurand == "roundness"), None)
        if row is not None and row.treatment != value:
            raise InputError(f"{info_path}: key '{prefix}bias_treatment' is '{value}' but "
                             f"{results_path}: line {row.line} gives the roundness "
                             f"treatment '{row.treatment}'")


def load_run(outdir):
    if not os.path.isdir(outdir):
        raise InputError(f"{outdir}: not a directory (expected the output directory of "
                         "`vcmm validate` or `vcmm demo`)")
    results_path = os.path.join(outdir, "results.csv")
    columns, rows, measurements, defaults = read_results(results_path)
    summary = read_summary(os.path.join(outdir, "summary.csv"))
    treatments_path = os.path.join(outdir, "treatments.csv")
    treatments = read_treatments(treatments_path) if os.path.exists(treatments_path) else []
    info_path = os.path.join(outdir, "run_info.json")
    run_info = read_run_info(info_path) if os.path.exists(info_path) else None
    check_bias_treatment(run_info, info_path, rows, results_path)

    appearance = list(dict.fromkeys(m.location for m in measurements))
    centres = [loc for loc in appearance if is_centre_label(loc)]
    centre = centres[0] if centres else appearance[0]
    locations = [centre] + [loc for loc in appearance if loc != centre]
    # A repeated set-up (same location and orientation, e.g. the demo's C-O000 and C-R000)
    # follows the first as a block of its own.
    measurements.sort(key=lambda m: (locations.index(m.location), m.orientation_deg,
                                     m.repeat, rank(m.height, HEIGHT_ORDER),
                                     rank(m.mode, MODE_ORDER), m.id))
    budget_path = os.path.join(outdir, "budget.csv")
    budgets = read_budget(budget_path, measurements) if os.path.exists(budget_path) else {}
    k, k_source = coverage_factor_of(run_info)
    return Run(outdir, measurements, locations, centre, bool(centres), columns, rows, summary,
               treatments, run_info, k, k_source, coverage_probability_of(run_info), defaults,
               budgets)


# --------------------------------------------------------------------------------------------
# Writing
# --------------------------------------------------------------------------------------------

def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def write_atomically(path, write):
    """Calls write(binary_file) on a temporary file beside path, then os.replace(tmp, path)."""
    directory = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(directory, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(path) + ".", suffix=".tmp",
                                   dir=directory)
    except OSError as e:
        raise OutputError(f"{path}: cannot write: {e.strerror}") from None
    try:
        with os.fdopen(fd, "wb") as f:
            write(f)
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, path)
    except OSError as e:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise OutputError(f"{path}: cannot write: {e.strerror}") from None
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


# --------------------------------------------------------------------------------------------
# Choosing what to show
# --------------------------------------------------------------------------------------------

def preference(m):
    """Sort key of a representative measurement: scanning, middle height, small angle."""
    return (rank(m.mode, MODE_ORDER), rank(m.height, HEIGHT_PREFERENCE), m.orientation_deg,
            m.id)


def describe(m):
    return (f"{m.id} (location {m.location}, orientation {m.orientation_deg:g}°, height "
            f"{m.height}, {m.mode.replace('_', '-')})")


def choose_location_pair(run, available):
    """(first measurement, second measurement, note): the centre and the first other location
    with residual profiles at the same orientation, height and mode (scanning, middle height,
    small orientation preferred).  When the centre has no such pair, the first location that
    has one stands in for it, and the note says so."""
    for first in run.locations:
        candidates = sorted((m for m in run.measurements
                             if m.location == first and m.id in available), key=preference)
        for c in candidates:
            for other_location in run.locations:
                if other_location == first:
                    continue
                for m in run.measurements:
                    if (m.location == other_location and m.id in available
                            and m.orientation_deg == c.orientation_deg
                            and m.height == c.height and m.mode == c.mode):
                        if not run.centre_found:
                            note = (f"No location is labelled C/centre/center; location "
                                    f"'{first}' stands in for the centre. ")
                        elif first != run.centre:
                            note = (f"The centre '{run.centre}' has no residual profile "
                                    "matching another location's; location "
                                    f"'{first}' stands in for it. ")
                        else:
                            note = ""
                        role = "centre" if note == "" else "stand-in for the centre"
                        return c, m, note + (f"Shown: {describe(c)} ({role}) and "
                                             f"{describe(m)}, the first other location with "
                                             "a profile at the same orientation, height and "
                                             "mode.")
    return None, None, ("no two locations have residual profiles at the same orientation, "
                        "height and mode")


def choose_orientation_set(run, available):
    """(measurements, note): all orientations at one location, height and mode."""
    best = None
    for location in run.locations:
        groups = {}
        for m in run.measurements:
            if m.location == location and m.id in available:
                groups.setdefault((m.height, m.mode), []).append(m)
        for (height, mode), ms in groups.items():
            count = len({m.orientation_deg for m in ms})
            # Larger is better: enough orientations, the centre, more orientations, then
            # scanning before touch-trigger and middle before other heights.
            key = (count >= 2, location == run.centre, count,
                   -rank(mode, MODE_ORDER)[0], -rank(height, HEIGHT_PREFERENCE)[0])
            if best is None or key > best[0]:
                best = (key, location, height, mode, ms)
    if best is None or not best[0][0]:
        return [], "no location has residual profiles at two or more orientations"
    _, location, height, mode, ms = best
    ms = one_per_orientation(ms)
    if location == run.centre and run.centre_found:
        where = "the centre"
    elif location == run.centre:
        where = (f"location {location} (no location is labelled C/centre/center; the first "
                 "location stands in for it)")
    else:
        where = (f"location {location} (the centre '{run.centre}' has residual profiles at "
                 "fewer than two orientations)" if run.centre_found else
                 f"location {location} (no location is labelled C/centre/center)")
    return ms, (f"Shown: orientations {', '.join(f'{m.orientation_deg:g}°' for m in ms)} at "
                f"{where}, height {height}, {mode.replace('_', '-')} "
                f"(ids {', '.join(m.id for m in ms)}).")


def one_per_orientation(ms):
    """One measurement per orientation, in orientation order.  Where an orientation was
    measured more than once (the demo's C-O000 of the location series and C-R000 of the
    orientation series), the one nearest in results.csv to the measurements at the other
    orientations is taken: the one of the same series (ties: the first in the file)."""
    by_orientation = {}
    for m in sorted(ms, key=lambda m: m.line):
        by_orientation.setdefault(m.orientation_deg, []).append(m)
    single = [c[0].line for c in by_orientation.values() if len(c) == 1]
    chosen = []
    for orientation in sorted(by_orientation):
        candidates = by_orientation[orientation]
        if len(candidates) > 1 and single:
            candidates = sorted(candidates,
                                key=lambda m: min(abs(m.line - line) for line in single))
        chosen.append(candidates[0])
    return chosen


def choose_histograms(run, available):
    """Up to two measurements: one per mode (scanning first), centre and middle preferred."""
    chosen = []
    modes = sorted({m.mode for m in run.measurements}, key=lambda x: rank(x, MODE_ORDER))
    for mode in modes[:2]:
        candidates = sorted((m for m in run.measurements if m.mode == mode
                             and m.id in available),
                            key=lambda m: (m.location != run.centre,) + preference(m))
        if candidates:
            chosen.append(candidates[0])
    return chosen


def available_ids(run, subdirectory):
    directory = os.path.join(run.outdir, subdirectory)
    if not os.path.isdir(directory):
        return set()
    return {m.id for m in run.measurements
            if os.path.isfile(os.path.join(directory, m.id + ".csv"))}


# --------------------------------------------------------------------------------------------
# Figures
# --------------------------------------------------------------------------------------------

@dataclasses.dataclass
class Figure:
    filename: str
    title: str
    caption: str
    # What was drawn, for the tests and for anyone checking a figure without looking at it:
    # every non-empty text of the figure (titles, tick labels, legend entries) and, for the
    # per-measurement figures, the number of points of each series, keyed "panel: label".
    texts: list = dataclasses.field(default_factory=list)
    series: dict = dataclasses.field(default_factory=dict)
    # Axis limits that follow the data, e.g. {"polar": (low, high), "data": (min, max)}.
    limits: dict = dataclasses.field(default_factory=dict)
    # Numbers drawn as bars, e.g. the budget's median shares (%) keyed (measurand, mode,
    # source).
    values: dict = dataclasses.field(default_factory=dict)


def import_matplotlib():
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError as e:
        raise MissingDependency(f"matplotlib/numpy not available to {sys.executable} ({e}); "
                                "run `vcmm report OUTDIR`, which finds a Python that has "
                                "them, or install them: apt-get install python3-matplotlib "
                                "python3-numpy") from None
    plt.rcParams.update({
        "font.size": 9, "axes.titlesize": 10, "axes.labelsize": 9, "legend.fontsize": 8,
        "xtick.labelsize": 8, "ytick.labelsize": 8, "axes.grid": True, "grid.alpha": 0.3,
        "savefig.dpi": DPI, "svg.hashsalt": "vcmm", "svg.fonttype": "none",
        "pdf.fonttype": 42,
    })
    return plt, np


def save(plt, fig, path):
    """Writes the figure as PNG (DPI), SVG and PDF beside each other (path ends in .png),
    each atomically; closes the figure; returns every non-empty text drawn."""
    import matplotlib.text
    # No date or software version in the files: the same input gives the same bytes.
    metadata = {"png": {"Software": None}, "svg": {"Date": None},
                "pdf": {"CreationDate": None, "Producer": None}}
    stem = os.path.splitext(path)[0]
    try:
        texts = [t.get_text() for t in fig.findobj(matplotlib.text.Text)
                 if t.get_text() and t.get_visible()]
        for kind in FIGURE_FORMATS:
            write_atomically(stem + "." + kind, lambda f, kind=kind: fig.savefig(
                f, format=kind, dpi=DPI, bbox_inches="tight", metadata=metadata[kind]))
    finally:
        plt.close(fig)
    return texts


def top_legend(fig, handles, ncol, title):
    """Bold title and a legend in a strip at the top, the axes laid out below them."""
    height = fig.get_figheight()
    rows = math.ceil(len(handles) / ncol)
    strip = (0.35 + 0.22 * rows) / height          # inches of title + legend, as a fraction
    fig.suptitle(title, y=1.0 - 0.05 / height, va="top", fontweight="bold")
    fig.legend(handles=handles, loc="upper center", bbox_to_anchor=(0.5, 1.0 - 0.3 / height),
               ncol=ncol, frameon=False)
    fig.tight_layout(rect=(0.0, 0.0, 1.0, 1.0 - strip), pad=0.5)


def two_row_legend(plt, first, second):
    """(handles, ncol) of a legend with `first` in its top row and `second` below: matplotlib
    fills a legend column by column, so the rows are interleaved and the shorter one padded
    with blank entries."""
    if not second:
        return first, len(first)
    ncol = max(len(first), len(second))

    def padded(row):
        return row + [plt.Line2D([], [], ls="", label=" ") for _ in range(ncol - len(row))]
    return [h for pair in zip(padded(first), padded(second)) for h in pair], ncol


def marker_of(mode, modes):
    if mode in MODE_MARKERS:
        return MODE_MARKERS[mode]
    others = [m for m in modes if m not in MODE_MARKERS]
    return EXTRA_MARKERS[others.index(mode) % len(EXTRA_MARKERS)]


def nice_ceil(x):
    """Smallest 1, 2, 2.5 or 5 x 10^e that is >= x (x > 0)."""
    if not x > 0:
        return 1.0
    e = 10.0 ** math.floor(math.log10(x))
    for m in (1.0, 2.0, 2.5, 5.0, 10.0):
        if m * e >= x * (1.0 - 1e-12):
            return m * e
    return 10.0 * e


def gum_decimals(u):
    """Decimal places that give the standard uncertainty u two significant digits (GUM
    7.2.6: u to at most two significant digits, the value to the same decimal place); None
    when u is not a positive finite number.  Never negative: 29 um stays '29'."""
    if u is None or not math.isfinite(u) or not u > 0:
        return None
    decimals = 1 - math.floor(math.log10(u))
    if decimals > 0 and round(u, decimals) >= 10.0 ** (2 - decimals):
        decimals -= 1                  # 0.0996 rounds to 0.100: two digits are '0.10'
    return max(0, decimals)


def format_with_uncertainty(value, u, *, signed=False, fallback=".4g"):
    """value rounded to the decimal place of u's second significant digit (GUM style), e.g.
    a bias of +0.000828 um next to u = 0.291 um is '+0.00'.  No '-0.00'."""
    if value is None:
        return "n/a"
    decimals = gum_decimals(u)
    text = format(value, ("+" if signed else "") + (fallback if decimals is None else
                                                    f".{decimals}f"))
    if decimals is not None and float(text) == 0.0:
        text = ("+" if signed else "") + format(0.0, f".{decimals}f")
    return text


def series_offsets(count):
    """x offsets of `count` series sharing a panel: side by side within SERIES_SPREAD of the
    measurement's position, so that no marker hides another."""
    if count <= 1:
        return [0.0]
    step = SERIES_SPREAD / (count - 1)
    return [-SERIES_SPREAD / 2 + i * step for i in range(count)]


def measurement_figure(plt, ms, panels, panel_height):
    """A figure of `panels` stacked panels sharing the measurement axis."""
    width = min(28.0, max(10.0, 0.24 * len(ms) + 3.0))
    fig, axes = plt.subplots(panels, 1, sharex=True, squeeze=False,
                             figsize=(width, panel_height * panels + 1.6))
    return fig, list(axes[:, 0])


def draw_setup_boundaries(ax, ms):
    """Solid grey lines between locations, dotted ones between the set-ups (orientation or a
    repeat of it) of one location."""
    for i in range(1, len(ms)):
        if ms[i].location != ms[i - 1].location:
            ax.axvline(i - 0.5, color="0.6", lw=0.8)
        elif (ms[i].orientation_deg, ms[i].repeat) != (ms[i - 1].orientation_deg,
                                                       ms[i - 1].repeat):
            ax.axvline(i - 0.5, color="0.7", lw=0.7, ls=":")


def label_measurement_axis(ax, run, ms):
    """Horizontal labels of the shared measurement axis on three levels: under each
    measurement its height initial (t, m, b; the marker gives the mode), under each set-up
    its orientation (a repeated set-up marked ′), under each location its name in bold."""
    ax.set_xlim(-0.6, len(ms) - 0.4)
    multiple_heights = len({m.height for m in ms}) > 1
    ax.set_xticks(range(len(ms)), [m.height[:1] if multiple_heights else "" for m in ms],
                  minor=True)
    ax.tick_params(axis="x", which="minor", labelsize=8, length=2)
    blocks = []            # [first index, last index, (location, orientation, repeat)]
    for i, m in enumerate(ms):
        key = (m.location, m.orientation_deg, m.repeat)
        if blocks and blocks[-1][2] == key:
            blocks[-1][1] = i
        else:
            blocks.append([i, i, key])
    setup_offset = -16.0 if multiple_heights else -4.0      # points below the axis
    for first, last, (_, orientation, repeat) in blocks:
        ax.annotate(f"{orientation:g}°" + "′" * repeat, xy=(0.5 * (first + last), 0.0),
                    xycoords=("data", "axes fraction"), xytext=(0.0, setup_offset),
                    textcoords="offset points", ha="center", va="top", fontsize=8,
                    color="0.25", annotation_clip=False)
    centres, names = [], []
    for location in run.locations:
        idx = [i for i, m in enumerate(ms) if m.location == location]
        if idx:
            centres.append(0.5 * (idx[0] + idx[-1]))
            names.append(location)
    ax.set_xticks(centres, names)
    ax.tick_params(axis="x", which="major", length=0, pad=-setup_offset + 14.0, labelsize=10)
    for label in ax.get_xticklabels(minor=False):
        label.set_fontweight("bold")
    ax.set_xlabel("measurement: "
                  + ("height (t top, m middle, b bottom) / " if multiple_heights else "")
                  + "set-up orientation (′ a repeated set-up) / location (bold); solid lines "
                  "separate locations, dotted lines set-ups; marker = mode", labelpad=6)


def mode_legend(plt, modes):
    return [plt.Line2D([], [], ls="", marker=marker_of(mode, modes), color="0.2",
                       markersize=6, label=mode.replace("_", "-")) for mode in modes]


def series_handle(plt, label, color, filled):
    return plt.Line2D([], [], ls="", marker="o", markersize=6,
                      markerfacecolor=color if filled else "none", markeredgecolor=color,
                      markeredgewidth=1.2, label=label)


def figure_en(plt, np, run, path):
    ms = run.measurements
    x = np.arange(len(ms))
    modes = list(dict.fromkeys(m.mode for m in ms))
    roundness_default = run.default_treatment("roundness")
    diameter_default = run.default_treatment("diameter")

    def has(measurand, column):
        return any(m.value(measurand, column) is not None for m in ms)

    # (treatment, measurand, E_n column, filled marker)
    diameter = [("uncorrected", "diameter", "En", True),
                ("corrected", "diameter", "En_corrected", False)]
    if diameter_default != "paper":
        diameter.append(("paper", "diameter", "En_paper", True))
    panels = [
        (f"Diameter (default treatment: {diameter_default})", diameter),
        ("Roundness, uncorrected", [("uncorrected", "roundness", "En", True)]),
        (f"Roundness, corrected by the default treatment '{roundness_default}'"
         + (" = (a) the seed study's" if roundness_default == "paper" else "")
         + f": {BIAS_TREATMENT_DESCRIPTIONS[roundness_default]}",
         [("corrected", "roundness", "En_corrected", False)]),
    ]
    if roundness_default != "paper":
        panels.append(("Roundness, (a) the seed study's correction, beside the default: bias "
                       "= Monte Carlo mean − estimate of the virtual experiment on the "
                       "measured profile", [("paper", "roundness", "En_paper", True)]))
    has_b, has_c = has("roundness", "En_denoised"), has("roundness", "En_inflated")
    if has_b or has_c:
        parts = ((["(b) bias from the denoised profile"] if has_b else [])
                 + (["(c) no correction, U enlarged by |b| of (a)"] if has_c else []))
        panels.append((("Roundness, treatments " if len(parts) == 2 else "Roundness, treatment ")
                       + " and ".join(parts),
                       ([("denoised", "roundness", "En_denoised", True)] if has_b else [])
                       + ([("inflated", "roundness", "En_inflated", False)] if has_c else [])))
    fig, axes = measurement_figure(plt, ms, len(panels), 2.4)
    handles = {}
    drawn = {}
    clipped_total = 0
    for ax, (title, series) in zip(axes, panels):
        ax.axhspan(-1.0, 1.0, color="tab:green", alpha=0.08, lw=0)
        for y in (-1.0, 1.0):
            ax.axhline(y, color="tab:red", lw=1.0, ls="--")
        ax.axhline(0.0, color="0.3", lw=0.8)
        draw_setup_boundaries(ax, ms)
        refused = sorted({i for i, m in enumerate(ms) for _, measurand, column, _ in series
                          if measurand in m.rows and not m.rows[measurand].applied(column)})
        for i in refused:
            ax.axvspan(i - 0.45, i + 0.45, color="0.5", alpha=0.25, lw=0)
        if refused:
            handles["refused"] = plt.Rectangle((0, 0), 1, 1, color="0.5", alpha=0.35)
        values_all = [m.value(s[1], s[2]) for s in series for m in ms]
        values_all = [abs(v) for v in values_all if v is not None]
        if not values_all:
            ax.text(0.5, 0.5, "no values in results.csv", transform=ax.transAxes,
                    ha="center", va="center", color="0.4")
        top = min(EN_AXIS_CAP, max(1.5, 1.2 * max(values_all, default=0.0)))
        for offset, (treatment, measurand, column, filled) in zip(series_offsets(len(series)),
                                                                  series):
            color = TREATMENT_COLORS[treatment]
            label = f"$E_n$ {run.label(treatment)}"
            count = 0
            for mode in modes:
                idx = [i for i, m in enumerate(ms)
                       if m.mode == mode and m.value(measurand, column) is not None]
                if not idx:
                    continue
                values = np.array([ms[i].value(measurand, column) for i in idx])
                shown = np.clip(values, -0.97 * top, 0.97 * top)
                # Hollow markers have no face and the filled (uncorrected) ones are drawn
                # on top, so no marker hides another even where values coincide.
                ax.scatter(x[idx] + offset, shown, marker=marker_of(mode, modes), s=30,
                           zorder=4 if filled else 3, facecolors=color if filled else "none",
                           edgecolors=color, linewidths=1.2)
                count += len(idx)
                for i, v, s in zip(idx, values, shown):
                    if v != s:
                        clipped_total += 1
                        ax.annotate(f"{v:.3g}", (x[i] + offset, s), textcoords="offset points",
                                    xytext=(4, -3 if v > 0 else 3), fontsize=7,
                                    color="tab:red", va="top" if v > 0 else "bottom")
            drawn[f"{title}: {run.label(treatment, measurand)}"] = count
            if count:
                handles.setdefault(("series", treatment),
                                   series_handle(plt, label, color, filled))
        ax.set_ylim(-top, top)
        ax.set_ylabel("$E_n$")
        ax.set_title(title, loc="left", fontsize=9)
        ax.grid(False, axis="x")
    label_measurement_axis(axes[-1], run, ms)
    axes[-1].grid(False, axis="x", which="both")
    first = [handles[("series", t)] for t in TREATMENTS if ("series", t) in handles]
    second = mode_legend(plt, modes)
    second.append(plt.Rectangle((0, 0), 1, 1, color="tab:green", alpha=0.15,
                                label=r"$|E_n| \leq 1$"))
    second.append(plt.Line2D([], [], color="tab:red", lw=1.0, ls="--", label="±1"))
    if "refused" in handles:
        h = handles["refused"]
        h.set_label("correction refused (would be negative)")
        second.append(h)
    legend, ncol = two_row_legend(plt, first, second)
    top_legend(fig, legend, ncol, "$E_n$ per measurement: " + EN_DEFINITION_TEX
               + f", k = {run.coverage_factor:g} (positive: the CMM reads low)")
    limits = {"tick_rotations": [t.get_rotation() for t in
                                 axes[-1].get_xticklabels(which="both") if t.get_text()]}
    texts = save(plt, fig, path)
    default_text = (f"the default treatment '{roundness_default}' (hollow orange; "
                    + BIAS_TREATMENT_DESCRIPTIONS[roundness_default] + ")")
    caption = (
        "E_n = (reference − measured) / √(U_ref² + U²) (positive: the CMM reads low) of "
        "every measurement, one panel per measurand and treatment: the diameter (filled blue: "
        f"uncorrected; hollow orange: corrected by its default treatment, {diameter_default}"
        + ("; filled brown: (a) the seed study's" if diameter_default != "paper" else "")
        + "), the roundness uncorrected, the roundness corrected by " + default_text
        + (", and, in the panel below it, by (a) the seed study's correction (filled brown; "
           "bias = Monte Carlo mean − estimate on the measured profile), so that the two "
           "can be compared measurement by measurement"
           if roundness_default != "paper" else
           ", which is the seed study's correction (a)")
        + (", and roundness with treatment (b) (bias from the virtual experiment on the "
           "filtered, denoised profile; filled green)" if has_b else "")
        + ((" and" if has_b else ", and roundness with") + " treatment (c) (no correction, "
           "U enlarged to k·u + |b| with b of (a); hollow purple)" if has_c else "")
        + ". Where two series share a panel they are drawn side by side, slightly apart, so "
        "that neither hides the other. Measurements are grouped by location (solid lines) "
        "and set-up (dotted lines), then ordered by height and mode; the marker shape gives "
        "the mode. The green band is "
        "|E_n| ≤ 1: with honest uncertainties about 95 % of the points fall inside it and "
        f"they scatter symmetrically about 0 with an RMS of about {run.expected_rms:.3g}. "
        "Points systematically "
        "on one side reveal a bias; points crowding near 0 reveal overstated uncertainties."
        + (" Grey columns mark measurements whose correction (of the panel's treatment) was "
           "refused because it would have made the roundness negative; that treatment then "
           "reports the estimate itself." if "refused" in handles else "")
        + (f" {clipped_total} value(s) beyond ±{EN_AXIS_CAP:g} are drawn at the edge with "
           "their value written beside them." if clipped_total else "")
        + f" k = {run.coverage_factor:g} ({run.coverage_factor_source}).")
    return Figure(os.path.basename(path), "E_n per measurement", caption, texts, drawn,
                  limits)


def figure_errors(plt, np, run, path):
    """Reported − true value per measurement, with ±U bars, for the uncorrected value, the
    default treatment and the seed study's: does each cover the truth?"""
    ms = run.measurements
    x = np.arange(len(ms))
    modes = list(dict.fromkeys(m.mode for m in ms))
    k = run.coverage_factor
    panels = []
    for measurand in MEASURANDS:
        if not any(m.value(measurand, "true_value") is not None for m in ms):
            continue
        # (treatment, value column, standard-uncertainty column, filled marker)
        series = [("uncorrected", "estimate", "u", True),
                  ("corrected", "corrected", "u_corrected", False)]
        if not run.default_is_paper(measurand):
            series.append(("paper", "corrected_paper", "u_corrected_paper", True))
        panels.append((measurand, series))
    fig, axes = measurement_figure(plt, ms, len(panels), 3.0)
    handles = {}
    drawn = {}
    for ax, (measurand, series) in zip(axes, panels):
        unit = next(m.rows[measurand].unit for m in ms if measurand in m.rows)
        factor = 1000.0 if unit == "mm" else 1.0          # shown in µm
        ax.axhline(0.0, color="0.3", lw=0.9)
        draw_setup_boundaries(ax, ms)
        coverage = []
        for offset, (treatment, column, u_column, filled) in zip(
                series_offsets(len(series)), series):
            color = TREATMENT_COLORS[treatment]
            idx = [i for i, m in enumerate(ms) if m.value(measurand, "true_value") is not None
                   and m.value(measurand, column) is not None]
            errors = np.array([(ms[i].value(measurand, column)
                                - ms[i].value(measurand, "true_value")) * factor for i in idx])
            expanded = np.array([k * (ms[i].value(measurand, u_column) or 0.0) * factor
                                 for i in idx])
            if idx:
                ax.errorbar(x[idx] + offset, errors, yerr=expanded, fmt="none", ecolor=color,
                            elinewidth=1.0, alpha=0.55, capsize=0, zorder=2)
            for mode in modes:
                sel = [j for j, i in enumerate(idx) if ms[i].mode == mode]
                if sel:
                    ax.scatter(x[[idx[j] for j in sel]] + offset, errors[sel],
                               marker=marker_of(mode, modes), s=28, zorder=4 if filled else 3,
                               facecolors=color if filled else "none", edgecolors=color,
                               linewidths=1.2)
            covered = int(np.sum(np.abs(errors) <= expanded)) if idx else 0
            short = run.label(treatment, measurand)
            coverage.append(f"{short}: {covered}/{len(idx)}")
            drawn[f"{measurand}: {short}"] = len(idx)
            if idx:
                handles.setdefault(treatment, series_handle(
                    plt, run.label(treatment) + f" ± U (k = {k:g})" + (
                        ", U = k·u_corrected (incl. u_bias)" if treatment == "corrected" else
                        ", U = k·u_corrected_paper" if treatment == "paper" else ", U = k·u"),
                    color, filled))
        ax.text(0.005, 0.97, "truth within ±U — " + "; ".join(coverage),
                transform=ax.transAxes, va="top", ha="left", fontsize=8,
                bbox={"facecolor": "white", "alpha": 0.85, "lw": 0})
        low, high = ax.get_ylim()
        ax.set_ylim(low, high + 0.12 * (high - low))      # room for the coverage line
        ax.set_ylabel("reported − true (µm)")
        ax.set_title(f"{measurand.capitalize()}: reported − true value (µm"
                     + ("; converted from mm" if factor != 1.0 else "")
                     + f"), bars ±U (k = {k:g}) = {k:g}·u of the treatment", loc="left",
                     fontsize=9)
        ax.grid(False, axis="x")
    label_measurement_axis(axes[-1], run, ms)
    axes[-1].grid(False, axis="x", which="both")
    legend, ncol = two_row_legend(plt, [handles[t] for t in TREATMENTS if t in handles],
                                  mode_legend(plt, modes))
    top_legend(fig, legend, ncol,
               "Error against the truth per measurement (demo: reported − true value)")
    texts = save(plt, fig, path)
    default = run.default_treatment("roundness")
    caption = (
        "For every measurement whose true value the run knows (the demo), the reported value "
        "minus the true value, in µm (diameter converted from mm), for the uncorrected "
        "estimate (filled blue), the default treatment (hollow orange; roundness: "
        f"'{default}'"
        + (", whose u_corrected includes u_bias, the standard uncertainty of the bias "
           "estimate itself" if default == "shrinkage" else "")
        + ") and"
        + (" (a) the seed study's correction (filled brown), side by side at each "
           "measurement" if default != "paper" else " nothing else: the default is the "
           "seed study's correction (a)")
        + f". Each bar is ±U = {k:g}·u with the u that treatment reports (uncorrected: u; "
        "default: u_corrected; seed study: u_corrected_paper). A bar that crosses zero "
        "covers the truth; the counts are written in each panel. With honest uncertainties "
        "about 95 % of the bars cross zero and the points scatter about zero."
        + (" Diameter: the default is the seed study's correction, so only two series are "
           "drawn." if run.default_is_paper("diameter") and default != "paper" else ""))
    return Figure(os.path.basename(path), "Error against the truth per measurement", caption,
                  texts, drawn)


REFERENCE_CIRCLE_NAMES = {"MZ": "minimum-zone (MZ)", "MI": "maximum-inscribed (MI)",
                          "LS": "least-squares (LS)", "MC": "minimum-circumscribed (MC)"}


def reference_and_filter(run):
    """(reference circle symbol, its name, filter text) from run_info.json, each saying so
    when run_info.json does not state it."""
    info = run.run_info or {}
    symbol = info.get("reference_circle")
    if isinstance(symbol, str) and symbol in REFERENCE_CIRCLE_NAMES:
        name = REFERENCE_CIRCLE_NAMES[symbol]
    else:
        symbol, name = "reference", "reference circle not stated in run_info.json"
    if "filter_cutoff_upr" not in info:
        filter_text = "filter not stated in run_info.json"
    elif isinstance(info["filter_cutoff_upr"], (int, float)) \
            and not isinstance(info["filter_cutoff_upr"], bool):
        filter_text = f"Gaussian filter {info['filter_cutoff_upr']:g} UPR"
    else:
        filter_text = "unfiltered"
    return symbol, name, filter_text


def figure_residuals(plt, np, run, profiles, path, title, selection_note, kind):
    colors = ["C0", "C3", "C2", "C1", "C4", "C5", "C6", "C7"]
    symbol, circle_name, filter_text = reference_and_filter(run)
    # The unrolled panels show every point; the polar plot's radial axis (µm) follows the
    # filtered profiles, whose zone RONt is evaluated on: 'nice' rings from just below the
    # smallest to just above the largest filtered deviation (and 0), so that a 1 µm form is
    # not flattened by the noise of the unfiltered points, which are drawn only within it.
    lowest = min(min(min(p.deviation_um), min(p.filtered_um)) for _, p in profiles)
    highest = max(max(max(p.deviation_um), max(p.filtered_um)) for _, p in profiles)
    lowest, highest = min(lowest, 0.0), max(highest, 0.0)
    span = highest - lowest if highest > lowest else 1.0
    filtered_low = min(0.0, min(min(p.filtered_um) for _, p in profiles))
    filtered_high = max(0.0, max(max(p.filtered_um) for _, p in profiles))
    margin = 0.1 * (filtered_high - filtered_low)
    step = nice_ceil((filtered_high - filtered_low) / 4.0) if filtered_high > filtered_low \
        else 0.1
    r_low = step * math.floor((filtered_low - margin) / step + 1e-9)
    r_high = step * math.ceil((filtered_high + margin) / step - 1e-9)
    r_span = r_high - r_low

    n = len(profiles)
    fig = plt.figure(figsize=(13.5, max(6.4, 1.9 * n + 2.4)))
    grid = fig.add_gridspec(n, 2, width_ratios=(1.0, 1.3), hspace=0.18, wspace=0.2)
    polar = fig.add_subplot(grid[:, 0], projection="polar")
    polar.set_axisbelow(False)           # rings and their labels above the data
    theta = np.linspace(0.0, 2.0 * np.pi, 721)
    unrolled = []
    legend = []
    ronts = {}
    for i, ((m, p), color) in enumerate(zip(profiles, colors)):
        label = {"locations": f"location {m.location}",
                 "orientations": f"orientation {m.orientation_deg:g}°"}[kind]
        angle = np.radians(np.array(p.angle_deg))
        deviation = np.array(p.deviation_um)
        filtered = np.array(p.filtered_um)
        inner, outer = float(filtered.min()), float(filtered.max())
        ront = outer - inner
        ront_text = format_with_uncertainty(ront, m.value("roundness", "u"))
        ronts[m.id] = ront
        inside = (deviation >= r_low) & (deviation <= r_high)
        polar.scatter(angle[inside], deviation[inside], s=3, color=color, alpha=0.25, lw=0,
                      zorder=1)
        closed_angle = np.append(angle, angle[0] + 2.0 * np.pi)
        closed = np.append(filtered, filtered[0])
        legend.append(polar.plot(closed_angle, closed, color=color, lw=1.5, zorder=2,
                                 label=f"{label} ({m.id}), RONt = {ront_text} µm")[0])
        for r in (inner, outer):       # the zone of the reference circle: RONt wide
            polar.plot(theta, np.full_like(theta, r), color=color, lw=1.0, ls=":", zorder=3)
        ax = fig.add_subplot(grid[i, 1], sharex=unrolled[0] if unrolled else None,
                             sharey=unrolled[0] if unrolled else None)
        unrolled.append(ax)
        ax.axhline(0.0, color="0.2", lw=1.0, ls="--", zorder=4)
        for r in (inner, outer):
            ax.axhline(r, color=color, lw=1.0, ls=":", zorder=3)
        ax.scatter(p.angle_deg, deviation, s=5, color=color, alpha=0.3, lw=0,
                   label="unfiltered", zorder=1)
        ax.plot(p.angle_deg, filtered, color=color, lw=1.4, label=f"filtered ({filter_text})",
                zorder=2)
        ax.text(0.01, 0.96, f"{label}: {m.id}", transform=ax.transAxes, va="top",
                fontsize=8, bbox={"facecolor": "white", "alpha": 0.85, "lw": 0}, zorder=5)
        ax.text(0.99, 0.96, f"RONt ({symbol}, {filter_text}) = {ront_text} µm",
                transform=ax.transAxes, va="top", ha="right", fontsize=8,
                bbox={"facecolor": "white", "alpha": 0.85, "lw": 0}, zorder=5)
        ax.set_ylabel("deviation (µm)")
        if i < n - 1:
            ax.tick_params(labelbottom=False)
    unrolled[0].set_xlim(0.0, 360.0)
    unrolled[0].set_xticks(range(0, 361, 45))
    # Room above the data for the two labels of each panel.
    unrolled[0].set_ylim(lowest - 0.08 * span, highest + 0.35 * span)
    unrolled[-1].set_xlabel("angle about the reference-circle centre (°)")
    unrolled[-1].legend(loc="lower right", ncol=2, fontsize=7, markerscale=2,
                        framealpha=0.85)

    # The deviation annulus occupies the outer half of the polar plot's radius; the hole
    # keeps the base circle (deviation 0) well away from the centre.
    polar.set_rorigin(r_low - 1.2 * r_span)
    polar.set_ylim(r_low, r_high)
    rings = [r_low + j * step for j in range(int(round(r_span / step)) + 1)]
    polar.set_yticks(rings)
    polar.set_yticklabels(["0" if abs(r) < 1e-9 * step else f"{r:+.10g}".replace("-", "−")
                           for r in rings],
                          fontsize=8)
    polar.set_rlabel_position(100.0)
    for tick in polar.get_yticklabels():
        tick.set_bbox({"facecolor": "white", "alpha": 0.85, "lw": 0, "pad": 1})
    base = polar.plot(theta, np.zeros_like(theta), color="black", lw=1.3, ls="--", zorder=4,
                      label=f"base circle: 0 = the {symbol} reference circle")[0]
    polar.set_thetagrids(range(0, 360, 45))
    polar.set_title(f"deviation about the {symbol} circle (µm): rings every {step:g} µm,\n"
                    "base circle dashed, zone dotted; radius not to scale", fontsize=9)
    zone = plt.Line2D([], [], color="0.3", lw=1.0, ls=":",
                      label=f"{symbol} zone: the two circles RONt apart enclosing the "
                            "filtered profile")
    polar.legend(handles=legend + [base, zone], loc="upper center",
                 bbox_to_anchor=(0.5, -0.06), fontsize=7, ncol=1, frameon=False)
    fig.suptitle(f"{title} — RONt about the {circle_name} circle, {filter_text}",
                 fontweight="bold")
    limits = {"polar": tuple(polar.get_ylim()), "unrolled": tuple(unrolled[0].get_ylim()),
              "filtered": (filtered_low, filtered_high), "all": (lowest, highest)}
    texts = save(plt, fig, path)
    caption = (
        "Radial deviations of the corrected measured profile about the run's reference "
        f"circle ({circle_name}; {filter_text}), "
        + ("at two locations (same orientation, height and mode)" if kind == "locations"
           else "at one location, every orientation")
        + ". Left: polar plot with the radial axis in µm, scaled to the filtered profiles "
        f"(rings every {step:g} µm from {r_low:+.10g} to {r_high:+.10g} µm; unfiltered points "
        "outside that range are left out here; the radius itself is not to scale): the "
        "black dashed base circle is zero deviation, i.e. the reference circle; "
        "the dotted circles of each profile's colour are its zone — the two circles "
        "concentric with the reference circle that enclose the filtered profile, RONt "
        f"apart (for MZ the minimum zone; for MI the inner one is the reference circle). "
        "Right: the same profiles unrolled, angle against deviation in µm, with the zone "
        "lines. Lines are the filtered deviations, faint points the unfiltered ones; RONt is "
        "written with the decimal places of the measurement's u (two significant digits). "
        + ("A form that stays put between the locations belongs to the ring; one that "
           "changes (e.g. an added 2-lobe oval) comes from the machine's error map at that "
           "location. " if kind == "locations" else
           "The angles are those of the residual files (about the reference-circle centre): "
           "if they are machine coordinates, the ring's own form turns with the orientation "
           "(its lobes shift by the orientation angle) while a machine error stays at the "
           "same angle; in workpiece coordinates it is the other way round. "
           + (f"run_info.json states the angles are "
              f"'{run.run_info['residual_angles']}'. "
              if isinstance((run.run_info or {}).get("residual_angles"), str) else ""))
        + selection_note)
    return Figure(os.path.basename(path), title, caption, texts, limits=limits)


def figure_histogram(plt, np, run, m, samples, path):
    k = run.coverage_factor
    p = run.coverage_probability
    interval_label = ("coverage interval" if p is None else
                      f"{100 * p:g} % coverage interval")
    fig, axes = plt.subplots(1, 2, figsize=(14.0, 5.8))
    warnings = []
    handles = {}
    interval_texts = []    # the ladder's intervals as written numbers, for the tests
    limits = {}
    for ax, measurand in zip(axes, MEASURANDS):
        row = m.rows.get(measurand)
        if row is None:
            ax.text(0.5, 0.5, f"no {measurand} row in results.csv", transform=ax.transAxes,
                    ha="center", va="center")
            continue
        v = row.values
        if measurand == "diameter":
            # Display in um relative to the reference (else the estimate): differences are
            # sub-um on ~100 mm.
            if v["reference"] is not None:
                origin = v["reference"]
                xlabel = f"diameter − reference (µm); reference D = {origin:.6f} mm"
            else:
                origin = v["estimate"]
                xlabel = f"diameter − estimate (µm); estimate D = {origin:.6f} mm"
            factor = 1000.0
        else:
            origin, factor = 0.0, 1.0
            xlabel = "roundness RONt (µm)"
        data = (np.array(samples[measurand]) - origin) * factor

        def shown(value):
            return (value - origin) * factor

        bins = int(min(80, max(10, round(math.sqrt(len(data))))))
        counts, _, _ = ax.hist(data, bins=bins, color="0.78", edgecolor="0.6", lw=0.4,
                               zorder=2)
        # Headroom above the histogram for the ladder of intervals.
        ax.set_ylim(0.0, 1.55 * max(counts))
        default_is_paper = row.treatment == "paper"
        # One decimal place for every number of the panel: two significant digits of the
        # smallest standard uncertainty the row reports (GUM 7.2.6).
        decimals_u = min(x for x in (v["u"], v["u_corrected"], v["u_corrected_paper"], 1e300)
                         if x > 0) * factor

        def number(value, *, signed=False):
            return format_with_uncertainty(None if value is None else value * factor,
                                           decimals_u, signed=signed)

        def clamp(low):
            return low if measurand == "diameter" else max(0.0, low)
        if v["reference"] is not None:
            ref = shown(v["reference"])
            band = k * v["u_reference"] * factor
            handles.setdefault("refband", ax.axvspan(
                ref - band, ref + band, color="tab:red", alpha=0.10, lw=0, zorder=1,
                label=f"reference ± U_ref (k = {k:g})"))
        # Vertical lines: the estimate thin black on top of the Monte Carlo mean, drawn wide
        # and translucent, so that each stays visible when they (nearly) coincide.
        lines = [
            ("reference", v["reference"], "tab:red", "-", 1.6, 1.0, 3),
            ("estimate from data", v["estimate"], "black", "-", 1.2, 1.0, 6),
            ("Monte Carlo mean (seed-study run)", v["mc_mean"], "tab:blue", (0, (4, 2)), 3.2,
             0.55, 5),
            (interval_label, v["interval_low"], "tab:blue", ":", 1.4, 1.0, 4),
            (None, v["interval_high"], "tab:blue", ":", 1.4, 1.0, 4),
        ]
        if v["true_value"] is not None:
            lines.append(("true value", v["true_value"], "tab:purple", "-.", 1.5, 1.0, 4))
        for label, value, color, style, width, alpha, z in lines:
            if value is None:
                continue
            h = ax.axvline(shown(value), color=color, ls=style, lw=width, alpha=alpha,
                           zorder=z)
            if label:
                h.set_label(label)
                handles.setdefault(label, h)
        # The ladder of intervals above the histogram (axes-fraction heights): each
        # treatment's reported value with its expanded uncertainty U = k·u (the corrected
        # intervals), and the reference's.
        ladder = [("uncorrected ± U", v["estimate"], v["estimate"] - k * v["u"],
                   v["estimate"] + k * v["u"], TREATMENT_COLORS["uncorrected"], "o")]
        ladder.append(("default corrected ± U_c (incl. u_bias)", v["corrected"],
                       v["corrected"] - k * v["u_corrected"],
                       v["corrected"] + k * v["u_corrected"], TREATMENT_COLORS["corrected"],
                       "D"))
        if not default_is_paper:
            ladder.append(("(a) corrected ± U_c", v["corrected_paper"],
                           v["corrected_paper"] - k * v["u_corrected_paper"],
                           v["corrected_paper"] + k * v["u_corrected_paper"],
                           TREATMENT_COLORS["paper"], "s"))
        if v["reference"] is not None:
            ladder.append(("reference ± U_ref", v["reference"],
                           v["reference"] - k * v["u_reference"],
                           v["reference"] + k * v["u_reference"], "tab:red", "o"))
        transform = ax.get_xaxis_transform()
        for j, (label, centre, low, high, color, marker) in enumerate(ladder):
            y = 0.95 - 0.045 * j
            h = ax.plot([shown(clamp(low)), shown(high)], [y, y], color=color, lw=2.4,
                        solid_capstyle="butt", transform=transform, zorder=7,
                        label=label)[0]
            ax.plot([shown(centre)], [y], marker=marker, color=color, markersize=6,
                    markerfacecolor="white",
                    markeredgewidth=1.5, transform=transform, zorder=8)
            handles.setdefault(label, h)
            interval_texts.append(f"{measurand}: {label}: [{number(clamp(low))}, "
                                  f"{number(high)}]")
        # Consistency of the samples file with results.csv: their mean should agree with
        # mc_mean within a few standard errors u/sqrt(M) (5 here: a chance of 6e-7).
        mean = float(np.mean(samples[measurand]))
        standard_error = v["u"] / math.sqrt(len(data)) if v["u"] > 0 else 0.0
        if abs(mean - v["mc_mean"]) > 5.0 * standard_error + 1e-12 * abs(v["mc_mean"]):
            warnings.append(f"the mean of the {measurand} samples ({mean:.7g}) differs from "
                            f"results.csv mc_mean ({v['mc_mean']:.7g}) by more than 5 "
                            "standard errors")

        def en(column):
            return "n/a" if v[column] is None else f"{v[column]:.2f}"
        title = [f"{measurand}, uncorrected: u = {number(v['u'])} µm, U (k = {k:g}) = "
                 f"{number(k * v['u'])} µm, $E_n$ = {en('En')}",
                 f"default ({row.treatment}" + (" = (a)" if default_is_paper else "")
                 + f"): b = {number(v['bias'], signed=True)} µm, "
                 f"u_c = {number(v['u_corrected'])} µm"
                 + (f" (incl. u_bias = {number(v['u_bias'])})" if v["u_bias"] > 0 else "")
                 + f", $E_n$ = {en('En_corrected')}"]
        if not default_is_paper:
            title.append(f"(a) seed study: b = {number(v['bias_paper'], signed=True)} µm, "
                         f"u_c = {number(v['u_corrected_paper'])} µm, "
                         f"$E_n$ = {en('En_paper')}")
        ax.set_title("\n".join(title), fontsize=8.5)
        flags = []
        if not row.correction_applied:
            flags.append("default correction refused\n(would be negative)")
        elif v["corrected"] == 0.0 and v["estimate"] - v["bias"] < 0.0:
            flags.append("default: corrected value\nclamped at 0")
        if not default_is_paper and not row.paper_applied:
            flags.append("(a) correction refused\n(would be negative)")
        if flags:
            ax.text(0.99, 0.70, "\n".join(flags), transform=ax.transAxes, ha="right",
                    va="top", fontsize=8, color="0.25",
                    bbox={"facecolor": "white", "alpha": 0.85, "lw": 0})
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"trials (of M = {len(data)})")
        limits[measurand] = (tuple(ax.get_xlim()), (float(data.min()), float(data.max())))
    order = ["reference", "refband", "estimate from data", "Monte Carlo mean (seed-study run)",
             interval_label, "true value", "uncorrected ± U",
             "default corrected ± U_c (incl. u_bias)", "(a) corrected ± U_c",
             "reference ± U_ref"]
    fig.legend(handles=[handles[key] for key in order if key in handles],
               loc="upper center", bbox_to_anchor=(0.5, 0.0), ncol=4, frameon=False)
    fig.suptitle(f"Monte Carlo samples of {describe(m)}; U = k·u, k = {k:g}",
                 fontweight="bold")
    fig.tight_layout()
    texts = save(plt, fig, path)
    default = run.default_treatment("roundness")
    caption = (
        f"Histograms of the M = {len(samples['diameter'])} Monte Carlo trials of "
        f"{describe(m)} (the seed study's virtual experiment on the measured profile): "
        "diameter (shown in µm relative to the reference diameter) and roundness. Vertical "
        "lines: the estimate from the measured data (thin black), the Monte Carlo mean "
        "(wide translucent blue dashes, so that the estimate stays visible on top of it; "
        "its distance from the estimate is the seed study's bias b of treatment (a)), the "
        f"ends of the {interval_label} (blue dotted"
        + ("" if p is not None else "; its coverage probability is not stated in "
           "run_info.json") + "), the reference value (red) with its expanded uncertainty "
        f"U_ref = {k:g}·u_ref (red band)"
        + (" and the true value of the simulation (purple dash-dot)"
           if any(m.value(x, "true_value") is not None for x in MEASURANDS) else "")
        + ". Above the histogram, one horizontal bar per reported result: the uncorrected "
        "estimate ± U (blue), the value corrected by the default treatment ± U_c (orange; "
        f"roundness: '{default}'"
        + (", whose bias comes from a second Monte Carlo run at a surrogate of the true "
           "profile, not from these samples, and whose u_corrected includes u_bias, the "
           "standard uncertainty of that bias estimate" if default == "shrinkage" else "")
        + ")"
        + (", the value corrected as the seed study does (a) = estimate − b ± U_c (brown)"
           if default != "paper" else "")
        + " and the reference ± U_ref (red); roundness intervals stop at 0. The panel titles give u, U, the bias b, u_c (u_corrected) and "
        "E_n of each treatment, every number of a panel rounded to the decimal place of "
        "two significant digits of its smallest u (GUM 7.2.6). A roundness histogram lying "
        "to the right of the estimate shows the noise bias: noise tends to increase a "
        "peak-to-valley value, in the simulation as on the real machine."
        + "".join(f" Warning: {w}." for w in warnings))
    return Figure(os.path.basename(path), f"Monte Carlo histogram, {m.id}", caption,
                  texts + interval_texts, limits=limits)


def treatment_tick(run, treatment):
    """A treatment's label broken over lines, for the crowded axes of treatments.png."""
    label = run.label(treatment, wrap=True)
    if treatment == "corrected":
        return label.replace("(default: ", "(default:\n")
    return label.replace(" ", "\n", 1) if label.startswith("(") else label


def figure_treatments(plt, np, run, path):
    rows = run.treatments
    treatments = sorted({r.treatment for r in rows}, key=lambda t: rank(t, TREATMENTS))
    measurands = [x for x in MEASURANDS if any(r.measurand == x for r in rows)]
    lookup = {(r.measurand, r.treatment): r for r in rows}
    has_error = any(r.rms_error is not None for r in rows)
    fig, axes = plt.subplots(2 if has_error else 1, 3, figsize=(15.0, 8.2 if has_error
                                                                 else 4.4))
    ticks = [treatment_tick(run, t) for t in treatments]
    axes = np.atleast_2d(axes)
    x = np.arange(len(treatments))
    width = 0.8 / max(1, len(measurands))
    # Not the treatment colours of the other figures: here colour is the measurand.
    colors = {"diameter": "C9", "roundness": "C8"}
    panels = [("mean $E_n$", lambda r: r.mean, EXPECTED_MEAN_EN, "honest 0"),
              ("RMS of $E_n$", lambda r: r.rms, run.expected_rms,
               f"honest {run.expected_rms:.3g}"),
              (r"share $|E_n| \leq 1$ (%)", lambda r: None if r.share is None else 100 * r.share,
               100 * run.expected_share, f"honest {100 * run.expected_share:.1f} %")]
    for ax, (title, get, expected, expected_label) in zip(axes[0], panels):
        for j, measurand in enumerate(measurands):
            values = [get(lookup[(measurand, t)]) if (measurand, t) in lookup else None
                      for t in treatments]
            positions = x + (j - (len(measurands) - 1) / 2) * width
            heights = [0.0 if v is None else v for v in values]
            bars = ax.bar(positions, heights, width * 0.92, color=colors.get(measurand, "C2"),
                          label=measurand)
            for bar, value in zip(bars, values):
                ax.annotate("n/a" if value is None else f"{value:.2f}" if "%" not in title
                            else f"{value:.1f}",
                            (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                            textcoords="offset points",
                            xytext=(0, 2 if bar.get_height() >= 0 else -9),
                            ha="center", fontsize=7)
        ax.axhline(0.0, color="0.3", lw=0.8)
        ax.axhline(expected, color="tab:red", ls="--", lw=1.2, zorder=4)
        ax.annotate(expected_label.replace(" ", "\n", 1), (1.0, expected),
                    xycoords=("axes fraction", "data"), xytext=(3, 0),
                    textcoords="offset points", ha="left", va="center", color="tab:red",
                    fontsize=7)
        ax.set_xticks(x, ticks, fontsize=8)
        ax.set_title(title)
        if "%" in title:
            ax.set_ylim(0, 110)
        else:
            low, high = ax.get_ylim()      # room for the value written under a bar
            ax.set_ylim(min(low * 1.1, -0.1), max(high, 0.6) * 1.08)
    if has_error:
        for ax, measurand in zip(axes[1], measurands):
            unit = next(r.unit for r in rows if r.measurand == measurand)
            factor, unit_shown = (1000.0, "µm") if unit == "mm" else (1.0, "µm")
            for j, (label, get, color) in enumerate((
                    ("mean error", lambda r: r.mean_error, "0.45"),
                    ("RMS error", lambda r: r.rms_error, "0.75"))):
                values = [get(lookup[(measurand, t)]) if (measurand, t) in lookup else None
                          for t in treatments]
                positions = x + (j - 0.5) * 0.4
                ax.bar(positions, [0.0 if v is None else v * factor for v in values], 0.37,
                       color=color, label=label)
            ax.axhline(0.0, color="0.3", lw=0.8)
            ax.set_xticks(x, ticks, fontsize=8)
            ax.set_ylabel(f"{unit_shown}")
            ax.set_title(f"{measurand}: reported value − true value ({unit_shown})")
        for ax in axes[1][len(measurands):]:
            ax.axis("off")
        spare = axes[1][len(measurands)] if len(measurands) < 3 else axes[1][-1]
        spare.legend(handles=[plt.Rectangle((0, 0), 1, 1, color="0.45", label="mean error"),
                              plt.Rectangle((0, 0), 1, 1, color="0.75", label="RMS error")],
                     loc="center left", title="bottom row: error against the truth",
                     frameon=False)
    legend = [plt.Rectangle((0, 0), 1, 1, color=colors.get(m, "C2"), label=m)
              for m in measurands]
    legend.append(plt.Line2D([], [], color="tab:red", ls="--",
                             label="expected with honest uncertainties"))
    top_legend(fig, legend, len(legend), "Bias treatments over the whole run (treatments.csv); "
               + EN_DEFINITION_TEX + f", k = {run.coverage_factor:g}")
    texts = save(plt, fig, path)
    default = run.default_treatment("roundness")
    caption = (
        "For each measurand and bias treatment present — uncorrected; corrected by the "
        f"run's default treatment (roundness: '{default}'"
        + (", bias evaluated at a shrinkage surrogate of the true profile, u_corrected "
           "including u_bias" if default == "shrinkage" else ", the seed study's") + "; "
        "diameter: '" + run.default_treatment("diameter") + "'"
        + (", so its bars equal those of (a)" if run.default_is_paper("diameter") else "")
        + "); (a) corrected as the seed study does, by the bias of the virtual experiment on "
        "the measured profile"
        + ("" if "denoised" not in treatments else "; (b) corrected by the bias of the "
           "virtual experiment run on the filtered, denoised profile")
        + "; (c) not corrected, expanded uncertainty enlarged to k·u + |b| with b of (a) — "
        "the mean and the RMS of E_n and the share of |E_n| ≤ 1 over all measurements. The "
        "red dashed lines are what honest "
        f"uncertainties give ({run.honest()}, k = {run.coverage_factor:g}). An RMS well "
        f"below {run.expected_rms:.3g} with a share near 100 % means overstated "
        f"uncertainties; an RMS above {run.expected_rms:.3g} "
        "or a mean away from 0 means understated uncertainties or a remaining bias."
        + (" Bottom row: mean and RMS of the error of the reported value against the "
           "simulation's true value (diameter converted to µm)." if has_error else ""))
    return Figure(os.path.basename(path), "Bias treatments", caption, texts)


def level_order(run, factor, levels):
    if factor == "location":
        return sorted(levels, key=lambda x: rank(x, run.locations))
    if factor == "orientation_deg":
        def key(level):
            try:
                return (0, float(level), level)
            except ValueError:
                return (1, 0.0, level)
        return sorted(levels, key=key)
    if factor == "height":
        return sorted(levels, key=lambda x: rank(x, HEIGHT_ORDER))
    if factor == "mode":
        return sorted(levels, key=lambda x: rank(x, MODE_ORDER))
    return sorted(levels)


def figure_factors(plt, np, run, path):
    """A dot plot per factor, measurand and statistic: the mean of E_n and the RMS of E_n at
    each level, one dot per treatment side by side (no line joins them: they are two
    statistics, not an interval)."""
    factors = [f for f in FACTORS[1:] if any(r.factor == f for r in run.summary)]
    measurands = [x for x in MEASURANDS if any(r.measurand == x for r in run.summary)]
    treatments = sorted({r.treatment for r in run.summary}, key=lambda t: rank(t, TREATMENTS))
    colors = TREATMENT_COLORS
    lookup = {(r.factor, r.level, r.measurand, r.treatment): r for r in run.summary}
    columns = [(measurand, stat) for measurand in measurands for stat in ("mean", "rms")]
    fig, axes = plt.subplots(len(factors), len(columns), squeeze=False,
                             figsize=(4.2 * len(columns), 2.9 * len(factors) + 1.2))
    offsets = np.linspace(-0.3, 0.3, len(treatments)) if len(treatments) > 1 else [0.0]
    expected_se = run.expected_rms       # standard deviation of one E_n when honest
    ranges = {"mean": [-1.0, 1.0], "rms": [0.0, 1.0]}
    for row, factor in enumerate(factors):
        levels = level_order(run, factor, {r.level for r in run.summary if r.factor == factor})
        x = np.arange(len(levels))
        for col, (measurand, stat) in enumerate(columns):
            ax = axes[row][col]
            counts = []
            for level in levels:
                r = lookup.get((factor, level, measurand, "uncorrected")) or next(
                    (lookup[(factor, level, measurand, t)] for t in treatments
                     if (factor, level, measurand, t) in lookup), None)
                counts.append(None if r is None else r.n)
            if stat == "mean":
                # Where an honest mean of n values falls 95 % of the time: ±2·(1/k)/√n.
                for i, n in enumerate(counts):
                    if n:
                        half = 2.0 * expected_se / math.sqrt(n)
                        ax.add_patch(plt.Rectangle((i - 0.45, -half), 0.9, 2 * half,
                                                   color="tab:green", alpha=0.12, lw=0))
                ax.axhline(EXPECTED_MEAN_EN, color="tab:red", ls="--", lw=1.0)
            else:
                ax.axhline(run.expected_rms, color="tab:red", ls="--", lw=1.0)
            for offset, treatment in zip(offsets, treatments):
                xs, ys = [], []
                for i, level in enumerate(levels):
                    r = lookup.get((factor, level, measurand, treatment))
                    value = None if r is None else getattr(r, stat)
                    if value is not None:
                        xs.append(i + offset)
                        ys.append(value)
                if xs:
                    ax.scatter(xs, ys, marker="o", s=30, zorder=3,
                               color=colors.get(treatment, "C5"), edgecolors="white",
                               linewidths=0.5)
                    ranges[stat][0] = min(ranges[stat][0], min(ys))
                    ranges[stat][1] = max(ranges[stat][1], max(ys))
            labels = [level.replace("_", "-") + ("" if n is None else f"\nn={n}")
                      for level, n in zip(levels, counts)]
            ax.set_xticks(x, labels, fontsize=7 if len(levels) > 8 else 8)
            ax.set_xlim(-0.6, len(levels) - 0.4)
            ax.grid(False, axis="x")
            for i in range(1, len(levels)):
                ax.axvline(i - 0.5, color="0.85", lw=0.6)
            ax.set_title(f"{measurand}: {'mean' if stat == 'mean' else 'RMS'} of $E_n$ by "
                         f"{factor.replace('_deg', ' (°)')}", loc="left", fontsize=9)
            ax.set_ylabel("mean $E_n$" if stat == "mean" else "RMS of $E_n$")
    for (measurand, stat), column in zip(columns, axes.T):
        low, high = ranges[stat]
        for ax in column:
            if stat == "mean":
                ax.set_ylim(min(low * 1.1, -1.1), max(high * 1.1, 1.1))
            else:
                ax.set_ylim(0.0, max(high * 1.1, 1.1))
    legend, ncol = two_row_legend(
        plt, [plt.Line2D([], [], ls="", marker="o", markersize=7, color=colors.get(t, "C5"),
                         label=run.label(t)) for t in treatments],
        [plt.Line2D([], [], color="tab:red", ls="--",
                    label=f"honest: mean 0, RMS {run.expected_rms:.3g} (1/k)"),
         plt.Rectangle((0, 0), 1, 1, color="tab:green", alpha=0.2,
                       label="honest mean of n values: 95 % within ±2·(1/k)/√n")])
    top_legend(fig, legend, ncol, "Mean and RMS of $E_n$ by factor level (summary.csv); "
               + EN_DEFINITION_TEX)
    texts = save(plt, fig, path)
    caption = (
        "Dot plots of the mean and of the RMS of E_n (" + EN_DEFINITION + ", k = "
        f"{run.coverage_factor:g}) for each level of each factor of the run — location, "
        "orientation, height, mode — per measurand, one colour per bias treatment ("
        + ", ".join(run.label(t) for t in treatments) + "; 'corrected' is the run's default "
        "treatment, the seed study's (a) is drawn beside it); n under each level is the "
        "number of measurements. With honest uncertainties the mean is near 0, within the "
        "green band ±2·(1/k)/√n where 95 % of honest means of n values fall, and the RMS "
        f"near {run.expected_rms:.3g} (red dashed lines). A level whose mean or RMS stands "
        "out points at an effect the uncertainty budget misses there, e.g. a "
        "location-dependent machine error.")
    return Figure(os.path.basename(path), "E_n by factor level", caption, texts)


def quantile(values, q):
    """The q-quantile of values by linear interpolation between order statistics (numpy's
    default), values non-empty."""
    ordered = sorted(values)
    position = q * (len(ordered) - 1)
    low = math.floor(position)
    high = min(low + 1, len(ordered) - 1)
    return ordered[low] + (position - low) * (ordered[high] - ordered[low])


def ratio_range(budgets, measurand):
    """(min, max) over the measurements of √Σu_i² / u of a measurand; None if none has it."""
    ratios = [b.ratio.get(measurand) for b in budgets]
    ratios = [r for r in ratios if r is not None]
    return (min(ratios), max(ratios)) if ratios else None


def figure_budget(plt, np, run, path):
    """Per error source, the median over the measurements of one mode of its share of the
    one-at-a-time variance sum u_i² / Σu_j², horizontal bars grouped by mode, one panel per
    measurand; whiskers the quartiles."""
    budgets = [run.budgets[m.id] for m in run.measurements if m.id in run.budgets]
    sources = list(budgets[0].sources)
    modes = sorted({b.mode for b in budgets}, key=lambda x: rank(x, MODE_ORDER))
    count = {mode: sum(b.mode == mode for b in budgets) for mode in modes}
    trials = sorted({b.trials for b in budgets})
    fig, axes = plt.subplots(1, 2, figsize=(12.0, 1.8 + 0.45 * len(sources) * len(modes)),
                             sharey=True)
    y = np.arange(len(sources))
    height = 0.8 / len(modes)
    medians = {}
    limits = {}
    for ax, measurand in zip(axes, MEASURANDS):
        column = "share_" + measurand
        for j, mode in enumerate(modes):
            shares = {src: [100.0 * b.sources[src][column] for b in budgets if b.mode == mode]
                      for src in sources}
            middle = [quantile(shares[src], 0.5) for src in sources]
            low = [quantile(shares[src], 0.25) for src in sources]
            high = [quantile(shares[src], 0.75) for src in sources]
            positions = y + (j - (len(modes) - 1) / 2) * height
            ax.barh(positions, middle, height * 0.9, color=MODE_COLORS.get(mode, f"C{4 + j}"),
                    xerr=[[mm - lo for mm, lo in zip(middle, low)],
                          [hi - mm for mm, hi in zip(middle, high)]],
                    error_kw={"ecolor": "0.25", "elinewidth": 0.9, "capsize": 2.0})
            for position, value, top in zip(positions, middle, high):
                ax.annotate(f"{value:.1f} %" if value >= 0.05 else "< 0.1 %",
                            (max(value, top), position), xytext=(4, 0),
                            textcoords="offset points", va="center", fontsize=7)
            for src, value in zip(sources, middle):
                medians[(measurand, mode, src)] = value
        ratios = ratio_range(budgets, measurand)
        limits["ratio " + measurand] = ratios
        ratio_text = ("" if ratios is None else
                      r"$\sqrt{\sum u_i^2}\,/\,u$" + f" = {ratios[0]:.3f} … {ratios[1]:.3f} "
                      "over the measurements")
        if measurand == "diameter":
            title = "diameter (LS): shares of $u^2$ (the $u_i$ add in quadrature)"
        else:
            title = "roundness (RONt): shares rank the sources only"
        ax.set_title(title + ("\n" + ratio_text if ratio_text else ""), loc="left",
                     fontsize=9)
        ax.set_xlim(0.0, 118.0)
        ax.set_xticks([0, 20, 40, 60, 80, 100])
        ax.set_xlabel(r"median share $u_i^2 / \sum u_j^2$ over the measurements (%)")
        ax.grid(False, axis="y")
    axes[0].set_yticks(y, sources)
    axes[0].invert_yaxis()              # stage order from the top
    legend = [plt.Rectangle((0, 0), 1, 1, color=MODE_COLORS.get(mode, f"C{4 + j}"),
                            label=f"{mode.replace('_', '-')} (n = {count[mode]})")
              for j, mode in enumerate(modes)]
    legend.append(plt.Line2D([], [], color="0.25", lw=0.9, marker="|", markersize=6,
                             label="whisker: 25 %–75 % of the measurements"))
    trials_text = (f"{trials[0]} trials a source" if len(trials) == 1 else
                   f"{trials[0]}–{trials[-1]} trials a source")
    top_legend(fig, legend, len(legend), "Uncertainty budget per error source (budget.csv): "
               "each source alone, " + trials_text)
    texts = save(plt, fig, path)

    def ratio_words(measurand):
        r = limits["ratio " + measurand]
        return "not defined (full u = 0)" if r is None else f"{r[0]:.3f} to {r[1]:.3f}"
    smallest = trials[0]
    tolerance = 4.0 / math.sqrt(2.0 * (smallest - 1))     # read_budget: trials >= 2
    caption = (
        "For each error source, the median over the measurements of one probing mode ("
        + ", ".join(f"{mode.replace('_', '-')}: {count[mode]}" for mode in modes)
        + ") of its share u_i² / Σ_j u_j², where u_i is the standard uncertainty the source "
        "gives alone — the others held at their estimates, on the very random numbers it has "
        f"in the full run (common random numbers), {trials_text}; the whiskers span the "
        "middle half (25 %–75 %) of the measurements' shares. Diameter: the LS diameter is "
        "linear in the errors, so the u_i add in quadrature and the shares split u² — the "
        f"quadrature sum √Σu_i² over the full run's u lies from {ratio_words('diameter')} "
        f"over the measurements (Monte Carlo allows about ±{tolerance:.3f} at "
        f"{smallest} trials). Roundness: RONt is not linear in the sources (a peak-to-valley "
        "of the summed deviations is not a sum of peak-to-valleys, and each source alone "
        "biases RONt upward), so the u_i need not add in quadrature — √Σu_i² / u lies from "
        f"{ratio_words('roundness')} — and the shares only rank the sources; they do not "
        "split u² into parts.")
    figure = Figure(os.path.basename(path), "Uncertainty budget", caption, texts)
    figure.series = {f"{measurand}: {mode}": count[mode] for measurand in MEASURANDS
                     for mode in modes}
    figure.limits = limits
    figure.values = medians
    return figure


def make_figures(run, notes):
    """Chooses what to show and reads every file it needs first (so that bad input stops the
    run before anything is written), then draws the figures; returns [Figure]."""
    directory = os.path.join(run.outdir, "figures")
    plans = [(figure_en, (os.path.join(directory, "en_per_measurement.png"),))]
    if any(m.value(x, "true_value") is not None for m in run.measurements for x in MEASURANDS):
        plans.append((figure_errors, (os.path.join(directory, "errors_per_measurement.png"),)))
    else:
        notes.append("errors_per_measurement.png not drawn: results.csv has no true values "
                     "(only `vcmm demo` knows them).")

    def profiles(chosen):
        return [(m, read_residuals(os.path.join(run.outdir, "residuals", m.id + ".csv")))
                for m in chosen]

    residuals = available_ids(run, "residuals")
    if len(run.locations) >= 2:
        c, corner, note = choose_location_pair(run, residuals)
        if c is None:
            notes.append(f"residuals_locations.png not drawn: {note}.")
        else:
            title = ("centre vs corner location" if run.centre_found else
                     f"location {c.location} vs location {corner.location} (no centre label)")
            plans.append((figure_residuals, (
                profiles([c, corner]), os.path.join(directory, "residuals_locations.png"),
                "Residuals about the reference circle: " + title, note, "locations")))
    else:
        notes.append("residuals_locations.png not drawn: the run has a single location.")
    chosen, note = choose_orientation_set(run, residuals)
    if chosen:
        plans.append((figure_residuals, (
            profiles(chosen), os.path.join(directory, "residuals_orientations.png"),
            "Residuals about the reference circle: orientations at one location", note,
            "orientations")))
    else:
        notes.append(f"residuals_orientations.png not drawn: {note}.")

    chosen = choose_histograms(run, available_ids(run, "samples"))
    if not chosen:
        notes.append("No Monte Carlo histogram drawn: no samples/<id>.csv file for any "
                     "measurement of results.csv.")
    for m in chosen:
        samples = read_samples(os.path.join(run.outdir, "samples", m.id + ".csv"))
        plans.append((figure_histogram, (m, samples,
                                         os.path.join(directory, f"histogram_{m.id}.png"))))

    if run.treatments:
        plans.append((figure_treatments, (os.path.join(directory, "treatments.png"),)))
    else:
        notes.append("treatments.png not drawn: no treatments.csv (only `vcmm demo`, which "
                     "knows the true values, writes it).")
    if any(r.factor != "all" for r in run.summary):
        plans.append((figure_factors, (os.path.join(directory, "factors.png"),)))
    else:
        notes.append("factors.png not drawn: summary.csv has no factor other than 'all'.")
    if run.budgets:
        plans.append((figure_budget, (os.path.join(directory, "budget.png"),)))
    else:
        notes.append("budget.png not drawn: the run has no uncertainty budget (no budget.csv; "
                     "`vcmm validate --budget` or `vcmm demo --budget` computes it).")

    plt, np = import_matplotlib()
    return [draw(plt, np, run, *arguments) for draw, arguments in plans]


# --------------------------------------------------------------------------------------------
# HTML
# --------------------------------------------------------------------------------------------

CSS = """
body { font-family: sans-serif; margin: 1.5em auto; max-width: 1400px; padding: 0 1em;
       color: #222; line-height: 1.4; }
h1 { font-size: 1.6em; margin-bottom: 0.2em; }
h2 { margin-top: 1.6em; border-bottom: 1px solid #ccc; }
table { border-collapse: collapse; font-size: 0.85em; margin: 0.5em 0; }
th, td { border: 1px solid #ddd; padding: 2px 6px; }
th { background: #f0f0f0; position: sticky; top: 0; }
td.num { text-align: right; font-variant-numeric: tabular-nums; font-family: monospace; }
td.out { background: #fbd5d5; color: #900; font-weight: bold; }
td.refused { font-style: italic; background: #eee; }
.scroll { max-height: 40em; overflow: auto; border: 1px solid #ccc; }
figure { margin: 1em 0 2em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { max-width: 75em; font-size: 0.9em; }
.note { color: #555; font-size: 0.9em; } code { font-size: 0.95em; }
"""


def esc(value):
    return html.escape(str(value), quote=True)


def href(path):
    return esc(urllib.parse.quote(path))


def flatten(prefix, value, out):
    if isinstance(value, dict) and value:
        for key, item in value.items():
            flatten(f"{prefix}.{key}" if prefix else str(key), item, out)
    else:
        out.append((prefix, value if isinstance(value, str) else
                    json.dumps(value, ensure_ascii=False)))


def number_text(value, column, unit, decimals=None):
    """A results.csv number as the report prints it: E_n and zeta to 0.01; values and
    uncertainties to `decimals` places (the row's GUM rounding, row_decimals) or, without
    one, mm to 1 nm and um to 0.1 nm."""
    if value is None:
        return ""
    if column in EN_COLUMNS or column.startswith("zeta"):
        return f"{value:.2f}"
    if column == "orientation_deg":
        return f"{value:g}"
    if decimals is None:
        decimals = 6 if unit == "mm" else 4
    text = f"{value:.{decimals}f}"
    return text.lstrip("-") if float(text) == 0.0 else text


# Standard uncertainties whose smallest sets the decimal place of a row of the results table.
ROUNDING_UNCERTAINTIES = ("u", "u_reference", "u_corrected", "u_corrected_paper")


def row_decimals(row):
    """Decimal places of every value of a results.csv row: two significant digits of the
    smallest standard uncertainty the row reports (GUM 7.2.6), so a value, its u and U are
    written to the same place; at least 1 nm (mm) or 0.1 nm (um) when no u is positive."""
    positive = [row.values[c] for c in ROUNDING_UNCERTAINTIES
                if row.values.get(c) is not None and row.values[c] > 0]
    if not positive:
        return None
    return gum_decimals(min(positive))


# Expanded-uncertainty columns of the per-measurement table (not in results.csv): name ->
# the standard uncertainty it is k times, and the column it follows.
def expanded_columns(k):
    return {f"U (k = {k:g})": "u", f"U_ref (k = {k:g})": "u_reference",
            f"U_corrected (k = {k:g})": "u_corrected"}


def html_table(header, rows):
    """rows: list of lists of (text, css_class or None)."""
    out = ["<table><thead><tr>"]
    out += [f"<th>{esc(h)}</th>" for h in header]
    out.append("</tr></thead><tbody>")
    for cells in rows:
        out.append("<tr>")
        for text, css in cells:
            out.append(f"<td class=\"{esc(css)}\">{esc(text)}</td>" if css else
                       f"<td>{esc(text)}</td>")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def summary_cells(run, r):
    def number(value, digits):
        return ("", "num") if value is None else (f"{value:.{digits}f}", "num")
    return [(r.factor, None), (r.level, None), (r.measurand, None),
            (run.label(r.treatment, r.measurand), None), (str(r.n), "num"),
            number(None if r.share is None else 100.0 * r.share, 1), number(r.mean, 3),
            number(r.rms, 3)]


# Cells shaded in the per-measurement table when a treatment's correction was refused.
REFUSED_DEFAULT_COLUMNS = frozenset(("correction_applied", "corrected", "u_corrected",
                                     "En_corrected", "zeta_corrected"))
REFUSED_PAPER_COLUMNS = frozenset(("paper_applied", "corrected_paper", "u_corrected_paper",
                                   "En_paper"))
# Tool tips of the per-measurement table's headers.
COLUMN_NOTES = {
    "treatment": "the default bias treatment of the corrected columns",
    "bias": "bias of the default treatment",
    "u_bias": "standard uncertainty of the default treatment's bias estimate itself; a "
              "component of u_corrected (0 for the seed study's treatment)",
    "corrected": "value corrected by the default treatment",
    "u_corrected": "standard uncertainty of the default treatment's corrected value; "
                   "includes u_bias",
    "bias_paper": "bias of the seed study's treatment (a): Monte Carlo mean − estimate",
    "corrected_paper": "value corrected by the seed study's treatment (a)",
    "u_corrected_paper": "standard uncertainty of (a)'s corrected value",
    "En_paper": "E_n of the seed study's treatment (a)",
    "En_inflated": "E_n of treatment (c): no correction, U = k u + |bias_paper|",
}


def treatment_definitions(run):
    """The treatments of this run, as a table: label, what is reported, its uncertainty."""
    default = run.default_treatment("roundness")
    has_b = any(r.treatment == "denoised" for r in run.summary) or any(
        r.values.get("En_denoised") is not None for r in run.result_rows)
    if default == "shrinkage":
        corrected = ("max(0, y − b), b evaluated at a shrinkage surrogate of the true "
                     "profile (second Monte Carlo run)",
                     "u_corrected, which includes u_bias (the bias estimate's own standard "
                     "uncertainty): u_corrected² = s(y*)² + u_bias² + s(y*)²/M")
    else:
        corrected = ("the seed study's correction (a): the corrected and *_paper columns "
                     "hold the same values", "as (a)")
    rows = [
        ("uncorrected", "the estimate y from the data", "u"),
        (run.label("corrected", "roundness"),
         "roundness: " + corrected[0] + "; diameter: the "
         + ("seed study's correction (a)" if run.default_is_paper("diameter") else
            run.default_treatment("diameter") + " treatment"), corrected[1]),
        (run.label("paper"), "y − b, b = Monte Carlo mean − y of the virtual experiment on "
         "the measured profile; refused (y kept) where it would make the roundness negative",
         "u_corrected_paper = √(u² + u²/M); refused: √(u² + b²)"),
        (run.label("denoised"), "y − b of the virtual experiment on the denoised profile"
         + ("" if has_b else " — not run (vcmm --denoised)"), "that run's u"),
        (run.label("inflated"), "y", "U = k·u + |b| with b of (a)"),
    ]
    return ("<p class=\"note\">The bias treatments (docs/validation.md, \"Bias "
            "treatments\"); 'corrected' is the run's default, shown beside the seed study's "
            "(a) in the tables and figures.</p>\n"
            + html_table(["treatment", "reported value", "uncertainty"],
                         [[(a, None), (b, None), (c, None)] for a, b, c in rows]) + "\n")


def results_section(run):
    rows_by_id = {m.id: m for m in run.measurements}
    order = []
    for m in run.measurements:
        for measurand in MEASURANDS:
            if measurand in m.rows:
                order.append(m.rows[measurand])
    numeric = set(RESULTS_REQUIRED_NUMBERS) | set(RESULTS_OPTIONAL_NUMBERS)
    present = [c for c in run.result_columns
               if c not in numeric or any(r.values.get(c) is not None for r in order)]
    dropped = [c for c in RESULTS_COLUMNS if c not in present]
    k = run.coverage_factor
    expanded = expanded_columns(k)
    columns = []
    for c in present:
        columns.append(c)
        columns += [name for name, source in expanded.items() if source == c]
    body = []
    highlighted = 0
    refused_rows = 0
    for r in order:
        refused = set()
        if not r.correction_applied:
            refused |= REFUSED_DEFAULT_COLUMNS
        if not r.paper_applied:
            refused |= REFUSED_PAPER_COLUMNS
        # An expanded uncertainty is shaded with the standard uncertainty it is k times.
        refused |= {name for name, source in expanded.items() if source in refused}
        refused_rows += bool(refused)
        decimals = row_decimals(r)
        cells = []
        for c in columns:
            classes = []
            if c in numeric or c in expanded:
                if c in expanded:
                    u = r.values.get(expanded[c])
                    value = None if u is None else k * u
                else:
                    value = r.values.get(c)
                classes.append("num")
                if c in EN_COLUMNS and value is not None and abs(value) > 1.0:
                    classes.append("out")
                    highlighted += 1
                text = number_text(value, c, r.unit, decimals)
            else:
                text = r.text.get(c, "")
            if c in refused:
                classes.append("refused")
            cells.append((text, " ".join(classes) or None))
        body.append(cells)
    notes = dict(COLUMN_NOTES)
    for name, source in expanded.items():
        notes[name] = f"expanded uncertainty = {k:g} × {source} (k = {k:g})"
    for c in EN_COLUMNS:
        notes.setdefault(c, EN_DEFINITION)
    out = ["<div class=\"scroll\"><table><thead><tr>"]
    out += [f"<th title=\"{esc(notes[c])}\">{esc(c)}</th>" if c in notes
            else f"<th>{esc(c)}</th>" for c in columns]
    out.append("</tr></thead><tbody>")
    for cells in body:
        out.append("<tr>")
        for text, css in cells:
            out.append(f"<td class=\"{esc(css)}\">{esc(text)}</td>" if css else
                       f"<td>{esc(text)}</td>")
        out.append("</tr>")
    out.append("</tbody></table></div>")
    note = (f"<p class=\"note\">{len(order)} rows ({len(rows_by_id)} measurements × "
            "measurands), ordered by location, orientation, height and mode. Diameter values "
            "in mm, roundness values in µm (column <code>unit</code>). <b>Number style (GUM "
            "7.2.6):</b> in each row every value, standard uncertainty u and expanded "
            f"uncertainty U = k·u (columns \"U (k = {k:g})\", \"U_ref (k = {k:g})\", "
            f"\"U_corrected (k = {k:g})\", added by the report) is written to the decimal "
            "place of two significant digits of the row's smallest standard uncertainty "
            "(of <code>u</code>, <code>u_reference</code>, <code>u_corrected</code>, "
            "<code>u_corrected_paper</code>). <b>Sign of E_n</b> (the study's): "
            f"{esc(EN_DEFINITION)}, k = {k:g} — positive when the CMM reads low; ζ likewise "
            "with the standard uncertainties; both dimensionless, to 0.01. "
            f"{highlighted} E_n value(s) with |E_n| &gt; 1 are highlighted. "
            "<code>treatment</code>, <code>bias</code>, <code>u_bias</code>, "
            "<code>corrected</code>, <code>u_corrected</code>, <code>correction_applied</code>"
            " and <code>En_corrected</code> are the default treatment's (roundness: "
            f"{esc(run.default_treatment('roundness'))})"
            + ("; its <code>u_corrected</code> includes <code>u_bias</code>, the standard "
               "uncertainty of the bias estimate itself (u_corrected² = s(y*)² + u_bias² + "
               "s(y*)²/M)" if run.default_treatment("roundness") == "shrinkage" else "")
            + "; the <code>*_paper</code> columns and <code>En_paper</code> are the seed "
            "study's treatment (a). "
            f"Shaded italic cells ({refused_rows} row(s)): a correction refused "
            "(<code>correction_applied</code> or <code>paper_applied</code> false: it would "
            "have made the roundness negative); that treatment then reports the estimate "
            "itself."
            + (f" Columns empty in every row and left out: {esc(', '.join(dropped))}."
               if dropped else "") + "</p>")
    return note + "".join(out)


def figure_files(figure):
    """The file names of a figure, PNG first, then the vector formats written beside it."""
    stem = os.path.splitext(figure.filename)[0]
    return [stem + "." + kind for kind in FIGURE_FORMATS]


def write_html(run, figures, notes, title):
    now = datetime.datetime.now(datetime.timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    parts = ["<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n",
             f"<title>{esc(title)}</title>\n<style>{CSS}</style>\n</head>\n<body>\n",
             f"<h1>{esc(title)}</h1>\n",
             f"<p class=\"note\">Written by {esc(PROG)} on {esc(now)} from the directory "
             f"<code>{esc(os.path.abspath(run.outdir))}</code>: "
             f"{len(run.measurements)} measurements at {len(run.locations)} location(s). "
             "This file is self-contained: the figures are embedded.</p>\n"]
    parts.append("<nav><p>Contents: <a href=\"#provenance\">provenance</a> · "
                 "<a href=\"#files\">files</a> · <a href=\"#summary\">summary</a> · "
                 "<a href=\"#treatments\">treatments</a> · <a href=\"#figures\">figures</a> · "
                 "<a href=\"#results\">per-measurement results</a></p></nav>\n")

    parts.append("<h2 id=\"provenance\">Provenance</h2>\n")
    if run.run_info is None:
        parts.append("<p class=\"note\">No run_info.json in the directory.</p>\n")
    else:
        flat = []
        flatten("", run.run_info, flat)
        parts.append("<p class=\"note\">From <a href=\"run_info.json\">run_info.json</a>.</p>")
        parts.append(html_table(["key", "value"], [[(k, None), (v, None)] for k, v in flat]))
    parts.append(f"<p class=\"note\">E_n uses k = {run.coverage_factor:g} "
                 f"({esc(run.coverage_factor_source)}); {esc(EN_DEFINITION)} "
                 "(reference − measured: positive when the CMM reads low).</p>\n")

    parts.append("<h2 id=\"files\">Files</h2>\n<ul>\n")
    for name, what in (("results.csv", "per-measurement results (table below)"),
                       ("summary.csv", "E_n statistics by factor level"),
                       ("treatments.csv", "bias treatments against the truth"),
                       ("budget.csv", "uncertainty budget per measurement and error source"),
                       ("results.json", "results for machines"),
                       ("summary.json", "summary for machines"),
                       ("run_info.json", "provenance")):
        if os.path.exists(os.path.join(run.outdir, name)):
            parts.append(f"<li><a href=\"{href(name)}\">{esc(name)}</a> — {esc(what)}</li>\n")
        else:
            parts.append(f"<li>{esc(name)} — not present</li>\n")
    for f in figures:
        parts.append(f"<li>{esc(f.title)}: " + " · ".join(
            f"<a href=\"{href('figures/' + name)}\">figures/{esc(name)}</a>"
            for name in figure_files(f)) + "</li>\n")
    parts.append("</ul>\n")

    parts.append("<h2 id=\"summary\">Summary (summary.csv)</h2>\n")
    parts.append(treatment_definitions(run))
    parts.append(f"<p class=\"note\">{esc(EN_DEFINITION)} (reference − measured). Share in "
                 f"%. Honest uncertainties give {esc(run.honest())} "
                 f"(k = {run.coverage_factor:g}).</p>\n")
    header = ["factor", "level", "measurand", "treatment", "n", "share |E_n| ≤ 1 (%)",
              "mean E_n", "RMS E_n"]
    overall = sorted((r for r in run.summary if r.factor == "all"),
                     key=lambda r: (rank(r.measurand, MEASURANDS),
                                    rank(r.treatment, TREATMENTS)))
    parts.append("<h3>Whole run</h3>\n")
    parts.append(html_table(header, [summary_cells(run, r) for r in overall]) if overall else
                 "<p class=\"note\">summary.csv has no 'all' rows.</p>")
    by_factor = sorted((r for r in run.summary if r.factor != "all"),
                       key=lambda r: (rank(r.factor, FACTORS),
                                      level_order(run, r.factor, {x.level for x in run.summary
                                                                  if x.factor == r.factor}
                                                  ).index(r.level),
                                      rank(r.measurand, MEASURANDS),
                                      rank(r.treatment, TREATMENTS)))
    if by_factor:
        parts.append("<h3>By factor level</h3>\n<div class=\"scroll\">")
        parts.append(html_table(header, [summary_cells(run, r) for r in by_factor]))
        parts.append("</div>\n")

    parts.append("<h2 id=\"treatments\">Bias treatments (treatments.csv)</h2>\n")
    if run.treatments:
        rows = []
        for r in sorted(run.treatments, key=lambda r: (rank(r.measurand, MEASURANDS),
                                                       rank(r.treatment, TREATMENTS))):
            def number(value, digits):
                return ("", "num") if value is None else (f"{value:.{digits}f}", "num")
            digits = 6 if r.unit == "mm" else 4
            rows.append([(r.measurand, None), (run.label(r.treatment, r.measurand), None),
                         (str(r.n), "num"),
                         number(r.mean, 3), number(r.rms, 3),
                         number(None if r.share is None else 100.0 * r.share, 1),
                         number(r.mean_error, digits), number(r.rms_error, digits),
                         (r.unit, None)])
        parts.append("<p class=\"note\">Error = reported value − true value of the "
                     "simulation, in the unit of the last column.</p>\n")
        parts.append(html_table(["measurand", "treatment", "n", "mean E_n", "RMS E_n",
                                 "share |E_n| ≤ 1 (%)", "mean error", "RMS error", "unit"],
                                rows))
    else:
        parts.append("<p class=\"note\">No treatments.csv: only <code>vcmm demo</code>, "
                     "which knows the true values, writes it.</p>\n")

    parts.append("<h2 id=\"figures\">Figures</h2>\n")
    for note in notes:
        parts.append(f"<p class=\"note\">{esc(note)}</p>\n")
    for f in figures:
        with open(os.path.join(run.outdir, "figures", f.filename), "rb") as png:
            data = base64.b64encode(png.read()).decode("ascii")
        parts.append(f"<figure id=\"{esc(f.filename)}\"><h3>{esc(f.title)}</h3>"
                     f"<img src=\"data:image/png;base64,{data}\" alt=\"{esc(f.title)}\">"
                     f"<figcaption>{esc(f.caption)} ("
                     + ", ".join(f"<a href=\"{href('figures/' + name)}\">{esc(name)}</a>"
                                 for name in figure_files(f))
                     + ")</figcaption></figure>\n")

    parts.append("<h2 id=\"results\">Per-measurement results (results.csv)</h2>\n")
    parts.append(results_section(run))
    parts.append("\n</body>\n</html>\n")
    text = "".join(parts)
    write_atomically(os.path.join(run.outdir, "report.html"),
                     lambda f: f.write(text.encode("utf-8")))


# --------------------------------------------------------------------------------------------

def main(argv=None):
    parser = argparse.ArgumentParser(
        prog=PROG,
        description="Draw the validation figures (OUTDIR/figures/*.png) and write a "
                    "self-contained HTML report (OUTDIR/report.html) for the output "
                    "directory of `vcmm validate` or `vcmm demo`.",
        epilog="Exit codes: 0 success, 1 internal error, 2 command-line error, 3 invalid "
               "input or unwritable output.")
    parser.add_argument("outdir", metavar="OUTDIR")
    parser.add_argument("--title", default=None, help="report title")
    args = parser.parse_args(argv)
    title = args.title if args.title is not None else (
        "vcmm validation report — " + os.path.basename(os.path.abspath(args.outdir)))
    try:
        run = load_run(args.outdir)
        notes = []
        figures = make_figures(run, notes)
        write_html(run, figures, notes, title)
    except (InputError, OutputError) as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 3
    except MissingDependency as e:
        print(f"{PROG}: error: {e}", file=sys.stderr)
        return 1
    except Exception:   # a bug: say so and keep the traceback for the report
        print(f"{PROG}: internal error (a bug; please report it with the input):",
              file=sys.stderr)
        traceback.print_exc()
        return 1
    for f in figures:
        for name in figure_files(f):
            print(os.path.join(run.outdir, "figures", name))
    print(os.path.join(run.outdir, "report.html"))
    for note in notes:
        print(f"{PROG}: note: {note}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
