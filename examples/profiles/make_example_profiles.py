#!/usr/bin/env python3
"""Generates the bundled example profiles (deterministic; Python standard library only).

ring_171mm_scan.csv    a 171 mm ring gauge (inner surface, radius 85.5 mm) scanned with 3600
                       equiangular points, as a CMM reports it in machine coordinates (centre
                       at x = 412.5 mm, y = 305.25 mm): form deviation of about 200 nm
                       peak-to-valley (harmonics 2, 3, 4, 5, 7, 11, 17) plus 15 nm white noise.
ring_171mm_touch16.csv the same ring probed at 16 equiangular touch-trigger points (25 nm
                       noise), z = measuring height.

The numbers are synthetic: they show the format and exercise the evaluation; they are not a
real calibration. Run `python3 make_example_profiles.py` in this folder to regenerate.
"""
import math
import random

CENTER = (412.5, 305.25)
RADIUS = 85.5
HEIGHT = 150.0  # measuring height: tip z in the machine frame of examples/cmm_model.json
# (order, amplitude mm, phase rad): ~200 nm peak-to-valley in total
HARMONICS = [(2, 45e-6, 0.4), (3, 30e-6, 1.9), (4, 12e-6, 2.7), (5, 10e-6, 0.1),
             (7, 6e-6, 4.0), (11, 4e-6, 5.2), (17, 3e-6, 1.3)]


def radius_at(theta):
    return RADIUS + sum(a * math.cos(k * theta + p) for k, a, p in HARMONICS)


def write(path, n, noise, seed, header):
    rng = random.Random(seed)
    with open(path, "w") as f:
        f.write(header)
        f.write("x_mm,y_mm,z_mm\n")
        for i in range(n):
            t = 2.0 * math.pi * i / n
            r = radius_at(t) + rng.gauss(0.0, noise)
            f.write(f"{CENTER[0] + r * math.cos(t):.9f},{CENTER[1] + r * math.sin(t):.9f},"
                    f"{HEIGHT:.3f}\n")


write("ring_171mm_scan.csv", 3600, 15e-6, 171,
      "# vcmm example: 171 mm ring gauge, scanning, 3600 points, machine coordinates (mm)\n"
      "# synthetic: ~200 nm form (harmonics 2-17) + 15 nm noise; see make_example_profiles.py\n")
write("ring_171mm_touch16.csv", 16, 25e-6, 1716,
      "# vcmm example: 171 mm ring gauge, touch-trigger, 16 points, machine coordinates (mm)\n"
      "# synthetic: ~200 nm form (harmonics 2-17) + 25 nm noise; see make_example_profiles.py\n")
