"""Run the installed `rcm-pin` console script for every catalogue entry (CI wheel check).

Started by .ci/run with the Python of a fresh virtual environment that has only the built
wheel installed, from a temporary directory outside the checkout: it fails if the package
reads anything from the repository (xacro/, urdf/) or lacks its package data.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np

import rcm_pin
from rcm_pin.analysis.capabilities import reference_poses

exe = Path(sys.executable).with_name("rcm-pin")
site = Path(rcm_pin.__file__).resolve()
assert "site-packages" in site.parts, f"rcm_pin imported from {site}, not from the wheel"


def cli(*argv: str) -> dict:
    proc = subprocess.run([str(exe), *argv, "--json"], capture_output=True, text=True, timeout=600)
    if proc.returncode != 0:
        raise SystemExit(f"rcm-pin {' '.join(argv)} failed ({proc.returncode}):\n{proc.stdout}"
                         f"\n{proc.stderr}")  # fmt: skip
    return json.loads(proc.stdout)


def output_values(solution: dict, fk: dict) -> np.ndarray:
    """The tool pose (serial) or the output coordinates (closed) of a solution."""
    if fk["output_coords"] == ["x", "y", "z", "rotation"]:
        return np.array(solution["pose"])
    return np.concatenate([np.ravel(solution["output"][c]) for c in fk["output_coords"]])


names = [m["name"] for m in cli("list")["mechanisms"]]
assert names == list(rcm_pin.names()), names
for name in names:
    mech = rcm_pin.load(name)
    # a regular configuration (the RCM home is on the wrist singularity sin q5 = 0)
    home = reference_poses(mech).regular(mech)
    inputs = home if mech.loops is None else home[mech.loops.drive_q]
    fk = cli("fk", name, "--q=" + ",".join(repr(float(v)) for v in inputs))
    sol = fk["solutions"][0]
    if mech.loops is None:
        pose = np.array(sol["pose"])
        target = ["--pose", ";".join(",".join(repr(float(v)) for v in r) for r in pose[:3])]
    else:
        flat = np.concatenate([np.ravel(sol["output"][c]) for c in fk["output_coords"]])
        target = ["--pose=" + ",".join(repr(float(v)) for v in flat)]
    ik = cli("ik", name, *target)
    assert ik["count"] >= 1, ik
    # every solution reaches the fk output (a redundant arm need not return the fk input):
    # the tool pose (serial) or the output coordinates (closed; the output frame's other
    # coordinates differ between working modes)
    worst = max(float(np.max(np.abs(output_values(s, fk) - output_values(sol, fk))))
                for s in ik["solutions"])  # fmt: skip
    best = min(float(np.max(np.abs(np.array(s["q"]) - np.array(sol["q"])))) for s in
               ik["solutions"])  # fmt: skip
    print(
        f"{name:<16} fk + ik: {ik['count']} solutions, output error <= {worst:.1e}, "
        f"nearest {best:.1e} from the fk input"
    )
    assert worst < 1e-9, f"{name}: an ik solution misses the fk output by {worst:.1e}"
print(f"wheel smoke test: {len(names)} mechanisms from {site.parent}")

# -- the core install (no extra): the commands a user runs first work without any extra ---------
q = "--q=0.1,0.2,0.08,0,0.3,0"
for argv in (
    ["singularities", "rcm_bevel", q],
    ["simulate", "rcm_bevel", "--duration", "0.05", "--arg", "q3_upper=0.3"],
    ["ocp", "ik", "rcm_bevel", "--xyz", "0.02,-0.03,0.09"],
):
    cli(*argv)
    print(f"core install: rcm-pin {' '.join(argv)} ok")
# ... and a feature whose extra is missing exits 2 naming the install command
sweep = ["sweep", "rcm_bevel", "--vary", "q2_limit=0.8:1.4:2", "--metric", "cone_coverage",
         "--out", "sweep-out", "--json"]  # fmt: skip
proc = subprocess.run([str(exe), *sweep], capture_output=True, text=True, timeout=600)
error = json.loads(proc.stdout)["error"]
assert proc.returncode == 2 and error["type"] == "MissingExtraError", (proc.returncode, error)
assert "pip install 'rcm-pin[design]'" in error["message"], error
print(f"core install: rcm-pin sweep exits 2: {error['message']}")
