"""The MuJoCo export per catalogue mechanism: tree error, rigid-limit error, drift.

For each catalogue mechanism (and the URDF fixtures loaded by path) the MJCF export with
the default drift tolerance (1e-6) is loaded in MuJoCo and compared with rcm-pin at three
seeded states, the same as tests/test_mujoco_export.py:

* tree: max relative error of MuJoCo's M and bias projected through the coupling;
* rigid: max relative error of MuJoCo's rigid-limit q̈ (its M, bias, efc_J, −J̇v) against
  rcm-pin's constrained forward dynamics (closed mechanisms);
* no J̇v: the same without −J̇v (what a hand-made comparison that forgets it gets);
* drift: the largest equality residual of a 0.2 s free motion from home at joint rates of
  norm 1 rad/s, against the prediction of rcm_pin.export.settings.

    PYTHONPATH=. python benchmarks/mujoco_export.py              # print the table
    PYTHONPATH=. python benchmarks/mujoco_export.py --write docs/mujoco.md

``--write`` replaces the table between the ``<!-- mujoco-table -->`` markers of the file.
"""

from __future__ import annotations

import argparse
import re
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np

import rcm_pin
from rcm_pin.export import check, to_mjcf
from rcm_pin.model.coupling import mimic_tags

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
PATHS = {"rcm_wrist_arm.urdf": "tool", "mimic_tree.urdf": "tool_link"}
PATHS["continuous_joints.urdf"] = "tool_link"
MARK = "<!-- mujoco-table -->"


def row(name: str, folder: Path) -> str:
    mech = rcm_pin.load(str(DATA / name), tool_frame=PATHS[name]) if name in PATHS else None
    mech = mech or rcm_pin.load(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        export = to_mjcf(mech, folder / f"{mech.name}.xml")
    mech, mj = export.mechanism, check.load_mujoco(export.path, export.mechanism)
    cases = check.random_states(mech, np.random.default_rng(28))
    tree = max(check.tree_error(mj, mech, q, v) for q, v, _ in cases)
    rigid = nojdot = "–"
    if mech.loops is not None:
        rigid = f"{max(check.rigid_limit_error(mj, mech, *c) for c in cases):.1e}"
        worst = 0.0
        for q, v, tau in cases:
            good = check.rigid_acceleration(mj, mech, q, v, tau)
            bad = check.rigid_acceleration(mj, mech, q, v, tau, jdot=False)
            worst = max(worst, float(np.linalg.norm(bad - good) / np.linalg.norm(good)))
        nojdot = f"{worst:.1e}"
    q, v, _ = check.random_states(mech, np.random.default_rng(30), n=1)[0]
    drift = check.free_motion_drift(mj, mech, q, v, duration=0.2)
    s = export.settings
    eqs = f"{len(mimic_tags(mech.urdf))} / {len(mech.loops.closures) if mech.loops else 0}"
    return (
        f"| {mech.name} | {eqs} | {s.timestep:g} | {tree:.1e} | {rigid} | {nojdot} | "
        f"{drift:.1e} | {s.predicted_drift:.1e} |"
    )


def table() -> str:
    head = (
        "| mechanism | mimic / closures | dt [s] | tree M, b | rigid limit | without J̇v | "
        "drift 0.2 s [m, rad] | predicted |\n|---|---|---|---|---|---|---|---|"
    )
    with tempfile.TemporaryDirectory() as folder:
        rows = [row(n, Path(folder)) for n in (*rcm_pin.names(), *PATHS)]
    return "\n".join([head, *rows])


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--write", type=Path, help="replace the table between the markers")
    args = parser.parse_args(argv)
    text = table()
    if args.write is None:
        print(text)
        return 0
    doc = args.write.read_text()
    pattern = re.compile(re.escape(MARK) + ".*?" + re.escape(MARK), re.DOTALL)
    if not pattern.search(doc):
        print(f"{args.write}: no {MARK} markers", file=sys.stderr)
        return 1
    args.write.write_text(pattern.sub(lambda _: f"{MARK}\n{text}\n{MARK}", doc))
    print(f"wrote the table into {args.write}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
