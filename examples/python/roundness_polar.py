#!/usr/bin/python3
"""Polar plot of a profile's deviations from its minimum-zone circles (docs/python.md).

Usage:  /usr/bin/python3 examples/python/roundness_polar.py [PROFILE.csv] [OUT.png]
Defaults: examples/profiles/ring_171mm_scan.csv, roundness_polar.png. Needs the module vcmm
(PYTHONPATH=build/python, or `pip install .`), numpy and matplotlib.
"""

import pathlib
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import vcmm  # noqa: E402

root = pathlib.Path(__file__).resolve().parents[2]
source = sys.argv[1] if len(sys.argv) > 1 else root / "examples/profiles/ring_171mm_scan.csv"
target = sys.argv[2] if len(sys.argv) > 2 else "roundness_polar.png"

points = np.loadtxt(source, delimiter=",", comments="#", skiprows=3)  # 2 comments + header
r = vcmm.roundness(points, filter_upr=50, circles=("MZ",))
mz = r.mz
print(f"RONt (MZ, 50 UPR) = {mz.ront * 1e3:.4f} um; certified: {mz.certified}, "
      f"{mz.optimality}: {mz.certificate.argument}")

# Deviations of the evaluated (filtered) profile from the mean MZ circle, in µm.
xy = r.profile - np.asarray(mz.center)
theta = np.arctan2(xy[:, 1], xy[:, 0])
deviation_um = (np.hypot(xy[:, 0], xy[:, 1]) - mz.radius) * 1e3
half_zone_um = mz.ront / 2 * 1e3
base = 2 * mz.ront * 1e3  # the radius at which the mean circle is drawn: the zone stays visible

order = np.argsort(theta)
ax = plt.figure(figsize=(6, 6)).add_subplot(projection="polar")
ax.plot(theta[order], base + deviation_um[order], lw=0.8, label="profile (50 UPR)")
circle = np.linspace(-np.pi, np.pi, 721)
for radius, name in ((base - half_zone_um, "MZ inner"), (base + half_zone_um, "MZ outer")):
    ax.plot(circle, np.full_like(circle, radius), "--", lw=1, label=name)
contacts = mz.contacts
ax.plot(theta[contacts], base + deviation_um[contacts], "ko", ms=4, label="MZ contacts")
ax.set_ylim(0, base + 2 * half_zone_um)
ticks = np.array([-half_zone_um, 0.0, half_zone_um])  # radial labels: the deviation, µm
ax.set_yticks(base + ticks)
ax.set_yticklabels([f"{t:+.3f}" if t else "0" for t in ticks], fontsize=8)
ax.set_rlabel_position(160)
ax.set_title(f"RONt = {mz.ront * 1e3:.3f} µm (MZ, Gaussian filter 50 UPR)\n"
             "radial: deviation from the mean MZ circle (µm)")
ax.legend(loc="lower left", bbox_to_anchor=(-0.1, -0.12), fontsize=8, ncol=2)
plt.savefig(target, dpi=150, bbox_inches="tight")
print(f"wrote {target}")
