"""vcmm — exact roundness evaluation and a validated virtual CMM, from Python.

    >>> import vcmm
    >>> r = vcmm.roundness(points, filter_upr=50)      # points: (n, 2) or (n, 3) array, mm
    >>> print(r.mz.ront)                                # RONt about the minimum-zone circles, mm

Every length is in millimetres (the C++ library's unit); angles in degrees where a name says
``_deg``. Points are numpy float64 arrays of shape (n, 2) or (n, 3) (x, y[, z]; z is not used
by the roundness functions) or anything numpy converts to one (a list of pairs).

Reference circles (ISO 12181-2): LS least squares, MZ minimum zone, MI maximum inscribed, MC
minimum circumscribed. MZ, MI and MC are exact: every combinatorial decision is taken by exact
predicates, and each result carries its contact points and a certificate that ``verify``
re-checks independently (docs/method.md).

Errors: input that cannot be evaluated raises ``vcmm.InvalidInput`` (a ``ValueError``) with
the library's message, naming the function, the rule and the offending value; a quantity that
does not exist for valid input (the MI circle of a partial arc) raises ``vcmm.UndefinedResult``
(a ``ValueError``); a digital-model file that breaks its schema raises
``vcmm.InvalidParameter`` (an ``InvalidInput`` with ``key_path``, the entry's dotted path).

Long calls release the GIL: other Python threads run while a fit or a Monte Carlo runs.
The compiled part is ``vcmm._vcmm`` (pybind11, python/src/); this module only arranges it.
Tutorial: docs/python.md.
"""

import json as _json
import os as _os
import sys as _sys

try:
    import numpy as _numpy  # noqa: F401  (the compiled part takes and returns numpy arrays)
except ImportError as _error:
    raise ImportError(
        f"vcmm needs numpy, which this Python ({_sys.executable}) cannot import: run the "
        "interpreter vcmm was built for (CMake's VCMM_PYTHON3, /usr/bin/python3 by default) "
        "or install numpy for this one (docs/python.md, 'Which Python')") from _error
try:
    from . import _vcmm
except ImportError as _error:
    _built = sorted(f for f in _os.listdir(_os.path.dirname(__file__)) if f.startswith("_vcmm"))
    raise ImportError(
        f"vcmm's compiled part does not load in this Python ({_sys.executable}, "
        f"{_sys.version.split()[0]}): found {', '.join(_built) or 'no _vcmm module'} — it was "
        "built for another interpreter; run that one (CMake's VCMM_PYTHON3) or rebuild with "
        "-DVCMM_PYTHON3=" + _sys.executable + " (docs/python.md, 'Which Python')") from _error
from ._vcmm import (  # noqa: F401  (re-exported)
    AngularCoverage,
    BiasCorrection,
    Certificate,
    ClaimCheck,
    CoverageInterval,
    DigitalModel,
    FilteredProfile,
    InvalidInput,
    InvalidParameter,
    LeastSquaresCircle,
    MaximumInscribedCircle,
    Measurement,
    MeasurandSummary,
    MinimumCircumscribedCircle,
    MinimumZoneCircle,
    MonteCarloResult,
    ProfileHarmonics,
    RingUncertaintyResult,
    UndefinedResult,
    Verification,
    least_squares_circle,
    maximum_inscribed_circle,
    minimum_circumscribed_circle,
    minimum_zone_circle,
)

__version__ = _vcmm.version()
__revision__ = _vcmm.revision()

#: The reference circles, in the order results list them.
CIRCLES = ("LS", "MZ", "MI", "MC")

_FIELDS = {"LS": "least_squares", "MZ": "minimum_zone", "MI": "maximum_inscribed",
           "MC": "minimum_circumscribed"}


class CircleOutcome:
    """One requested reference circle of a :func:`roundness` evaluation.

    ``defined``: whether the circle exists for the profile; if not, ``reason`` says why and
    reading any circle attribute raises :class:`UndefinedResult` with that reason.
    ``caution``: set where the circle exists but is no roundness reference for the profile
    (MI and MC of an arc under 180°). ``certified``: the independent exact check
    (:func:`verify`) accepted the certificate (always False for LS, a numerical fit; None
    when :func:`roundness` was told not to check).
    ``circle``: the fitted circle (``LeastSquaresCircle``, ``MinimumZoneCircle``, ...).
    Its attributes are readable here directly: ``center`` (x, y), ``radius`` (MZ: the mean
    (R + r)/2, with ``inner_radius`` and ``outer_radius``), ``ront``, ``ronp``, ``ronv``,
    ``ronq`` (mm), ``contacts`` (indices into the input; MZ also ``outer_contacts`` and
    ``inner_contacts``), ``optimality`` ('global', 'local', or 'numerical' for LS) and, for
    MZ, MI and MC, ``certificate`` (``.argument``: the proof in words).
    """

    __slots__ = ("name", "defined", "reason", "caution", "certified", "circle")

    def __init__(self, name, circle, reason, caution, certified):
        self.name = name
        self.circle = circle
        self.defined = circle is not None
        self.reason = reason
        self.caution = caution
        self.certified = certified

    def __getattr__(self, attribute):
        if attribute.startswith("__"):
            raise AttributeError(attribute)
        if self.circle is None:
            raise UndefinedResult(f"{self.name} undefined: {self.reason}")
        return getattr(self.circle, attribute)

    def __dir__(self):
        return sorted(set(self.__slots__) | set(dir(self.circle) if self.circle else ()))

    def __repr__(self):
        if not self.defined:
            return f"<vcmm.CircleOutcome {self.name} undefined: {self.reason}>"
        return (f"<vcmm.CircleOutcome {self.name} center={self.center} radius={self.radius} "
                f"ront={self.ront} certified={self.certified}>")


class Roundness:
    """The result of :func:`roundness`.

    ``ls``, ``mz``, ``mi``, ``mc``: a :class:`CircleOutcome` per requested circle (None when
    not requested); ``circles``: the same as a dict by name, in request order.
    ``n_points``; ``filter_upr`` (None: unfiltered) and ``filter_path`` ('fft', 'nonuniform'
    or 'open_profile' for a partial arc); ``profile``: the (n, 2) points the circles were
    fitted to (the filtered profile when filtered, else the input); ``coverage``: the
    angular coverage (``covered_rad``, ``largest_gap_rad``, ``closed``) about the first
    defined circle's centre.
    """

    def __init__(self, evaluation, names, verify_certificates):
        self.evaluation = evaluation
        self.n_points = evaluation.n_points
        self.filter_upr = evaluation.filter_upr
        self.filter_path = evaluation.filter_path
        self.coverage = evaluation.coverage
        undefined, cautions = evaluation.undefined, evaluation.cautions
        self.circles = {}
        for name in names:
            circle = getattr(evaluation, _FIELDS[name])
            certified = None
            if verify_certificates and circle is not None:
                certified = bool(evaluation.verify(name))  # None → False for LS
            self.circles[name] = CircleOutcome(name, circle, undefined.get(name),
                                               cautions.get(name), certified)
        self.ls = self.circles.get("LS")
        self.mz = self.circles.get("MZ")
        self.mi = self.circles.get("MI")
        self.mc = self.circles.get("MC")

    @property
    def profile(self):
        return self.evaluation.profile

    def __repr__(self):
        parts = ", ".join(f"{n} RONt={c.ront:.6g}" if c.defined else f"{n} undefined"
                          for n, c in self.circles.items())
        filt = f"{self.filter_upr:g} UPR" if self.filter_upr is not None else "unfiltered"
        return f"<vcmm.Roundness {self.n_points} points, {filt}: {parts} (mm)>"


def roundness(points, filter_upr=None, circles=CIRCLES, verify_certificates=True):
    """Roundness of a profile: the Gaussian filter (optional), then each requested reference
    circle with its RON parameters, each on its own (``vcmm::geometry::evaluate_roundness``).

    points: (n, 2) or (n, 3) array-like, mm. filter_upr: ISO 16610-21 Gaussian cut-off in
    undulations per revolution (15, 50, 150, 500, 1500) or None for unfiltered; a closed
    profile takes the closed filter, a partial arc the open-profile one. circles: any of
    "LS", "MZ", "MI", "MC" (any case). A circle that does not exist for the profile (the MI
    of a partial arc) is reported undefined with its reason; the others are still given.
    Contact indices refer to the input order; certificates to ``profile``.
    verify_certificates: re-check every MZ, MI and MC certificate with :func:`verify` (the
    ``certified`` attribute; as ``vcmm roundness`` does). It costs most of the time: on the
    bundled 3 600-point scan 0.2 ms for the four circles, 13 ms for the three checks (MI
    11 ms). False leaves ``certified`` None.
    Raises InvalidInput for input no circle can be fitted to (too few, non-finite, identical
    or collinear points; an arc with a gap wider than half the cut-off wavelength).
    """
    if isinstance(circles, str):
        circles = (circles,)
    names = []
    for c in circles:
        name = str(c).upper()
        if name not in _FIELDS:
            raise InvalidInput(f"roundness: circles must be among LS, MZ, MI, MC; got '{c}'")
        if name not in names:
            names.append(name)
    evaluation = _vcmm.evaluate_roundness(points, filter_upr, names)
    return Roundness(evaluation, names, verify_certificates)


def verify(points, circle):
    """Re-checks a MZ, MI or MC result exactly and independently of the fitter (the contacts,
    containment, alternation, the reported numbers within a few ulps, a global claim
    re-derived); returns a :class:`Verification` (true when valid; else ``reason`` names the
    first failed condition). ``circle``: a fitter's result or a :class:`CircleOutcome`;
    ``points``: the points it was fitted to (for a filtered evaluation, ``result.profile``).
    """
    if isinstance(circle, CircleOutcome):
        if not circle.defined:
            raise UndefinedResult(f"{circle.name} undefined: {circle.reason}")
        circle = circle.circle
    if isinstance(circle, LeastSquaresCircle):
        raise InvalidInput("verify: the least-squares circle is a numerical fit and carries no "
                           "certificate; give a MZ, MI or MC circle")
    return _vcmm.verify(points, circle)


def gaussian_filter(points, cutoff_upr, profile="closed", path="automatic"):
    """ISO 16610-21 Gaussian filter of a profile's radial deviations about its LS centre.

    profile: 'closed' (a full profile, going once round its centre with no gap wider than
    half the cut-off wavelength) or 'open' (a partial arc, ends treated by the weighted
    least-squares line). path (closed only): 'automatic' (FFT on equiangular samples, exact
    transmission 2^-(k/f_c)^2; else convolution) or 'nonuniform' (always the convolution).
    Returns a :class:`FilteredProfile`: ``points`` (n, 2) in input order, ``filter_center``,
    ``mean_radius``, ``path``. Needs at least 8 points and a cut-off in (0, n/2].
    """
    return _vcmm.gaussian_filter(points, float(cutoff_upr), profile, path)


def gaussian_filter_deviations(deviations, cutoff_upr):
    """The Gaussian filter of an equiangular closed sequence of radial deviations (any unit),
    by the exact transmission H(k) = 2^-(k/f_c)^2; returns a numpy array."""
    return _vcmm.gaussian_filter_deviations(list(map(float, deviations)), float(cutoff_upr))


def harmonics(points, max_order, center=None, radius=None):
    """Harmonic analysis of a closed profile's radial deviations d(θ) = a_0 + Σ a_k cos kθ +
    b_k sin kθ about a circle (default: the profile's LS circle), θ counter-clockwise from +x.

    Returns a :class:`ProfileHarmonics`: ``cos`` and ``sin`` (a_k, b_k in mm, k = 0 …
    max_order), ``deviations``, ``path`` ('fft' on equiangular samples, else 'quadrature'),
    ``synthesized(gains)``. Amplitude of harmonic k: hypot(a_k, b_k); its peak-to-valley is
    twice that. Needs at least 8 points and 1 ≤ max_order ≤ n/2.
    """
    if center is None or radius is None:
        ls = least_squares_circle(points)
        center = ls.center if center is None else center
        radius = ls.radius if radius is None else radius
    return _vcmm.profile_harmonics(points, tuple(center), float(radius), int(max_order))


def check_claim(points, reference, center, radii=None, center_resolution=0.0):
    """Checks another program's reference circle against the exact one (docs/method.md §9).

    reference: 'MZ', 'MI', 'MC' or 'LS'; center: (x, y) mm; radii: MZ (inner, outer), the
    others one radius (a number) — None: the tightest radii for the centre;
    center_resolution: half a unit in the last decimal the other program wrote (0 for exact
    doubles). Returns a :class:`ClaimCheck`: ``feasible``, ``violations``, ``claimed_ront``,
    ``exact_ront``, ``excess_ront``, ``optimal`` and the exact circle.
    """
    if radii is not None and not isinstance(radii, (tuple, list)):
        radii = (float(radii), float(radii))
    return _vcmm.check_claimed_circle(points, str(reference).upper(), tuple(center),
                                      None if radii is None else tuple(radii),
                                      float(center_resolution))


# ---- the virtual CMM and the Monte Carlo uncertainty ------------------------------------------

def load_model(model=None):
    """A :class:`DigitalModel` (docs/errormodel.md): a path to the JSON file, the parsed JSON
    as a dict, a JSON string, an existing DigitalModel, or None for the bundled example
    model (examples/cmm_model.json). Raises InvalidParameter naming the offending entry."""
    if model is None:
        return _vcmm.parse_digital_model(_vcmm.bundled_example_model_json(),
                                         "bundled example model")
    if isinstance(model, DigitalModel):
        return model
    if isinstance(model, dict):
        return _vcmm.parse_digital_model(_json.dumps(model), "model dict")
    if isinstance(model, str) and model.lstrip().startswith("{"):
        return _vcmm.parse_digital_model(model, "model JSON text")
    return _vcmm.read_digital_model_file(_os.fspath(model))


def simulate(model, ring_diameter, location, *, points=None, mode="scanning",
             orientation_deg=0.0, height=0.0, temperature_c=20.0, stylus_offset=(0, 0, 0),
             seed=1, sources=None, form=True, formula="first_order", corrected=False):
    """What the virtual CMM reports for a ring gauge (as ``vcmm simulate``): the nominal ring
    of ``ring_diameter`` mm (with the seed study's ~200 nm form unless ``form=False``),
    ``points`` equiangular points (default 3600 scanning, 16 touch), centred at machine
    ``location`` (x, y, z) mm, rotated ``orientation_deg`` about machine Z, section at
    ``height``; one draw (``seed``) of every error source of ``model`` (or only ``sources``:
    roughness, temperature, kinematic, probe, noise); ``formula`` 'first_order' or 'exact'
    kinematics; ``corrected``: the known systematic errors removed. Returns a
    :class:`Measurement` (``points``, ``normals``, ``machine_points`` as (n, 3) arrays)."""
    return _vcmm.simulate(load_model(model), float(ring_diameter), points, mode,
                          tuple(map(float, location)), float(orientation_deg), float(height),
                          float(temperature_c), tuple(map(float, stylus_offset)), int(seed),
                          None if sources is None else list(sources), bool(form), formula,
                          bool(corrected))


def measurement(data, **setup):
    """A :class:`Measurement` from ``data``: a Measurement (returned as is), a file path (vcmm's
    measurement CSV, plain x,y[,z] points or a roundness-meter profile angle_deg,deviation_um;
    docs/formats.md) or an (n, 2)/(n, 3) array of points. Plain points and profiles need their
    metadata as keywords (the options of ``vcmm uncertainty``): mode ('scanning'/'touch'),
    temperature_c, stylus_offset (x, y, z) mm, location (x, y, z) mm (machine position of the
    ring centre), orientation_deg, frame ('machine'/'workpiece'), surface ('inner'/'outer');
    profiles also radius (mm) and height (mm). Raises InvalidInput naming every missing item."""
    if isinstance(data, Measurement):
        if setup:
            raise InvalidInput("measurement: a Measurement carries its own metadata; got "
                               + ", ".join(sorted(setup)))
        return data
    for key in ("location", "stylus_offset"):
        if setup.get(key) is not None:
            setup[key] = tuple(map(float, setup[key]))
    if isinstance(data, (str, bytes, _os.PathLike)):
        return _vcmm.read_measurement_file(_os.fsdecode(data), **setup)
    for key in ("radius", "height"):
        if key in setup:
            raise InvalidInput(f"measurement: '{key}' applies to roundness-meter profile files "
                               "only")
    return _vcmm.measurement_from_points(data, **setup)


def uncertainty(model, data, *, trials=100000, adaptive_tolerance=None, seed=1, threads=0,
                reference="MZ", filter_upr=50.0, coverage=0.95, bias_treatment="shrinkage",
                pilot_trials=None, surrogate_trials=None, sources=None, progress=None,
                trial="auto", **setup):
    """Monte Carlo uncertainty (JCGM 101) of the LS diameter and the roundness RONt of one ring
    measurement, with bias and bias-corrected estimates, as ``vcmm uncertainty``
    (``vcmm::validation::evaluate_ring_uncertainty``).

    model: see :func:`load_model`. data: see :func:`measurement` (``setup`` keywords: its
    metadata). trials: M (or ``adaptive_tolerance`` in mm: the JCGM 101 7.9 adaptive run);
    seed fixes every number whatever ``threads`` (0: all cores); reference 'MZ', 'MI', 'LS'
    or 'MC' and filter_upr (None: unfiltered) define RONt; bias_treatment 'shrinkage'
    (default) or 'paper' (the seed study's, always reported as ``roundness_paper``);
    sources: error sources switched on (default all). trial: the first run's Monte Carlo
    trial, 'auto' (spectral where it applies), 'exact' or 'spectral' (docs/validation.md,
    "The spectral trial"; ``trial`` of the result says which ran and why). progress: called as
    progress(done, planned) about every 0.1 s from the calling thread. The GIL is released
    while the trials run; Ctrl-C raises KeyboardInterrupt.

    Returns a :class:`RingUncertaintyResult`: ``estimate_diameter``, ``estimate_roundness``,
    ``diameter``, ``roundness``, ``roundness_paper`` (:class:`BiasCorrection`: estimate,
    bias, corrected, standard_uncertainty, interval, note), ``samples`` ((M, 2) array:
    diameter, roundness in mm), ``monte_carlo`` (trials, status, summaries, wall_seconds),
    ``json()`` and ``table()`` (the reports of the command). Lengths in mm.
    """
    return _vcmm.evaluate_ring_uncertainty(
        load_model(model), measurement(data, **setup), trials=int(trials),
        adaptive_tolerance=None if adaptive_tolerance is None else float(adaptive_tolerance),
        seed=int(seed), threads=int(threads), reference=str(reference).upper(),
        filter_upr=None if filter_upr is None else float(filter_upr), coverage=float(coverage),
        bias_treatment=bias_treatment, pilot_trials=pilot_trials,
        surrogate_trials=surrogate_trials, sources=None if sources is None else list(sources),
        progress=progress, trial=str(trial))


def validate(campaign, output_dir, *, threads=0, denoised=False, progress=None, budget=None,
             budget_trials=0):
    """Runs a validation campaign, as ``vcmm validate CAMPAIGN -o OUTPUT_DIR``
    (``vcmm::validation::run_campaign``; docs/validation.md): the uncertainty of every
    measurement, E_n and zeta against the references under each bias treatment, and the
    output files in ``output_dir`` (results.csv/json, summary, samples, run_info.json). A rerun
    resumes: finished measurements are loaded, not recomputed. ``denoised`` adds treatment (b).
    progress(done, planned) as in :func:`uncertainty`; the GIL is released, Ctrl-C stops.

    Returns plain tables (lists of dicts, for ``pandas.DataFrame`` or ``csv`` alike):
    ``measurements`` (id, location, orientation_deg, height, mode, points, seed, trials and
    per measurand ``diameter``/``roundness`` a dict: estimate_mm, u_mm, reference_mm,
    corrected_mm, u_corrected_mm, en, en_corrected, en_paper, ... — values in mm, NaN where
    there is nothing), ``summary`` (E_n statistics per factor level and treatment),
    ``treatments`` (with known truth), ``computed``, ``resumed``, ``cancelled``,
    ``wall_seconds``. Each measurement also says which Monte Carlo ``trial`` its first run took
    ("exact" or "spectral") and carries its uncertainty ``budget`` (None without one): trials,
    ``sources`` (per error source u_i and share u_i²/Σu_j² of diameter and roundness, mm),
    the quadrature sums and the full run's u. ``budget=True``/``False`` overrides the
    campaign's ``"budget"`` and ``budget_trials`` its ``"budget_trials"``, as
    ``vcmm validate --budget --budget-trials N`` (docs/validation.md, "Uncertainty budget").
    """
    return _vcmm.run_campaign(_os.fspath(campaign), _os.fspath(output_dir), int(threads),
                              bool(denoised), progress,
                              None if budget is None else bool(budget), int(budget_trials))
