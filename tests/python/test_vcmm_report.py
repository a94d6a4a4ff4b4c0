"""Tests of python/vcmm_report.py on the synthetic output directories of
python/make_report_fixture.py.

Run:  /usr/bin/python3 -m unittest discover -s tests/python -v   (ctest: python_report)

The script is run as a subprocess with the interpreter running these tests, as a user would
run it, so exit codes, standard error and the files written are what is checked.  The tests
are deterministic (fixed fixture seeds) and need matplotlib and numpy (Debian
python3-matplotlib, python3-numpy); without them they are skipped with a message saying so.
"""

import base64
import csv
import html
import html.parser
import importlib.util
import json
import os
import re
import shutil
import struct
import subprocess
import sys
import tempfile
import unittest
import zlib

HERE = os.path.dirname(os.path.abspath(__file__))
PYTHON_DIR = os.path.normpath(os.path.join(HERE, "..", "..", "python"))
SCRIPT = os.path.join(PYTHON_DIR, "vcmm_report.py")
sys.path.insert(0, PYTHON_DIR)

HAVE_PLOTTING = all(importlib.util.find_spec(name) is not None
                    for name in ("matplotlib", "numpy"))

if HAVE_PLOTTING:
    import make_report_fixture

SKIP_MESSAGE = ("matplotlib/numpy not importable by " + sys.executable
                + ": install Debian python3-matplotlib python3-numpy "
                "(scripts/install-deps.sh does) and run with /usr/bin/python3")
EN_COLUMNS = ("En", "En_corrected", "En_paper", "En_denoised", "En_inflated")
DEMO_FIGURES = ["en_per_measurement.png", "errors_per_measurement.png",
                "residuals_locations.png", "residuals_orientations.png", "treatments.png",
                "factors.png", "histogram_C-O000-middle-scan.png",
                "histogram_C-O000-middle-touch.png"]
# Every figure is written as PNG, SVG and PDF.
DEMO_FILES = [name[:-len(".png")] + ext for name in DEMO_FIGURES
              for ext in (".png", ".svg", ".pdf")]
# vcmm's command-line program, set by ctest (tests/CMakeLists.txt) for the `vcmm report` test.
VCMM_CLI = os.environ.get("VCMM_CLI")


def run_report(outdir, *extra):
    return subprocess.run([sys.executable, SCRIPT, outdir, *extra], capture_output=True,
                          text=True, timeout=120)


def png_size(path):
    """(width, height) of a PNG after checking its signature, the IHDR chunk's CRC and that
    the file ends with an IEND chunk; raises AssertionError otherwise."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise AssertionError(f"{path}: not a PNG signature")
    length, kind = struct.unpack(">I4s", data[8:16])
    if kind != b"IHDR" or length != 13:
        raise AssertionError(f"{path}: first chunk is {kind!r}, not IHDR")
    crc = struct.unpack(">I", data[16 + length:20 + length])[0]
    if crc != zlib.crc32(data[12:16 + length]):
        raise AssertionError(f"{path}: IHDR CRC mismatch")
    if data[-12:-4] != b"\x00\x00\x00\x00IEND":
        raise AssertionError(f"{path}: does not end with IEND (truncated?)")
    return struct.unpack(">II", data[16:24])


def png_dpi(path):
    """The resolution a PNG's pHYs chunk states, in dots per inch (None without one)."""
    with open(path, "rb") as f:
        data = f.read()
    position = 8
    while position + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[position:position + 8])
        if kind == b"pHYs":
            x, y, unit = struct.unpack(">IIB", data[position + 8:position + 17])
            return None if unit != 1 else min(x, y) * 0.0254
        position += 12 + length
    return None


def check_vector_files(test, stem):
    """The SVG and PDF beside a PNG exist and look whole."""
    with open(stem + ".svg", "rb") as f:
        svg = f.read()
    test.assertIn(b"<svg", svg[:1000])
    test.assertTrue(svg.rstrip().endswith(b"</svg>"), stem)
    with open(stem + ".pdf", "rb") as f:
        pdf = f.read()
    test.assertTrue(pdf.startswith(b"%PDF-"), stem)
    test.assertIn(b"%%EOF", pdf[-64:])


class Collector(html.parser.HTMLParser):
    """Collects tags, attributes, table header texts and cell classes of a page."""

    def __init__(self):
        super().__init__()
        self.tags = []
        self.th_texts = []
        self.td_classes = []
        self._in_th = False

    def handle_starttag(self, tag, attrs):
        self.tags.append((tag, dict(attrs)))
        if tag == "th":
            self._in_th = True
            self.th_texts.append("")
        if tag == "td":
            self.td_classes.append(dict(attrs).get("class", ""))

    def handle_endtag(self, tag):
        if tag == "th":
            self._in_th = False

    def handle_data(self, data):
        if self._in_th:
            self.th_texts[-1] += data


def count_abs_en_above_one(results_csv):
    count = 0
    with open(results_csv, newline="") as f:
        for row in csv.DictReader(f):
            count += sum(1 for c in EN_COLUMNS if row[c] and abs(float(row[c])) > 1.0)
    return count


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class DemoDirectory(unittest.TestCase):
    """A `vcmm demo`-like directory with the demo's plan: 7 locations at 0° and the centre in
    4 orientations, 3 heights, 2 modes (66 measurements), truth, the default (shrinkage) and
    the study's treatment, (c), no (b) (the default), treatments.csv."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_demo_")
        cls.outdir = os.path.join(cls.tmp, "demo")
        cls.ids = make_report_fixture.write_fixture(cls.outdir, seed=11, trials=400)
        cls.proc = run_report(cls.outdir, "--title", "Demo <script>alert(1)</script> & co")
        cls.figures = os.path.join(cls.outdir, "figures")
        report = os.path.join(cls.outdir, "report.html")
        cls.html = ""
        if os.path.exists(report):
            with open(report, encoding="utf-8") as f:
                cls.html = f.read()
        cls.page = Collector()
        cls.page.feed(cls.html)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_exit_code_and_output_list(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        self.assertNotIn("Traceback", self.proc.stderr)
        self.assertIn(os.path.join(self.outdir, "report.html"), self.proc.stdout)

    def test_every_expected_png_is_valid_and_sensibly_sized(self):
        expected = DEMO_FIGURES
        self.assertEqual(sorted(os.listdir(self.figures)), sorted(DEMO_FILES))
        for name in expected:
            with self.subTest(name=name):
                path = os.path.join(self.figures, name)
                width, height = png_size(path)
                self.assertGreaterEqual(png_dpi(path), 199.9)
                # ~10-28 inch wide figures at 200 dpi, cropped to their content.
                self.assertTrue(1400 <= width <= 6000, (name, width))
                self.assertTrue(700 <= height <= 6000, (name, height))
                check_vector_files(self, path[:-len(".png")])
                # A drawn figure with text and data is tens of kB; a blank one is a few kB.
                self.assertGreater(os.path.getsize(os.path.join(self.figures, name)), 20000)

    def test_without_budget_one_note_and_no_figure(self):
        notes = [line for line in self.proc.stderr.splitlines() if "budget" in line]
        self.assertEqual(notes, ["vcmm_report.py: note: budget.png not drawn: the run has no "
                                 "uncertainty budget (no budget.csv; `vcmm validate --budget` "
                                 "or `vcmm demo --budget` computes it)."])
        self.assertFalse(any(n.startswith("budget.") for n in os.listdir(self.figures)))
        self.assertIn("budget.png not drawn", self.html)
        self.assertIn("<li>budget.csv — not present</li>", self.html)

    def test_histograms_are_one_scanning_and_one_touch_at_the_centre(self):
        names = [n for n in os.listdir(self.figures)
                 if n.startswith("histogram_") and n.endswith(".png")]
        ids = sorted(n[len("histogram_"):-len(".png")] for n in names)
        self.assertEqual(ids, ["C-O000-middle-scan", "C-O000-middle-touch"])
        self.assertTrue(all(i in self.ids for i in ids))

    def test_no_temporary_files_left(self):
        for directory in (self.outdir, self.figures):
            leftovers = [n for n in os.listdir(directory) if n.endswith(".tmp")]
            self.assertEqual(leftovers, [], directory)

    def test_html_embeds_every_figure_as_a_data_uri_equal_to_the_png(self):
        images = [a["src"] for tag, a in self.page.tags if tag == "img"]
        pngs = sorted(n for n in os.listdir(self.figures) if n.endswith(".png"))
        self.assertEqual(len(images), len(pngs))
        embedded = set()
        for src in images:
            prefix = "data:image/png;base64,"
            self.assertTrue(src.startswith(prefix), src[:60])
            embedded.add(base64.b64decode(src[len(prefix):], validate=True))
        on_disk = set()
        for name in pngs:
            with open(os.path.join(self.figures, name), "rb") as f:
                on_disk.add(f.read())
        self.assertEqual(embedded, on_disk)

    def test_html_is_self_contained_with_relative_links_that_exist(self):
        self.assertNotIn("http://", self.html)
        self.assertNotIn("https://", self.html)
        self.assertNotIn("url(", self.html)
        for tag, attrs in self.page.tags:
            self.assertNotIn(tag, ("script", "link", "iframe", "object", "embed"))
            if tag == "a":
                target = attrs["href"]
                if target.startswith("#"):
                    continue
                self.assertFalse(target.startswith(("/", "file:", "//")), target)
                self.assertTrue(os.path.isfile(os.path.join(self.outdir, target)), target)
        hrefs = {a.get("href") for tag, a in self.page.tags if tag == "a"}
        for name in ("results.csv", "summary.csv", "results.json", "treatments.csv",
                     "figures/en_per_measurement.png", "figures/errors_per_measurement.png",
                     "figures/factors.png", "figures/factors.svg", "figures/factors.pdf"):
            self.assertIn(name, hrefs)

    def test_results_table_has_expanded_uncertainties_and_the_sign_of_en(self):
        headers = set(self.page.th_texts)
        for name in ("U (k = 2)", "U_ref (k = 2)", "U_corrected (k = 2)"):
            self.assertIn(name, headers)
        self.assertIn("E_n = (reference − measured) / √(U_ref² + U²), U = k·u", self.html)
        self.assertIn("positive when the CMM reads low", self.html)

    def test_results_table_writes_each_row_to_the_decimal_place_of_its_u(self):
        # Every roundness row: the values, their u and U share the decimal places of two
        # significant digits of the row's smallest u (GUM 7.2.6).
        import vcmm_report
        table = self.html[self.html.index("<h2 id=\"results\">"):]
        header = [html.unescape(h) for h in re.findall(r"<th(?: [^>]*)?>(.*?)</th>", table)]
        rows = [dict(zip(header, (html.unescape(c) for c in
                                  re.findall(r"<td(?: [^>]*)?>(.*?)</td>", row))))
                for row in re.findall(r"<tr>(.*?)</tr>", table)[1:]]
        rows = [r for r in rows if r.get("measurand") == "roundness"]
        self.assertEqual(len(rows), len(self.ids))
        for cell in rows:
            u = min(float(cell[c]) for c in ("u", "u_reference", "u_corrected",
                                              "u_corrected_paper") if float(cell[c]) > 0)
            decimals = vcmm_report.gum_decimals(u)
            for column in ("estimate", "u", "U (k = 2)", "reference", "corrected"):
                written = cell[column].split(".")
                self.assertEqual(len(written[1]) if len(written) == 2 else 0, decimals,
                                 (cell["id"], column, cell[column]))
            self.assertAlmostEqual(float(cell["U (k = 2)"]), 2 * float(cell["u"]),
                                   delta=1.01 * 10.0 ** -decimals)

    def test_html_contains_the_three_tables(self):
        headers = set(self.page.th_texts)
        self.assertIn("share |E_n| ≤ 1 (%)", headers)          # summary
        self.assertIn("mean error", headers)                     # treatments
        self.assertIn("En_corrected", headers)                   # per-measurement results
        self.assertIn("En_paper", headers)
        self.assertIn("u_bias", headers)
        self.assertIn("true_value", headers)
        ids_in_cells = sum(self.html.count(f"<td>{i}</td>") for i in self.ids)
        self.assertEqual(ids_in_cells, 2 * len(self.ids))        # diameter + roundness rows

    def test_abs_en_above_one_is_highlighted_exactly(self):
        expected = count_abs_en_above_one(os.path.join(self.outdir, "results.csv"))
        self.assertGreater(expected, 0, "the fixture should contain some |E_n| > 1")
        self.assertEqual(sum(1 for c in self.page.td_classes if "out" in c.split()), expected)

    def test_refused_corrections_are_shaded(self):
        with open(os.path.join(self.outdir, "results.csv"), newline="") as f:
            rows = list(csv.DictReader(f))
        refused = sum(row[c] == "false" for row in rows
                      for c in ("correction_applied", "paper_applied"))
        self.assertGreater(refused, 0, "the fixture should refuse some (a) corrections")
        self.assertEqual(self.html.count('<td class="refused">false</td>'), refused)

    def test_text_is_escaped(self):
        self.assertNotIn("<script>", self.html)
        self.assertIn("Demo &lt;script&gt;alert(1)&lt;/script&gt; &amp; co", self.html)

    def test_provenance_shows_run_info_keys(self):
        for key in ("seed", "trials_per_measurement", "coverage_probability",
                    "factors.locations", "bias_treatment", "kinematic_errors", "form_scale",
                    "reference_circle"):
            self.assertIn(f"<td>{key}</td>", self.html)

    def test_treatments_are_labelled_default_and_seed_study(self):
        # Summary and treatments tables: the default named after results.csv `treatment`,
        # the study's beside it; no (b) row when the run did not use --denoised.
        self.assertIn("<td>corrected (default: shrinkage)</td>", self.html)
        self.assertIn("<td>corrected (default: paper = (a))</td>", self.html)   # diameter
        self.assertIn("<td>(a) seed study</td>", self.html)
        self.assertIn("<td>(c) U + |b|</td>", self.html)
        # (b) only in the table defining the treatments, marked as not run.
        self.assertEqual(self.html.count("<td>(b) denoised</td>"), 1)
        self.assertIn("not run (vcmm --denoised)", self.html)

    def test_whole_run_table_puts_default_and_seed_study_side_by_side(self):
        start = self.html.index("<h3>Whole run</h3>")
        table = self.html[start:self.html.index("</table>", start)]
        roundness = table[table.index("<td>roundness</td>"):]
        labels = [label for label in ("uncorrected", "corrected (default: shrinkage)",
                                      "(a) seed study", "(c) U + |b|")]
        positions = [roundness.index(f"<td>{label}</td>") for label in labels]
        self.assertEqual(positions, sorted(positions))

    def test_u_corrected_is_said_to_include_u_bias(self):
        self.assertIn("<code>u_corrected</code> includes <code>u_bias</code>", self.html)
        self.assertIn("u_corrected, which includes u_bias", self.html)

    def test_captions_compare_default_and_seed_study(self):
        self.assertIn("(a) the seed study&#x27;s correction (filled brown", self.html)
        self.assertIn("Error against the truth per measurement", self.html)
        self.assertIn("A bar that crosses zero covers the truth", self.html)


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class ValidateDirectoryWithoutCentre(unittest.TestCase):
    """A `vcmm validate`-like directory: no truth, no treatment (b), no treatments.csv,
    refused corrections left empty, and no location called C/centre."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_validate_")
        cls.outdir = os.path.join(cls.tmp, "validate")
        make_report_fixture.write_fixture(
            cls.outdir, seed=5, trials=200, locations=("P1", "P2", "P3"),
            heights=("middle",), validate=True,
            missing_reference=[("P2-O090-middle-scan", "diameter")])
        with open(os.path.join(cls.outdir, "run_info.json"), "w", encoding="utf-8") as f:
            f.write('{"command": "vcmm validate <campaign> & \\"x\\"", '
                    '"evaluation": {"k": 2, "coverage_probability": 0.95}}\n')
        cls.proc = run_report(cls.outdir)
        with open(os.path.join(cls.outdir, "report.html"), encoding="utf-8") as f:
            cls.html = f.read()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_succeeds_without_treatments_and_errors_figures(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        figures = os.listdir(os.path.join(self.outdir, "figures"))
        self.assertNotIn("treatments.png", figures)
        self.assertNotIn("errors_per_measurement.png", figures)
        self.assertIn("errors_per_measurement.png not drawn", self.proc.stderr)
        for name in ("en_per_measurement.png", "residuals_locations.png",
                     "residuals_orientations.png", "factors.png"):
            self.assertIn(name, figures)
        self.assertIn("No treatments.csv", self.html)
        self.assertIn("treatments.png not drawn", self.proc.stderr)

    def test_says_that_no_centre_was_found(self):
        self.assertIn("No location is labelled C/centre/center", self.html)
        self.assertIn("location &#x27;P1&#x27; stands in for the centre", self.html)

    def test_empty_columns_are_left_out_and_named(self):
        self.assertIn("left out: corrected_denoised, En_denoised, true_value", self.html)

    def test_a_row_without_reference_has_no_scores(self):
        import vcmm_report
        run = vcmm_report.load_run(self.outdir)
        m = next(m for m in run.measurements if m.id == "P2-O090-middle-scan")
        for column in ("reference", "u_reference", "En", "En_corrected", "En_paper",
                       "En_inflated", "zeta"):
            self.assertIsNone(m.value("diameter", column), column)
        self.assertIsNotNone(m.value("roundness", "En"))

    def test_nested_run_info_is_flattened_and_escaped(self):
        self.assertIn("<td>evaluation.k</td>", self.html)
        self.assertIn("vcmm validate &lt;campaign&gt; &amp; &quot;x&quot;", self.html)
        self.assertIn("k = 2 (run_info.json evaluation.k)", self.html)


def draw(outdir, *names):
    """Draws the named figures of vcmm_report in this process into a fresh figures directory
    of outdir; returns {name: Figure} (with the texts and series drawn)."""
    import vcmm_report
    run = vcmm_report.load_run(outdir)
    plt, np = vcmm_report.import_matplotlib()
    functions = {"en_per_measurement": vcmm_report.figure_en,
                 "errors_per_measurement": vcmm_report.figure_errors,
                 "treatments": vcmm_report.figure_treatments,
                 "factors": vcmm_report.figure_factors}
    directory = os.path.join(outdir, "figures_in_process")
    vcmm_report.FIGURE_FORMATS = ("png",)       # the vector files are tested elsewhere
    return {name: functions[name](plt, np, run, os.path.join(directory, name + ".png"))
            for name in names}


def panel_titles(figure):
    """The series keys of a per-measurement Figure are "panel title: treatment label"."""
    return {key.rsplit(": ", 1)[0] for key in figure.series}


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class FigureContents(unittest.TestCase):
    """What the figures draw (texts and point counts, in-process): the default treatment and
    the seed study's side by side, for the default run (shrinkage, no (b))."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_contents_")
        cls.outdir = os.path.join(cls.tmp, "demo")
        cls.ids = make_report_fixture.write_fixture(cls.outdir, seed=12, trials=40)
        cls.figures = draw(cls.outdir, "en_per_measurement", "errors_per_measurement",
                           "treatments", "factors")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_en_figure_has_default_and_seed_study_panels_with_every_point(self):
        f = self.figures["en_per_measurement"]
        n = len(self.ids)
        default = [k for k in f.series if k.startswith("Roundness, corrected by the default "
                                                       "treatment 'shrinkage'")]
        study = [k for k in f.series if k.startswith("Roundness, (a) the seed study")]
        self.assertEqual(len(default), 1, f.series)
        self.assertEqual(len(study), 1, f.series)
        self.assertEqual(f.series[default[0]], n)
        self.assertEqual(f.series[study[0]], n)
        # Adjacent panels: the study's comes right after the default's.
        titles = list(dict.fromkeys(k.rsplit(": ", 1)[0] for k in f.series))
        self.assertEqual(titles.index(study[0].rsplit(": ", 1)[0]),
                         titles.index(default[0].rsplit(": ", 1)[0]) + 1)
        for label in ("$E_n$ uncorrected",
                      "$E_n$ corrected (default: shrinkage; diameter: paper)",
                      "$E_n$ (a) seed study", "$E_n$ (c) U + |b|"):
            self.assertIn(label, f.texts)
        self.assertFalse(any("(b)" in t for t in f.texts), "no (b) without --denoised")

    def test_en_figure_ticks_are_short_and_horizontal(self):
        f = self.figures["en_per_measurement"]
        # Heights under the measurements, orientations under the set-ups (the repeated
        # set-up C-R000 marked ′), locations under their groups; no long ids.
        for label in ("t", "m", "b", "0°", "0°′", "90°", "270°", "C", "L1", "E2"):
            self.assertIn(label, f.texts)
        self.assertNotIn("C-O000-top-scan", f.texts)
        self.assertTrue(all(rotation == 0.0 for rotation in f.limits["tick_rotations"]),
                        f.limits["tick_rotations"])

    def test_en_figure_writes_e_n_as_a_subscript_and_states_its_sign(self):
        f = self.figures["en_per_measurement"]
        self.assertIn("$E_n$", f.texts)                 # the axis labels
        self.assertFalse(any("E_n" in t and "$" not in t for t in f.texts),
                         [t for t in f.texts if "E_n" in t and "$" not in t])
        self.assertTrue(any("reference − measured" in t for t in f.texts))

    def test_errors_figure_has_three_series_for_the_roundness(self):
        f = self.figures["errors_per_measurement"]
        n = len(self.ids)
        self.assertEqual(f.series, {
            "diameter: uncorrected": n, "diameter: corrected (default: paper = (a))": n,
            "roundness: uncorrected": n, "roundness: corrected (default: shrinkage)": n,
            "roundness: (a) seed study": n})
        self.assertTrue(any(t.startswith("truth within ±U — uncorrected:") for t in f.texts))
        self.assertIn("corrected (default: shrinkage; diameter: paper) ± U (k = 2), "
                      "U = k·u_corrected (incl. u_bias)", f.texts)

    def test_treatments_figure_has_a_seed_study_bar(self):
        f = self.figures["treatments"]
        self.assertIn("(a)\nseed study", f.texts)
        self.assertIn("corrected\n(default:\nshrinkage;\ndiameter: paper)", f.texts)
        self.assertIn("(c)\nU + |b|", f.texts)
        self.assertNotIn("(b)\ndenoised", f.texts)
        self.assertIn("(a) corrected as the seed study does", f.caption)

    def test_factors_figure_has_the_seed_study(self):
        self.assertIn("(a) seed study", self.figures["factors"].texts)


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class DenoisedRunWithPaperDefault(unittest.TestCase):
    """`vcmm demo --denoised --bias-treatment paper`: (b) present, the default is the seed
    study's, so the labels say so and no separate (a) panel repeats it."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_paper_")
        cls.outdir = os.path.join(cls.tmp, "paper")
        make_report_fixture.write_fixture(cls.outdir, seed=13, trials=40, denoised=True,
                                          bias_treatment="paper", locations=("C", "L1"),
                                          orientations_deg=(0, 90), heights=("middle",))
        cls.proc = run_report(cls.outdir)
        with open(os.path.join(cls.outdir, "report.html"), encoding="utf-8") as f:
            cls.html = f.read()
        cls.figures = draw(cls.outdir, "en_per_measurement", "errors_per_measurement",
                           "treatments")

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_succeeds_with_every_figure(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stderr)
        self.assertEqual(sorted(os.listdir(os.path.join(self.outdir, "figures"))),
                         sorted(DEMO_FILES))

    def test_labels_follow_the_treatment_column(self):
        self.assertIn("<td>corrected (default: paper = (a))</td>", self.html)
        self.assertNotIn("default: shrinkage", self.html)
        self.assertIn("<td>(b) denoised</td>", self.html)
        self.assertIn("<td>(a) seed study</td>", self.html)

    def test_en_figure_has_b_and_no_duplicate_seed_study_panel(self):
        f = self.figures["en_per_measurement"]
        titles = panel_titles(f)
        self.assertTrue(any("default treatment 'paper' = (a)" in t for t in titles), titles)
        self.assertFalse(any(t.startswith("Roundness, (a)") for t in titles), titles)
        self.assertIn("$E_n$ (b) denoised", f.texts)
        self.assertIn("$E_n$ corrected (default: paper = (a))", f.texts)

    def test_errors_figure_has_two_series_per_measurand(self):
        self.assertEqual(len(self.figures["errors_per_measurement"].series), 4)

    def test_treatments_figure_still_has_the_seed_study_and_b(self):
        f = self.figures["treatments"]
        self.assertIn("(a)\nseed study", f.texts)
        self.assertIn("(b)\ndenoised", f.texts)


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class GumRounding(unittest.TestCase):
    """One number style: u to two significant digits, values to the same decimal place."""

    def test_two_significant_digits_of_u(self):
        import vcmm_report
        self.assertEqual(vcmm_report.gum_decimals(0.291), 2)
        self.assertEqual(vcmm_report.gum_decimals(0.000293), 5)
        self.assertEqual(vcmm_report.gum_decimals(0.0996), 2)      # 0.100 -> '0.10'
        self.assertEqual(vcmm_report.gum_decimals(29.0), 0)
        self.assertIsNone(vcmm_report.gum_decimals(0.0))

    def test_values_rounded_to_the_place_of_u(self):
        import vcmm_report
        f = vcmm_report.format_with_uncertainty
        # The example: bias +0.000828 um next to u = 0.291 um.
        self.assertEqual(f(0.000828, 0.291, signed=True), "+0.00")
        self.assertEqual(f(-0.001, 0.291, signed=True), "+0.00")   # no '-0.00'
        self.assertEqual(f(0.291, 0.291), "0.29")
        self.assertEqual(f(171.0001264, 0.000293), "171.00013")
        self.assertEqual(f(None, 0.1), "n/a")


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class AxesFollowTheData(unittest.TestCase):
    """The polar and unrolled residual plots and the histograms are scaled to the data, not
    to a fixed range: a profile ten times smaller gets axes ten times smaller (the polar plot
    to the filtered profile, the unrolled panels to every point)."""

    @classmethod
    def setUpClass(cls):
        import vcmm_report
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_scale_")
        cls.outdir = os.path.join(cls.tmp, "scale")
        make_report_fixture.write_fixture(cls.outdir, seed=21, trials=200,
                                          locations=("C", "L1"), orientations_deg=(0, 90),
                                          heights=("middle",))
        vcmm_report.FIGURE_FORMATS = ("png",)
        cls.report_run = vcmm_report.load_run(cls.outdir)
        cls.plt, cls.np = vcmm_report.import_matplotlib()
        available = vcmm_report.available_ids(cls.report_run, "residuals")
        first, second, cls.note = vcmm_report.choose_location_pair(cls.report_run, available)
        cls.profiles = [(m, vcmm_report.read_residuals(
            os.path.join(cls.outdir, "residuals", m.id + ".csv"))) for m in (first, second)]

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def draw_residuals(self, scale):
        import vcmm_report
        profiles = [(m, vcmm_report.Residuals(p.angle_deg, [scale * v for v in p.deviation_um],
                                              [scale * v for v in p.filtered_um]))
                    for m, p in self.profiles]
        return vcmm_report.figure_residuals(
            self.plt, self.np, self.report_run, profiles,
            os.path.join(self.outdir, "figures", f"residuals_{scale:g}.png"), "test",
            self.note, "locations")

    def test_polar_and_unrolled_axes_follow_the_data(self):
        for scale in (1.0, 0.1, 10.0):
            with self.subTest(scale=scale):
                f = self.draw_residuals(scale)
                # The polar plot follows the filtered profiles, the unrolled panels every
                # point.
                for axis, data in (("polar", "filtered"), ("unrolled", "all")):
                    low, high = f.limits[data]
                    shown_low, shown_high = f.limits[axis]
                    self.assertLessEqual(shown_low, low)
                    self.assertGreaterEqual(shown_high, high)
                    # Not a fixed range: at most about twice the data's span.
                    self.assertLess(shown_high - shown_low, 2.5 * (high - low),
                                    (axis, f.limits))

    def test_polar_names_the_reference_filter_zone_and_ront(self):
        f = self.draw_residuals(1.0)
        joined = "\n".join(f.texts)
        self.assertIn("maximum-inscribed (MI)", joined)        # run_info reference_circle
        self.assertIn("Gaussian filter 50 UPR", joined)        # run_info filter_cutoff_upr
        self.assertIn("MI zone", joined)
        self.assertIn("RONt = ", joined)
        self.assertIn("0", f.texts)                            # the base circle's ring label

    def test_histogram_axes_and_numbers(self):
        import vcmm_report
        m = next(m for m in self.report_run.measurements if m.id == "C-O000-middle-scan")
        samples = vcmm_report.read_samples(os.path.join(self.outdir, "samples",
                                                        m.id + ".csv"))
        f = vcmm_report.figure_histogram(self.plt, self.np, self.report_run, m, samples,
                                         os.path.join(self.outdir, "figures", "h.png"))
        for measurand in ("diameter", "roundness"):
            (x_low, x_high), (low, high) = f.limits[measurand]
            self.assertLessEqual(x_low, low)
            self.assertGreaterEqual(x_high, high)
        # The estimate and the Monte Carlo mean are separate legend entries; the corrected
        # intervals are drawn (and written out for the check).
        for label in ("estimate from data", "Monte Carlo mean (seed-study run)",
                      "default corrected ± U_c (incl. u_bias)", "(a) corrected ± U_c"):
            self.assertIn(label, f.texts)
        # Every number in µm of a panel title has the same decimal places.
        titles = [t for t in f.texts if t.startswith(("diameter, uncorrected",
                                                      "roundness, uncorrected"))]
        self.assertEqual(len(titles), 2)
        for title in titles:
            places = {len(x) for x in re.findall(r"[-+]?\d+\.(\d+) µm", title)}
            self.assertEqual(len(places), 1, title)
            self.assertIn("$E_n$", title)


def read_budget_rows(outdir):
    with open(os.path.join(outdir, "budget.csv"), newline="") as f:
        return list(csv.DictReader(f))


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class BudgetFigure(unittest.TestCase):
    """`vcmm validate --budget` / `vcmm demo --budget`: budget.csv gives the figure budget
    (median share per error source, per measurand and mode) with its caption, listed in the
    report.  Drawn in-process (only this figure, in all three formats: the whole script runs
    end to end in CliBudgetReport and DemoDirectory); a run without budget: DemoDirectory."""

    @classmethod
    def setUpClass(cls):
        import vcmm_report
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_budget_")
        cls.outdir = os.path.join(cls.tmp, "run")
        cls.ids = make_report_fixture.write_fixture(
            cls.outdir, seed=31, trials=20, locations=("C",), orientations_deg=(0,),
            heights=("top", "middle", "bottom"), budget=True)
        run = vcmm_report.load_run(cls.outdir)
        plt, np = vcmm_report.import_matplotlib()
        formats = vcmm_report.FIGURE_FORMATS
        vcmm_report.FIGURE_FORMATS = ("png", "svg", "pdf")  # draw() may have cut them
        try:
            cls.figure = vcmm_report.figure_budget(
                plt, np, run, os.path.join(cls.outdir, "figures", "budget.png"))
        finally:
            vcmm_report.FIGURE_FORMATS = formats
        vcmm_report.write_html(run, [cls.figure], [], "budget")
        with open(os.path.join(cls.outdir, "report.html"), encoding="utf-8") as f:
            cls.html = f.read()

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def test_figure_files_in_every_format(self):
        png = os.path.join(self.outdir, "figures", "budget.png")
        width, height = png_size(png)
        self.assertGreater(width, 1000)
        self.assertAlmostEqual(png_dpi(png), 200.0, delta=0.5)
        check_vector_files(self, os.path.join(self.outdir, "figures", "budget"))

    def test_report_lists_the_table_and_the_figure_with_its_caption(self):
        self.assertIn('<a href="budget.csv">budget.csv</a>', self.html)
        self.assertIn('<figure id="budget.png"><h3>Uncertainty budget</h3>', self.html)
        self.assertIn("the u_i add in quadrature and the shares split u²", self.html)
        self.assertIn("the shares only rank the sources", self.html)
        # The ratio range stated is the one in budget.csv.
        rows = [r for r in read_budget_rows(self.outdir) if r["source"] == "quadrature_sum"]
        for measurand in ("diameter", "roundness"):
            ratios = [float(r["ratio_" + measurand]) for r in rows]
            self.assertIn(f"{min(ratios):.3f} to {max(ratios):.3f}", self.html)

    def test_medians_per_measurand_mode_and_source(self):
        figure = self.figure
        rows = read_budget_rows(self.outdir)
        sources = list(dict.fromkeys(r["source"] for r in rows
                                     if r["source"] not in ("quadrature_sum", "full_run")))
        self.assertEqual(sources, ["roughness", "temperature", "kinematic", "probe", "noise"])
        self.assertEqual(figure.series, {"diameter: scanning": 3, "diameter: touch_trigger": 3,
                                         "roundness: scanning": 3,
                                         "roundness: touch_trigger": 3})
        for measurand in ("diameter", "roundness"):
            for mode in ("scanning", "touch_trigger"):
                for source in sources:
                    shares = sorted(100.0 * float(r["share_" + measurand]) for r in rows
                                    if r["mode"] == mode and r["source"] == source)
                    median = shares[1]                           # 3 measurements
                    self.assertAlmostEqual(figure.values[(measurand, mode, source)], median,
                                           places=9)
        # The probe dominates the roundness of the scans in the fixture (as in the demo).
        self.assertGreater(figure.values[("roundness", "scanning", "probe")], 80.0)
        self.assertIn("scanning (n = 3)", figure.texts)
        self.assertIn("touch-trigger (n = 3)", figure.texts)

    def test_bad_budget_tables_are_named(self):
        for name, edit, words in (
                ("unknown_id", lambda r: r.update(id="X-1") if r["source"] == "noise" else None,
                 "measurement 'X-1' is not in results.csv"),
                ("share", lambda r: r.update(share_roundness="1.5")
                 if r["source"] == "probe" else None,
                 "column 'share_roundness' must be a fraction in [0, 1]; '1.5'"),
                ("mode", lambda r: r.update(mode="touch_trigger")
                 if r["mode"] == "scanning" and r["source"] == "probe" else None,
                 "has mode 'touch_trigger' but 'scanning' in results.csv"),
                ("trials", lambda r: r.update(trials="1"),
                 "column 'trials' must be >= 2")):
            outdir = os.path.join(self.tmp, "bad_" + name)
            shutil.copytree(self.outdir, outdir)
            rows = read_budget_rows(outdir)
            for r in rows[:7]:
                edit(r)
            with open(os.path.join(outdir, "budget.csv"), "w", newline="") as f:
                writer = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
                writer.writeheader()
                writer.writerows(rows)
            import vcmm_report                  # the reader, in-process: nothing is drawn
            with self.assertRaises(vcmm_report.InputError) as caught:
                vcmm_report.load_run(outdir)
            self.assertIn(os.path.join(outdir, "budget.csv") + ": line ", str(caught.exception))
            self.assertIn(words, str(caught.exception), name)


@unittest.skipUnless(HAVE_PLOTTING and VCMM_CLI, "VCMM_CLI not set (ctest sets it) or "
                     + SKIP_MESSAGE)
class CliBudgetReport(unittest.TestCase):
    """End to end: a tiny `vcmm validate --budget` run (one simulated 360-point scan, two
    entries, 200 trials: about a second) drawn by `vcmm report`."""

    def test_validate_with_budget_then_report(self):
        tmp = tempfile.mkdtemp(prefix="vcmm_report_cli_budget_")
        try:
            model = os.path.join(PYTHON_DIR, "..", "examples", "cmm_model.json")
            points = os.path.join(tmp, "ring.csv")
            proc = subprocess.run(
                [VCMM_CLI, "simulate", "--model", model, "--ring", "171", "--points", "360",
                 "--location", "600,500,250", "--stylus-offset", "0,0,-100",
                 "--temperature", "20.4", "--seed", "3", "-o", points],
                capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            entries = [{"id": mid, "points": points,
                        "setup": {"location": "C", "orientation_deg": 0, "height": height,
                                  "mode": "scanning"},
                        "reference": {"roundness": {"value_um": 0.2, "u_um": 0.01}}}
                       for mid, height in (("a", "top"), ("b", "bottom"))]
            campaign = os.path.join(tmp, "campaign.json")
            with open(campaign, "w") as f:
                json.dump({"schema": "vcmm.campaign", "schema_version": 1,
                           "model": os.path.abspath(model),
                           "evaluation": {"filter_cutoff_upr": 15, "trials": 200},
                           "measurements": entries}, f)
            outdir = os.path.join(tmp, "run")
            proc = subprocess.run([VCMM_CLI, "validate", campaign, "-o", outdir, "--budget",
                                   "--budget-trials", "100", "--progress", "never"],
                                  capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            proc = subprocess.run([VCMM_CLI, "report", outdir], capture_output=True,
                                  text=True, timeout=300)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            for kind in ("png", "svg", "pdf"):
                self.assertTrue(os.path.isfile(os.path.join(outdir, "figures",
                                                            "budget." + kind)), kind)
            self.assertNotIn("budget.png not drawn", proc.stderr)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


@unittest.skipUnless(HAVE_PLOTTING and VCMM_CLI, "VCMM_CLI not set (ctest sets it) or "
                     + SKIP_MESSAGE)
class CliReport(unittest.TestCase):
    """`vcmm report DIR` finds a Python with matplotlib and the script, and passes the exit
    code through."""

    def test_report_command(self):
        tmp = tempfile.mkdtemp(prefix="vcmm_report_cli_")
        try:
            outdir = os.path.join(tmp, "run")
            make_report_fixture.write_fixture(outdir, seed=4, trials=20, locations=("C",),
                                              orientations_deg=(0,), heights=("middle",))
            # A PATH whose first python3 has no matplotlib: /usr/bin/python3 is tried first.
            fake = os.path.join(tmp, "bin")
            os.makedirs(fake)
            with open(os.path.join(fake, "python3"), "w") as f:
                f.write("#!/bin/sh\nexit 1\n")
            os.chmod(os.path.join(fake, "python3"), 0o755)
            env = dict(os.environ, PATH=fake + os.pathsep + os.environ.get("PATH", ""))
            proc = subprocess.run([VCMM_CLI, "report", outdir, "--title", "CLI"],
                                  capture_output=True, text=True, timeout=300, env=env)
            self.assertEqual(proc.returncode, 0, proc.stderr)
            self.assertIn(os.path.join(outdir, "report.html"), proc.stdout)
            for kind in ("png", "svg", "pdf"):
                self.assertTrue(os.path.isfile(os.path.join(
                    outdir, "figures", "en_per_measurement." + kind)), kind)
            proc = subprocess.run([VCMM_CLI, "report", os.path.join(tmp, "missing")],
                                  capture_output=True, text=True, timeout=120)
            self.assertEqual(proc.returncode, 3, proc.stderr)
            self.assertIn("not a directory", proc.stderr)
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class BadInput(unittest.TestCase):
    """Every malformed or missing input: exit code 3, one message naming the file (and the
    line), no traceback, no report written."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_bad_")
        cls.base = os.path.join(cls.tmp, "base")
        # Lines of results.csv: 2, 3 C-O000-middle-scan (diameter, roundness), 4, 5
        # C-O090-middle-scan, 6, 7 L1-O000-middle-scan, ...
        make_report_fixture.write_fixture(cls.base, seed=3, trials=20, locations=("C", "L1"),
                                          orientations_deg=(0, 90), heights=("middle",))
        cls.count = 0

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def copy(self):
        type(self).count += 1
        outdir = os.path.join(self.tmp, f"case{self.count}")
        shutil.copytree(self.base, outdir)
        return outdir

    def edit_line(self, path, line_number, edit):
        with open(path, encoding="utf-8") as f:
            lines = f.read().split("\n")
        lines[line_number - 1] = edit(lines[line_number - 1])
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(lines))

    def set_field(self, path, line_number, column, value):
        with open(path, encoding="utf-8") as f:
            header = f.readline().strip().split(",")
        index = header.index(column)

        def edit(line):
            fields = line.split(",")
            fields[index] = value
            return ",".join(fields)
        self.edit_line(path, line_number, edit)

    def assert_rejected(self, outdir, *fragments):
        proc = run_report(outdir)
        self.assertEqual(proc.returncode, 3, proc.stderr)
        self.assertNotIn("Traceback", proc.stderr)
        self.assertTrue(proc.stderr.startswith("vcmm_report.py: error: "), proc.stderr)
        self.assertEqual(proc.stderr.count("\n"), 1, proc.stderr)   # one line
        for fragment in fragments:
            self.assertIn(fragment, proc.stderr)
        if os.path.isdir(outdir):
            self.assertFalse(os.path.exists(os.path.join(outdir, "report.html")))
            self.assertFalse(os.path.exists(os.path.join(outdir, "figures")))
        return proc.stderr

    def test_missing_directory(self):
        self.assert_rejected(os.path.join(self.tmp, "no_such_dir"), "no_such_dir",
                             "not a directory")

    def test_missing_results_csv(self):
        outdir = self.copy()
        os.remove(os.path.join(outdir, "results.csv"))
        self.assert_rejected(outdir, "results.csv", "file not found")

    def test_missing_summary_csv(self):
        outdir = self.copy()
        os.remove(os.path.join(outdir, "summary.csv"))
        self.assert_rejected(outdir, "summary.csv", "file not found")

    def test_results_header_lacks_a_column(self):
        outdir = self.copy()
        path = os.path.join(outdir, "results.csv")
        self.edit_line(path, 1, lambda line: line.replace(",En_corrected,", ",En_corr,"))
        self.assert_rejected(outdir, "results.csv: line 1", "En_corrected")

    def test_results_header_lacks_a_new_column(self):
        # Each column of the bias-treatment format, renamed or missing: named in the error.
        for column in ("treatment", "u_bias", "bias_paper", "corrected_paper",
                       "u_corrected_paper", "paper_applied", "En_paper"):
            with self.subTest(column=column):
                outdir = self.copy()
                path = os.path.join(outdir, "results.csv")
                self.edit_line(path, 1, lambda line: ",".join(
                    column + "_old" if field == column else field
                    for field in line.split(",")))
                self.assert_rejected(outdir, "results.csv: line 1", "lacks column(s) "
                                     + column + ";")

    def test_results_old_format_is_rejected_naming_the_new_columns(self):
        outdir = self.copy()
        path = os.path.join(outdir, "results.csv")
        with open(path, encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
        old = ("id,location,orientation_deg,height,mode,measurand,unit,reference,u_reference,"
               "estimate,u,mc_mean,bias,corrected,u_corrected,correction_applied,interval_low,"
               "interval_high,En,En_corrected,zeta,zeta_corrected,corrected_denoised,"
               "En_denoised,En_inflated,true_value").split(",")
        with open(path, "w", encoding="utf-8") as f:
            f.write(",".join(old) + "\n")
            for row in rows:
                f.write(",".join(row[c] for c in old) + "\n")
        self.assert_rejected(outdir, "results.csv: line 1", "treatment, u_bias, bias_paper, "
                             "corrected_paper, u_corrected_paper, paper_applied, En_paper")

    def test_results_paper_applied_not_a_flag(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 3, "paper_applied", "yes")
        self.assert_rejected(outdir, "results.csv: line 3", "'paper_applied'", "true, false",
                             "'yes'")

    def test_results_unknown_treatment(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 3, "treatment", "magic")
        self.assert_rejected(outdir, "results.csv: line 3", "'treatment'",
                             "shrinkage, paper", "'magic'")

    def test_results_two_default_treatments_for_one_measurand(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 5, "treatment", "paper")
        self.assert_rejected(outdir, "results.csv: line 5", "'paper' but 'shrinkage'",
                             "line 3")

    def test_results_u_bias_empty(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 3, "u_bias", "")
        self.assert_rejected(outdir, "results.csv: line 3", "'u_bias' is empty")

    def test_results_u_bias_negative(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 3, "u_bias", "-0.1")
        self.assert_rejected(outdir, "results.csv: line 3", "'u_bias' must be >= 0", "'-0.1'")

    def test_results_en_paper_missing_although_referenced(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 4, "En_paper", "")
        self.assert_rejected(outdir, "results.csv: line 4", "'En_paper' is empty although "
                             "the row has a reference")

    def test_results_reference_without_its_uncertainty(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 6, "u_reference", "")
        self.assert_rejected(outdir, "results.csv: line 6", "'reference' and 'u_reference'")

    def test_run_info_bias_treatment_contradicts_results(self):
        outdir = self.copy()
        path = os.path.join(outdir, "run_info.json")
        with open(path, encoding="utf-8") as f:
            text = f.read()
        with open(path, "w", encoding="utf-8") as f:
            f.write(text.replace('"bias_treatment": "shrinkage"', '"bias_treatment": "paper"'))
        self.assert_rejected(outdir, "run_info.json", "'bias_treatment' is 'paper'",
                             "results.csv: line 3", "'shrinkage'")

    def test_results_value_not_a_number(self):
        outdir = self.copy()
        path = os.path.join(outdir, "results.csv")
        self.set_field(path, 5, "estimate", "12x5")
        self.assert_rejected(outdir, "results.csv: line 5", "'estimate'", "'12x5'")

    def test_results_nan_rejected(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 3, "En", "nan")
        self.assert_rejected(outdir, "results.csv: line 3", "'En'", "not finite")

    def test_results_required_number_empty(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 4, "u", "")
        self.assert_rejected(outdir, "results.csv: line 4", "'u' is empty")

    def test_results_wrong_field_count(self):
        outdir = self.copy()
        self.edit_line(os.path.join(outdir, "results.csv"), 6, lambda line: line + ",1")
        self.assert_rejected(outdir, "results.csv: line 6", "34 fields", "header has 33")

    def test_results_unknown_measurand(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 2, "measurand", "ront")
        self.assert_rejected(outdir, "results.csv: line 2", "measurand", "'ront'")

    def test_results_wrong_unit(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "results.csv"), 2, "unit", "um")  # a diameter
        self.assert_rejected(outdir, "results.csv: line 2", "unit", "'um'")

    def test_results_duplicate_measurand_row(self):
        outdir = self.copy()
        path = os.path.join(outdir, "results.csv")
        with open(path, encoding="utf-8") as f:
            lines = f.read().splitlines()
        lines.append(lines[1])
        with open(path, "w", encoding="utf-8") as f:
            f.write("\n".join(lines) + "\n")
        self.assert_rejected(outdir, f"results.csv: line {len(lines)}", "second 'diameter'")

    def test_summary_share_in_percent_rejected(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "summary.csv"), 2, "share_abs_En_le_1", "95.4")
        self.assert_rejected(outdir, "summary.csv: line 2", "fraction in [0, 1]", "'95.4'")

    def test_summary_unknown_treatment(self):
        # 'paper' is a treatment of summary.csv now; a misspelt one is rejected.
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "summary.csv"), 4, "treatment", "papers")
        self.assert_rejected(outdir, "summary.csv: line 4", "uncorrected, corrected, paper, "
                             "denoised, inflated", "'papers'")

    def test_treatments_unknown_treatment(self):
        outdir = self.copy()
        self.set_field(os.path.join(outdir, "treatments.csv"), 3, "treatment", "magic")
        self.assert_rejected(outdir, "treatments.csv: line 3", "'magic'")

    def test_run_info_invalid_json(self):
        outdir = self.copy()
        with open(os.path.join(outdir, "run_info.json"), "w", encoding="utf-8") as f:
            f.write('{\n  "seed": 1,\n  "trials": ,\n}\n')
        self.assert_rejected(outdir, "run_info.json: line 3", "invalid JSON")

    def test_residuals_not_a_number(self):
        outdir = self.copy()
        path = os.path.join(outdir, "residuals", "C-O000-middle-scan.csv")
        self.set_field(path, 7, "deviation_um", "abc")
        self.assert_rejected(outdir, os.path.join("residuals", "C-O000-middle-scan.csv"),
                             "line 7", "'abc'")

    def test_residuals_angles_out_of_order(self):
        outdir = self.copy()
        path = os.path.join(outdir, "residuals", "C-O000-middle-scan.csv")
        self.set_field(path, 10, "angle_deg", "1.0")
        self.assert_rejected(outdir, "C-O000-middle-scan.csv: line 10", "increasing order")

    def test_samples_infinite(self):
        outdir = self.copy()
        path = os.path.join(outdir, "samples", "C-O000-middle-touch.csv")
        self.set_field(path, 4, "roundness_um", "inf")
        self.assert_rejected(outdir, os.path.join("samples", "C-O000-middle-touch.csv"),
                             "line 4", "not finite")

    def test_command_line_error_exits_2(self):
        proc = subprocess.run([sys.executable, SCRIPT], capture_output=True, text=True,
                              timeout=60)
        self.assertEqual(proc.returncode, 2)
        self.assertIn("OUTDIR", proc.stderr)


@unittest.skipUnless(HAVE_PLOTTING, SKIP_MESSAGE)
class SelectionRules(unittest.TestCase):
    """Which measurements the residual and histogram figures show (module functions called
    directly: no drawing)."""

    @classmethod
    def setUpClass(cls):
        import vcmm_report
        cls.report = vcmm_report
        cls.tmp = tempfile.mkdtemp(prefix="vcmm_report_select_")
        cls.outdir = os.path.join(cls.tmp, "run")
        make_report_fixture.write_fixture(cls.outdir, seed=8, trials=20,
                                          locations=("L1", "Centre", "L2"),
                                          heights=("top", "middle"))
        # The demo's plan: C at 0° twice (C-O000 of the location series, C-R000 of the
        # orientation series).
        cls.demo = os.path.join(cls.tmp, "demo")
        make_report_fixture.write_fixture(cls.demo, seed=9, trials=20)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def load(self):
        return self.report.load_run(self.outdir)

    def test_centre_label_is_found_and_ordered_first(self):
        run = self.load()
        self.assertTrue(run.centre_found)
        self.assertEqual(run.locations, ["Centre", "L1", "L2"])
        self.assertEqual(run.measurements[0].id, "Centre-O000-top-scan")

    def test_location_pair_prefers_centre_scanning_middle_smallest_angle(self):
        run = self.load()
        ids = {m.id for m in run.measurements}
        first, second, note = self.report.choose_location_pair(run, ids)
        self.assertEqual((first.id, second.id), ("Centre-O000-middle-scan", "L1-O000-middle-scan"))
        self.assertNotIn("stands in", note)

    def test_location_pair_falls_back_when_the_centre_has_no_profiles(self):
        run = self.load()
        ids = {m.id for m in run.measurements if m.location != "Centre"}
        first, second, note = self.report.choose_location_pair(run, ids)
        self.assertEqual((first.id, second.id), ("L1-O000-middle-scan", "L2-O000-middle-scan"))
        self.assertIn("The centre 'Centre' has no residual profile", note)

    def test_location_pair_needs_matching_profiles(self):
        run = self.load()
        ids = {"Centre-O000-middle-scan", "L1-O090-middle-scan"}
        first, second, note = self.report.choose_location_pair(run, ids)
        self.assertIsNone(first)
        self.assertIn("no two locations", note)

    def test_orientation_set_at_the_centre(self):
        run = self.load()
        chosen, note = self.report.choose_orientation_set(run, {m.id for m in run.measurements})
        self.assertEqual([m.id for m in chosen],
                         [f"Centre-O{o:03d}-middle-scan" for o in (0, 90, 180, 270)])
        self.assertIn("at the centre", note)

    def test_histograms_one_per_mode_at_the_centre(self):
        run = self.load()
        chosen = self.report.choose_histograms(run, {m.id for m in run.measurements})
        self.assertEqual([m.id for m in chosen],
                         ["Centre-O000-middle-scan", "Centre-O000-middle-touch"])

    def test_repeated_setup_follows_the_first_as_its_own_block(self):
        run = self.report.load_run(self.demo)
        centre = [m.id for m in run.measurements if m.location == "C"]
        prefixes = list(dict.fromkeys(i[:6] for i in centre))
        self.assertEqual(prefixes, ["C-O000", "C-R000", "C-R090", "C-R180", "C-R270"])
        repeats = {m.id[:6]: m.repeat for m in run.measurements if m.location == "C"}
        self.assertEqual(repeats["C-O000"], 0)
        self.assertEqual(repeats["C-R000"], 1)
        self.assertEqual(len(run.measurements), 66)

    def test_orientation_set_takes_the_orientation_series_at_a_repeated_orientation(self):
        run = self.report.load_run(self.demo)
        chosen, note = self.report.choose_orientation_set(run,
                                                          {m.id for m in run.measurements})
        self.assertEqual([m.id for m in chosen],
                         [f"C-R{o:03d}-middle-scan" for o in (0, 90, 180, 270)])
        self.assertIn("at the centre", note)

    def test_location_pair_and_histograms_in_the_demo_plan(self):
        run = self.report.load_run(self.demo)
        ids = {m.id for m in run.measurements}
        first, second, _ = self.report.choose_location_pair(run, ids)
        self.assertEqual((first.id, second.id), ("C-O000-middle-scan", "L1-O000-middle-scan"))
        self.assertEqual([m.id for m in self.report.choose_histograms(run, ids)],
                         ["C-O000-middle-scan", "C-O000-middle-touch"])


if __name__ == "__main__":
    unittest.main()
