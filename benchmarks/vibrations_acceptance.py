"""Acceptance run of the natural frequencies (issue 14), run once by hand (about a minute).

    .venv/bin/python benchmarks/vibrations_acceptance.py [--poses 200] [--seed 0]

For each of the three parallel mechanisms, ``--poses`` random closed configurations (drives
moved uniformly by up to ±0.3 rad, or ±0.3·L for a prismatic drive, from home, the loops
closed by ``rcm_pin.forward``; type-2 and unreachable draws are skipped and counted) with a
random per-drive stiffness in [0.5, 2]·c₀: the max relative difference of the frequencies by
det(C − ω² M_q) = 0 and by the linearised constrained dynamics, and of ω(k c)/(√k ω(c)) − 1
for a random k in [1e-2, 1e2].
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import rcm_pin
from rcm_pin.analysis.position import forward
from rcm_pin.dynamics.vibrations import linearised_frequencies, natural_frequencies

BASE = {"planar_3rrr": 1e3, "spherical_3rrr": 2e2, "translational_3ppapa": 1e5}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--poses", type=int, default=200)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    rng = np.random.default_rng(args.seed)
    for name, c0 in BASE.items():
        t0 = time.perf_counter()
        mech = rcm_pin.load(name)
        home = mech.home
        drives = mech.loops.drive_q
        scale = np.where(mech.revolute[drives], 0.3, 0.3 * mech.loops.length_scale)
        worst_route = worst_sqrt = 0.0
        done = skipped = 0
        while done < args.poses:
            qa = home[drives] + scale * rng.uniform(-1.0, 1.0, 3)
            c = c0 * rng.uniform(0.5, 2.0, 3)
            k = 10.0 ** rng.uniform(-2.0, 2.0)
            try:
                q = forward(mech, qa, q_guess=home).solutions[0].q
                w = natural_frequencies(mech, q, c).frequencies
                lin = linearised_frequencies(mech, q, c)
            except rcm_pin.RcmPinError:
                skipped += 1
                continue
            wk = natural_frequencies(mech, q, k * c).frequencies
            worst_route = max(worst_route, float(np.max(np.abs(lin / w - 1.0))))
            worst_sqrt = max(worst_sqrt, float(np.max(np.abs(wk / (np.sqrt(k) * w) - 1.0))))
            done += 1
        print(
            f"{name}: {done} poses ({skipped} skipped), max rel. diff. of the two routes "
            f"{worst_route:.2e} (acceptance 1e-6), √c scaling {worst_sqrt:.2e}, "
            f"{time.perf_counter() - t0:.1f} s"
        )


if __name__ == "__main__":
    main()
