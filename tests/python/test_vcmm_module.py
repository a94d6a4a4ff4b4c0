"""pytest suite of the Python module `vcmm` (python/, docs/python.md).

Run by ctest (test `python_module`, tests/CMakeLists.txt) with PYTHONPATH at the build tree's
package and VCMM_EXE at the command-line tool, or by hand:
    PYTHONPATH=build/python VCMM_EXE=build/cli/vcmm /usr/bin/python3 -m pytest tests/python
Cases: analytic (a three-lobed ring), equality with `vcmm roundness --json` on the bundled
scan, exceptions and their messages, permutation invariance, the filter and harmonics, the
claim check, and the Monte Carlo: seed reproducibility, progress, the GIL released.
"""

import json
import sys
import math
import os
import pathlib
import signal
import subprocess
import threading

import numpy as np
import pytest

import vcmm

SOURCE_DIR = pathlib.Path(os.environ.get("VCMM_SOURCE_DIR",
                                         pathlib.Path(__file__).resolve().parents[2]))
SCAN = SOURCE_DIR / "examples" / "profiles" / "ring_171mm_scan.csv"

R, A = 10.0, 1e-3  # three-lobed ring: radius 10 mm, lobe amplitude 1 µm


def lobed_ring(n=360, radius=R, amplitude=A, order=3, start=0.0):
    t = start + 2 * np.pi * np.arange(n) / n
    r = radius + amplitude * np.cos(order * t)
    return np.column_stack([r * np.cos(t), r * np.sin(t)])


def read_points(path):
    rows = []
    for line in pathlib.Path(path).read_text().splitlines():
        if not line.strip() or line.startswith("#"):
            continue
        try:
            rows.append([float(v) for v in line.split(",")])
        except ValueError:
            continue  # the header
    return np.array(rows)


# ---- analytic cases ----------------------------------------------------------------------------

def test_three_lobed_ring_analytic():
    r = vcmm.roundness(lobed_ring())
    # MZ: 3 outer peaks and 3 inner valleys about the origin, RONt = 2a.
    assert r.mz.ront == pytest.approx(2 * A, abs=1e-12)
    assert r.mz.inner_radius == pytest.approx(R - A, abs=1e-12)
    assert r.mz.outer_radius == pytest.approx(R + A, abs=1e-12)
    assert r.mi.radius == pytest.approx(R - A, abs=1e-12)
    assert r.mc.radius == pytest.approx(R + A, abs=1e-12)
    assert r.ls.radius == pytest.approx(R, abs=1e-12)
    for c in (r.ls, r.mz, r.mi, r.mc):
        assert c.defined and c.reason is None and c.caution is None
        assert math.hypot(*c.center) < 1e-12
    for c in (r.mz, r.mi, r.mc):
        assert c.certified and c.optimality == "global"
        assert c.certificate.argument
        assert vcmm.verify(r.profile, c)
    assert not r.ls.certified and r.ls.optimality == "numerical"
    assert len(r.mz.outer_contacts) == 2 and len(r.mz.inner_contacts) == 2
    # Peaks at multiples of 120°, valleys at 60° + multiples of 120° (points 0, 60, 120, ...).
    assert all(i % 120 == 0 for i in r.mz.outer_contacts)
    assert all(i % 120 == 60 for i in r.mz.inner_contacts)
    assert r.mz.contacts == r.mz.outer_contacts + r.mz.inner_contacts
    assert r.n_points == 360 and r.filter_upr is None and r.filter_path is None
    assert r.coverage.closed


def test_certificates_checked_on_request():
    r = vcmm.roundness(lobed_ring(), verify_certificates=False)
    assert all(c.certified is None for c in r.circles.values())
    assert r.mz.ront == pytest.approx(2 * A, abs=1e-12)


def test_individual_fitters_match_roundness():
    pts = lobed_ring()
    r = vcmm.roundness(pts)
    assert vcmm.minimum_zone_circle(pts).center == r.mz.center
    assert vcmm.maximum_inscribed_circle(pts).radius == r.mi.radius
    assert vcmm.minimum_circumscribed_circle(pts).radius == r.mc.radius
    assert vcmm.least_squares_circle(pts).radius == r.ls.radius
    assert vcmm.minimum_zone_circle(pts, method="overlay").ront == pytest.approx(2 * A, abs=1e-12)


def test_lists_and_three_columns_accepted():
    pts = lobed_ring(n=36)
    as_list = [list(p) for p in pts]
    with_z = np.column_stack([pts, np.full(len(pts), 7.0)])
    ref = vcmm.minimum_zone_circle(pts)
    assert vcmm.minimum_zone_circle(as_list).ront == ref.ront
    assert vcmm.minimum_zone_circle(with_z).ront == ref.ront
    assert vcmm.minimum_zone_circle(np.asfortranarray(pts)).ront == ref.ront


# ---- the same numbers as the command line --------------------------------------------------------

def cli_json(*args):
    exe = os.environ.get("VCMM_EXE")
    if not exe:
        pytest.skip("VCMM_EXE (the vcmm command) not given")
    out = subprocess.run([exe, "roundness", str(SCAN), "--json", *args], check=True,
                         capture_output=True, text=True).stdout
    return json.loads(out)


@pytest.mark.parametrize("filter_upr", [None, 50])
def test_equals_cli_json_on_bundled_scan(filter_upr):
    expected = cli_json("--filter-upr", "none" if filter_upr is None else str(filter_upr))
    r = vcmm.roundness(read_points(SCAN), filter_upr=filter_upr)
    assert r.n_points == expected["n_points"]
    assert r.filter_upr == expected["filter"]
    assert r.filter_path == expected.get("filter_path")
    assert r.coverage.closed == expected["coverage"]["closed"]
    for name in vcmm.CIRCLES:
        e, c = expected[name], r.circles[name]
        assert c.defined == e["defined"]
        assert list(c.center) == e["center"]  # bit for bit: the same library call
        for key in ("RONt", "RONp", "RONv", "RONq"):
            assert getattr(c, key.lower()) == e[key], (name, key)
        if name == "MZ":
            assert (c.inner_radius, c.outer_radius) == (e["inner_radius"], e["outer_radius"])
            assert c.outer_contacts == e["contacts"]["outer"]
            assert c.inner_contacts == e["contacts"]["inner"]
        else:
            assert c.radius == e["radius"]
            assert c.contacts == e["contacts"]
        assert c.certified == e["certified"]
        assert c.optimality == e["optimality"]
        if name != "LS":
            assert c.certificate.argument == e["certificate"]


# ---- errors: Python exceptions with the library's messages ----------------------------------------

def test_invalid_input_messages():
    with pytest.raises(vcmm.InvalidInput, match="needs at least 3 points; got 2"):
        vcmm.least_squares_circle([[0, 0], [1, 1]])
    bad = lobed_ring(n=20)
    bad[17, 0] = np.nan
    with pytest.raises(vcmm.InvalidInput, match=r"point 17 .*non-finite"):
        vcmm.roundness(bad)
    with pytest.raises(vcmm.InvalidInput, match=r"got shape \(5,\)"):
        vcmm.minimum_zone_circle(np.zeros(5))
    with pytest.raises(vcmm.InvalidInput, match=r"\(n, 2\) or \(n, 3\).*shape \(4, 4\)"):
        vcmm.roundness(np.zeros((4, 4)))
    with pytest.raises(vcmm.InvalidInput, match="collinear"):
        vcmm.minimum_zone_circle([[0, 0], [1, 1], [2, 2], [3, 3]])
    with pytest.raises(vcmm.InvalidInput, match="must be among LS, MZ, MI, MC; got 'XY'"):
        vcmm.roundness(lobed_ring(), circles=("MZ", "XY"))
    assert issubclass(vcmm.InvalidInput, ValueError)
    assert issubclass(vcmm.UndefinedResult, ValueError)


def test_undefined_circle_of_a_partial_arc():
    arc = lobed_ring(n=360)[:60]  # 59°: no maximum-inscribed circle
    with pytest.raises(vcmm.UndefinedResult):
        vcmm.maximum_inscribed_circle(arc)
    r = vcmm.roundness(arc)
    assert not r.mi.defined and r.mi.reason
    with pytest.raises(vcmm.UndefinedResult, match="MI undefined: "):
        r.mi.ront
    assert r.mz.defined and not r.coverage.closed
    assert r.mc.caution  # MC of an arc < 180° is no roundness reference
    with pytest.raises(vcmm.UndefinedResult):
        vcmm.verify(arc, r.mi)


def test_invalid_model_names_the_entry():
    model = json.loads((SOURCE_DIR / "examples" / "cmm_model.json").read_text())
    model["noise"]["scanning_sigma_um"] = -1
    with pytest.raises(vcmm.InvalidParameter, match="scanning_sigma_um") as info:
        vcmm.load_model(model)
    assert info.value.key_path == "noise.scanning_sigma_um"
    assert isinstance(info.value, vcmm.InvalidInput)


# ---- properties ------------------------------------------------------------------------------------

def test_permutation_invariance():
    rng = np.random.default_rng(7)  # printed on failure by pytest's locals
    pts = read_points(SCAN)[:, :2]
    perm = rng.permutation(len(pts))
    a = vcmm.roundness(pts)
    b = vcmm.roundness(pts[perm])
    for name in ("MZ", "MI", "MC"):
        ca, cb = a.circles[name], b.circles[name]
        assert cb.ront == pytest.approx(ca.ront, rel=1e-12, abs=1e-15)
        assert cb.radius == pytest.approx(ca.radius, rel=1e-15)
        assert np.allclose(cb.center, ca.center, rtol=0, atol=1e-12)
        assert sorted(perm[cb.contacts]) == sorted(ca.contacts)
        assert cb.certified


def test_verify_rejects_a_circle_on_other_points():
    pts = lobed_ring()
    mc = vcmm.minimum_circumscribed_circle(pts)
    bigger = pts * 1.001
    v = vcmm.verify(bigger, mc)
    assert not v and v.reason
    with pytest.raises(vcmm.InvalidInput, match="no certificate"):
        vcmm.verify(pts, vcmm.least_squares_circle(pts))


# ---- filter, harmonics, claims ---------------------------------------------------------------------

def test_gaussian_filter_transmission():
    # 3 and 100 UPR, 1 µm each: at a 50 UPR cut-off H(k) = 2^-(k/50)^2.
    t = 2 * np.pi * np.arange(3600) / 3600
    r = R + A * np.cos(3 * t) + A * np.cos(100 * t)
    pts = np.column_stack([r * np.cos(t), r * np.sin(t)])
    f = vcmm.gaussian_filter(pts, 50)
    assert f.path == "fft" and f.points.shape == (3600, 2)
    h = vcmm.harmonics(f.points, 120)
    amplitude = np.hypot(h.cos, h.sin)
    assert amplitude[3] == pytest.approx(A * 2 ** -(3 / 50) ** 2, rel=1e-6)
    assert amplitude[100] == pytest.approx(A * 2 ** -(100 / 50) ** 2, rel=1e-6)
    nonuniform = vcmm.gaussian_filter(pts, 50, path="nonuniform")
    assert nonuniform.path == "nonuniform"
    filtered = vcmm.roundness(pts, filter_upr=50)
    assert np.array_equal(filtered.profile, f.points)
    dev = vcmm.gaussian_filter_deviations(A * np.cos(100 * t), 50)
    assert np.max(np.abs(dev)) == pytest.approx(A / 16, rel=1e-9)
    with pytest.raises(vcmm.InvalidInput, match="profile must be 'closed' or 'open'"):
        vcmm.gaussian_filter(pts, 50, profile="round")


def test_harmonics_of_the_lobed_ring():
    h = vcmm.harmonics(lobed_ring(), 10)
    assert h.path == "fft" and h.max_order == 10
    assert np.hypot(h.cos[3], h.sin[3]) == pytest.approx(A, rel=1e-9)
    assert np.max(np.delete(np.hypot(h.cos, h.sin), 3)) < 1e-12
    back = h.synthesized([1.0] * 11)
    assert np.allclose(back, lobed_ring(), atol=1e-12)


def test_claim_check():
    pts = lobed_ring()
    exact = vcmm.check_claim(pts, "mz", (0.0, 0.0))
    assert exact.feasible and exact.optimal and exact.exact_certified
    assert exact.excess_ront == pytest.approx(0, abs=1e-12)
    off = vcmm.check_claim(pts, "MZ", (2e-4, 0.0))
    assert off.feasible and not off.optimal and off.excess_ront > 1e-4
    mi = vcmm.check_claim(pts, "MI", (0.0, 0.0), radii=R)  # too large: the valleys inside
    assert not mi.feasible and 170 < mi.violations < 190 and len(mi.violating) == 10
    assert vcmm.check_claim(pts, "MI", (0.0, 0.0)).optimal  # the tightest radius for the centre


# ---- virtual CMM and Monte Carlo ------------------------------------------------------------------

MODEL = vcmm.load_model()  # the bundled example model


def measured():
    return vcmm.simulate(MODEL, 171, (400, 300, 150), points=360, seed=3)


def test_simulate_is_reproducible():
    a, b = measured(), measured()
    assert a.points.shape == (360, 3) and a.normals.shape == (360, 3)
    assert np.array_equal(a.points, b.points)
    assert not np.array_equal(a.points, vcmm.simulate(MODEL, 171, (400, 300, 150), points=360,
                                                      seed=4).points)
    radius = np.hypot(a.points[:, 0], a.points[:, 1])
    assert np.mean(radius) == pytest.approx(85.5, abs=1e-3)
    assert a.location == (400.0, 300.0, 150.0) and a.mode == "scanning"


FAST = dict(trials=400, pilot_trials=100, surrogate_trials=200)


def test_uncertainty_seed_reproducible_whatever_the_threads():
    m = measured()
    a = vcmm.uncertainty(MODEL, m, seed=11, threads=1, **FAST)
    b = vcmm.uncertainty(MODEL, m, seed=11, threads=2, **FAST)
    c = vcmm.uncertainty(MODEL, m, seed=12, threads=2, **FAST)
    assert a.samples.shape == (400, 2)
    assert np.array_equal(a.samples, b.samples)
    assert a.roundness.corrected == b.roundness.corrected
    assert not np.array_equal(a.samples, c.samples)
    assert a.monte_carlo.status == "completed"
    assert a.monte_carlo.ranks == 1  # one process (MPI only through vcmm-mpi, docs/mpi.md)
    assert a.diameter.estimate == a.estimate_diameter
    assert a.samples[:, 0].mean() == pytest.approx(a.diameter.monte_carlo_mean, rel=1e-12)
    report = json.loads(a.json())
    assert report["schema"] == "vcmm.uncertainty_result"
    assert report["monte_carlo"]["ranks"] == 1
    assert "diameter" in a.table()


def test_uncertainty_from_plain_points_names_missing_metadata():
    pts = measured().machine_points
    with pytest.raises(vcmm.InvalidInput, match="--mode|mode") as info:
        vcmm.uncertainty(MODEL, pts, **FAST)
    assert "temperature" in str(info.value) and "stylus" in str(info.value)
    r = vcmm.uncertainty(MODEL, pts, mode="scanning", temperature_c=20.0,
                         stylus_offset=(0, 0, -50), bias_treatment="paper", **FAST)
    assert r.estimate_diameter == pytest.approx(171, abs=1e-3)


def test_progress_and_the_gil_released():
    counter = {"n": 0}
    done = threading.Event()

    def count():
        while not done.is_set():
            counter["n"] += 1

    calls = []
    thread = threading.Thread(target=count)
    thread.start()
    try:
        r = vcmm.uncertainty(MODEL, measured(), trials=10000, seed=1, threads=1,
                             bias_treatment="paper",
                             progress=lambda d, p: calls.append((d, p, counter["n"])))
    finally:
        done.set()
        thread.join()
    assert r.monte_carlo.trials == 10000
    assert calls and calls[-1][0] == calls[-1][1]
    assert all(d <= p for d, p, _ in calls)
    # The counting thread ran while the trials did: between the first and the last progress
    # report (≥ 0.1 s apart) it counted far more than a thread starved of the GIL could.
    assert len(calls) >= 2 and calls[-1][2] - calls[0][2] > 10000


def test_progress_exception_stops_the_run():
    def stop(done, planned):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        vcmm.uncertainty(MODEL, measured(), trials=100000, seed=1, threads=1,
                         bias_treatment="paper", progress=stop)


def test_version():
    assert vcmm.__version__.count(".") == 2


def test_uncertainty_equals_cli_on_a_plain_point_file():
    exe = os.environ.get("VCMM_EXE")
    if not exe:
        pytest.skip("VCMM_EXE (the vcmm command) not given")
    model = SOURCE_DIR / "examples" / "cmm_model.json"
    out = subprocess.run([exe, "uncertainty", "--model", str(model), "--points", str(SCAN),
                          "--mode", "scanning", "--temperature", "20.5", "--stylus-offset",
                          "0,0,-150", "--trials", "400", "--seed", "5", "--bias-treatment",
                          "paper", "--json", "--progress", "never"],
                         check=True, capture_output=True, text=True).stdout
    expected = json.loads(out)
    r = vcmm.uncertainty(model, SCAN, mode="scanning", temperature_c=20.5,
                         stylus_offset=(0, 0, -150), trials=400, seed=5,
                         bias_treatment="paper")
    got = json.loads(r.json())
    assert got["measurands"] == expected["measurands"]
    assert got["correlation_diameter_roundness"] == expected["correlation_diameter_roundness"]


def test_the_tutorial_plot_runs(tmp_path):
    pytest.importorskip("matplotlib")
    script = SOURCE_DIR / "examples" / "python" / "roundness_polar.py"
    target = tmp_path / "polar.png"
    out = subprocess.run([sys.executable, str(script), str(SCAN), str(target)], check=True,
                         capture_output=True, text=True, env=dict(os.environ)).stdout
    assert "RONt (MZ, 50 UPR) = 0.1427 um; certified: True" in out
    assert target.stat().st_size > 10000


def test_ctrl_c_stops_the_monte_carlo():
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            vcmm.uncertainty(MODEL, measured(), trials=1_000_000, seed=1, threads=1,
                             bias_treatment="paper")
    finally:
        timer.cancel()


def test_measurement_from_arrays():
    m = measured()
    again = vcmm.Measurement(m.points, m.normals, m.location, m.orientation_deg, m.mode,
                             m.temperature_c, m.stylus_offset)
    assert np.array_equal(again.points, m.points) and len(again) == 360
    assert again.csv() == m.csv()
    with pytest.raises(vcmm.InvalidInput, match=r"normal 0 must be a unit vector.*\|n\| = 2"):
        vcmm.Measurement(m.points, 2 * m.normals, m.location)
    with pytest.raises(vcmm.InvalidInput, match=r"normals: expected an \(n, 3\) array"):
        vcmm.Measurement(m.points, m.normals[:, :2], m.location)
    # Plain (x, y) points in the workpiece frame need the location.
    xy = m.points[:, :2]
    with pytest.raises(vcmm.InvalidInput, match="location"):
        vcmm.measurement(xy, mode="touch", temperature_c=20.0, stylus_offset=(0, 0, -150),
                         frame="workpiece")
    w = vcmm.measurement(xy, mode="touch", temperature_c=20.0, stylus_offset=(0, 0, -150),
                         frame="workpiece", location=(400, 300, 150))
    assert w.mode == "touch_trigger" and w.location == (400.0, 300.0, 150.0)


def test_validate_equals_the_cli(tmp_path):
    exe = os.environ.get("VCMM_EXE")
    if not exe:
        pytest.skip("VCMM_EXE (the vcmm command) not given")
    world = tmp_path / "world"
    (world / "measurements").mkdir(parents=True)
    (world / "model.json").write_text((SOURCE_DIR / "examples" / "cmm_model.json").read_text())
    entries = []
    for i, (location, orientation) in enumerate((((400, 300, 150), 0), ((500, 400, 200), 90))):
        m = vcmm.simulate(MODEL, 171, location, points=360, orientation_deg=orientation,
                          seed=20 + i)
        name = f"M{i}"
        (world / "measurements" / f"{name}.csv").write_text(m.csv())
        entries.append({"id": name, "points": f"measurements/{name}.csv",
                        "setup": {"location": f"L{i}", "location_mm": list(location),
                                  "orientation_deg": orientation, "height": "middle",
                                  "mode": "scanning"},
                        "reference": {"roundness": {"value_um": 0.2, "u_um": 0.01},
                                      "diameter": {"value_mm": 171.0, "u_um": 0.05}}})
    campaign = {"schema": "vcmm.campaign", "schema_version": 1, "model": "model.json",
                "evaluation": {"trials": 200, "seed": 3, "bias_treatment": "paper"},
                "measurements": entries}
    (world / "campaign.json").write_text(json.dumps(campaign))
    calls = []
    got = vcmm.validate(world / "campaign.json", tmp_path / "py", threads=2,
                        progress=lambda d, p: calls.append(d))
    subprocess.run([exe, "validate", str(world / "campaign.json"), "-o", str(tmp_path / "cli"),
                    "--threads", "2", "--progress", "never"], check=True, capture_output=True)
    assert [m["id"] for m in got["measurements"]] == ["M0", "M1"]
    assert got["computed"] == 2 and not got["cancelled"] and calls
    assert all(math.isfinite(m["roundness"]["en"]) for m in got["measurements"])
    for table in ("results.csv", "summary.csv"):
        assert (tmp_path / "py" / table).read_text() == (tmp_path / "cli" / table).read_text()
    again = vcmm.validate(world / "campaign.json", tmp_path / "py")
    assert again["resumed"] == 2
    # The same numbers, loaded instead of computed (NaN where nothing: compared as text).
    def numbers(measurements):
        return json.dumps([{k: v for k, v in m.items() if k not in ("wall_seconds", "resumed")}
                           for m in measurements], sort_keys=True)

    assert all(m["resumed"] for m in again["measurements"])
    assert numbers(again["measurements"]) == numbers(got["measurements"])
    assert all(m["budget"] is None and m["trial"] in ("exact", "spectral")
               for m in got["measurements"])

    # The uncertainty budget, as `vcmm validate --budget --budget-trials 100`: the same
    # budget.csv, and per measurement the budget as plain data.
    with pytest.raises(ValueError, match="budget_trials needs budget=True"):
        vcmm.validate(world / "campaign.json", tmp_path / "pyb", budget_trials=100)
    with pytest.raises(ValueError, match="budget_trials must be from 100"):
        vcmm.validate(world / "campaign.json", tmp_path / "pyb", budget=True, budget_trials=500)
    withb = vcmm.validate(world / "campaign.json", tmp_path / "pyb", threads=2, budget=True,
                          budget_trials=100)
    subprocess.run([exe, "validate", str(world / "campaign.json"), "-o", str(tmp_path / "clib"),
                    "--threads", "2", "--progress", "never", "--budget", "--budget-trials",
                    "100"], check=True, capture_output=True)
    assert (tmp_path / "pyb" / "budget.csv").read_text() == \
        (tmp_path / "clib" / "budget.csv").read_text()
    for m in withb["measurements"]:
        b = m["budget"]
        assert b["trials"] == 100
        assert [c["source"] for c in b["sources"]] == \
            ["roughness", "temperature", "kinematic", "probe", "noise"]
        assert math.isclose(sum(c["diameter_share"] for c in b["sources"]), 1.0, rel_tol=1e-12)
        assert math.isclose(b["diameter_quadrature_mm"],
                            math.sqrt(sum(c["diameter_u_mm"] ** 2 for c in b["sources"])),
                            rel_tol=1e-12)
        assert b["diameter_full_u_mm"] > 0
