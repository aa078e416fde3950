"""The corpus of robots nobody here wrote: every URDF example-robot-data installs.

Each robot is loaded by path (no family: the numeric defaults) with its last link as the
tool, and every check compares rcm-pin with a second route built here from the URDF
alone: plain Pinocchio on the model without mimic joints (continuous joints get the
cos/sin pair from the angle, mimic joints their multiplier and offset read from the
XML by this module), so a wrong coordinate map cannot hide. A check ends in one of three
outcomes: ``ok`` (the two routes agree to the tolerance next to it), ``refused`` (a typed
:class:`rcm_pin.errors.RcmPinError`, with its message) or a failure (anything else: a
traceback or a disagreement). ``tests/test_corpus.py`` runs the fast checks on every
robot; ``benchmarks/corpus.py`` runs all of them and prints the table.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pinocchio as pin

import rcm_pin
from rcm_pin.errors import RcmPinError

#: Pose and dynamics agreement between rcm-pin and plain Pinocchio [m, rad, SI]: both
#: run the same spatial algebra on the same numbers, so they agree to round-off.
EXACT = 1e-12
#: IK round trip: the pose reached from the solution, against the target [m, rad].
SOLVED = 1e-9


def robots_dir() -> Path:
    """Where example-robot-data installs its robots (``share/example-robot-data/robots``)."""
    share = Path(pin.__file__).resolve()
    for parent in share.parents:
        candidate = parent / "share" / "example-robot-data" / "robots"
        if candidate.is_dir():
            return candidate
    raise FileNotFoundError("example-robot-data is not installed beside pinocchio")


def corpus() -> list[Path]:
    """Every URDF of example-robot-data, sorted by path."""
    return sorted(robots_dir().rglob("*.urdf"))


def robot_id(path: Path) -> str:
    """A short test id: the URDF stem, with its package when the stem repeats."""
    if not path.is_relative_to(robots_dir()):
        return f"tests/data/{path.stem}"
    return f"{path.relative_to(robots_dir()).parts[0]}/{path.stem}"


@dataclass(frozen=True)
class Outcome:
    """One check on one robot: ``ok``, ``refused`` (typed error) or ``failed``."""

    status: str
    detail: str = ""


def plain_model(path: Path) -> pin.Model | None:
    """Plain Pinocchio's model of the URDF without mimic joints (None: urdfdom refuses it)."""
    try:
        return pin.buildModelFromUrdf(str(path))
    except ValueError:
        return None


def last_link(path: Path) -> str:
    """The tool: the last body frame of plain Pinocchio's tree, else the XML's last link."""
    model = plain_model(path)
    if model is None:
        links = [link.get("name", "") for link in ET.parse(path).getroot().iter("link")]
        return links[-1] if links else ""
    bodies = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
    return bodies[-1]


def _mimics(path: Path) -> dict[str, tuple[str, float, float]]:
    """follower joint -> (leader, multiplier, offset), read from the XML here."""
    out = {}
    for joint in ET.parse(path).getroot().iter("joint"):
        tag = joint.find("mimic")
        if tag is not None:
            out[joint.get("name", "")] = (
                tag.get("joint", ""),
                float(tag.get("multiplier", "1")),
                float(tag.get("offset", "0")),
            )
    return out


def plain_q(path: Path, full: pin.Model, angles: dict[str, float]) -> np.ndarray:
    """q of the no-mimic model from one value per independent joint (cos/sin built here)."""
    mimics = _mimics(path)
    q = pin.neutral(full)
    for j in range(1, full.njoints):
        name = full.names[j]
        if name in mimics:
            leader, mult, offset = mimics[name]
            value = mult * angles[leader] + offset
        elif name in angles:
            value = angles[name]
        else:
            continue
        joint = full.joints[j]
        if joint.nq == 2 and joint.nv == 1:
            q[joint.idx_q : joint.idx_q + 2] = (math.cos(value), math.sin(value))
        elif joint.nq == 1:
            q[joint.idx_q] = value
        else:
            raise AssertionError(f"{name}: {joint.shortname()} has no single coordinate")
    return q


def random_configuration(mech: rcm_pin.Mechanism, rng: np.random.Generator) -> np.ndarray:
    """Uniform inside the limits cut to one turn [-π, π] (revolute) or [-1, 1] m: some
    files give unbounded joints limits of 1e16 instead of none."""
    span = np.where(mech.revolute, math.pi, 1.0)
    lo, hi = np.maximum(mech.lower, -span), np.minimum(mech.upper, span)
    return rng.uniform(np.minimum(lo, hi), hi)


def load(path: Path) -> rcm_pin.Mechanism:
    """The robot by path with its last link as the tool."""
    return rcm_pin.load(path, tool_frame=last_link(path))


def check_fk(path: Path, rng: np.random.Generator, samples: int = 5) -> Outcome:
    """Tool pose and mass matrix of rcm-pin against plain Pinocchio at random angles."""
    from rcm_pin.dynamics import mass_matrix

    mech = load(path)
    if len(set(mech.joint_names)) != len(mech.joint_names):
        return Outcome("failed", f"coordinate joints repeat: {mech.joint_names}")
    full = plain_model(path)
    if full is None:
        return Outcome("failed", "rcm-pin loads a URDF that urdfdom refuses")
    data = full.createData()
    frame = full.getFrameId(mech.output.frame)
    worst = 0.0
    for _ in range(samples):
        q = random_configuration(mech, rng)
        qf = plain_q(path, full, dict(zip(mech.joint_names, q, strict=True)))
        pin.framesForwardKinematics(full, data, qf)
        expected = data.oMf[frame].homogeneous
        worst = max(worst, float(np.abs(rcm_pin.tool_pose(mech, q) - expected).max()))
        M_full = pin.crba(full, data, qf)
        M_full = np.triu(M_full) + np.triu(M_full, 1).T
        G = _velocity_map(path, full, mech)
        if mech.nv:
            M = mass_matrix(mech, q)
            worst = max(worst, float(np.abs(M - G.T @ M_full @ G).max()))
    if worst > EXACT * max(1.0, _scale(full)):
        return Outcome("failed", f"pose or M differs from plain Pinocchio by {worst:.1e}")
    return Outcome("ok", f"max |Δ| {worst:.0e}")


def _scale(full: pin.Model) -> float:
    """Mass-matrix scale for a relative tolerance: total mass x (reach + 1)²."""
    return sum(i.mass for i in full.inertias) * 10.0


def _velocity_map(path: Path, full: pin.Model, mech: rcm_pin.Mechanism) -> np.ndarray:
    """v_full = G v: one column per coordinate, built from the XML mimic tags here."""
    mimics = _mimics(path)
    columns = {name: i for i, name in enumerate(mech.joint_names)}
    G = np.zeros((full.nv, len(mech.joint_names)))
    for j in range(1, full.njoints):
        name, joint = full.names[j], full.joints[j]
        if joint.nv != 1:
            continue
        if name in mimics:
            leader, mult, _ = mimics[name]
            G[joint.idx_v, columns[leader]] = mult
        elif name in columns:
            G[joint.idx_v, columns[name]] = 1.0
    return G


def check_ik(path: Path, rng: np.random.Generator) -> Outcome:
    """``rcm_pin.inverse`` of a pose from FK: a solution reaching it, or a typed refusal."""
    mech = load(path)
    q = random_configuration(mech, rng)
    target = rcm_pin.tool_pose(mech, q)
    try:
        result = rcm_pin.inverse(mech, target)
    except RcmPinError as exc:
        return Outcome("refused", f"{type(exc).__name__}: {exc}")
    errors = [np.abs(rcm_pin.tool_pose(mech, s.q) - target).max() for s in result.solutions]
    if not errors or min(errors) > SOLVED:
        return Outcome("failed", f"best IK pose error {min(errors, default=math.inf):.1e}")
    return Outcome("ok", f"{len(errors)} solution(s), pose error {min(errors):.0e}")


def run(check, path: Path, seed: int = 0) -> Outcome:
    """One check; a typed error is a refusal, anything else a failure with its type."""
    rng = np.random.default_rng(seed)
    try:
        return check(path, rng)
    except RcmPinError as exc:
        return Outcome("refused", f"{type(exc).__name__}: {exc}")
    except Exception as exc:  # the corpus reports every other exception as a failure
        return Outcome("failed", f"{type(exc).__name__}: {exc}")


def cli(argv: list[str]) -> tuple[int, dict]:
    """``rcm-pin ARGV --json`` in this process: exit status and its one JSON document."""
    import contextlib
    import io
    import json

    from rcm_pin.cli import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = main([*argv, "--json"])
    return status, json.loads(out.getvalue())


def cli_outcome(status: int, doc: dict) -> Outcome | None:
    """A refusal for exit 2 / 3 with a typed JSON error, a failure for any other non-zero."""
    if status in (2, 3) and "error" in doc:
        error = doc["error"]
        return Outcome("refused", f"exit {status} {error['type']}: {error['message']}")
    if status != 0:
        return Outcome("failed", f"exit {status}: {doc}")
    return None


def _q_text(q: np.ndarray) -> str:
    return ",".join(repr(float(v)) for v in q)


def check_cli_fk(path: Path, rng: np.random.Generator) -> Outcome:
    """``rcm-pin fk PATH --q ...`` against plain Pinocchio at a random configuration."""
    mech = load(path)
    q = random_configuration(mech, rng)
    status, doc = cli(["fk", str(path), "--tool-frame", mech.output.frame, "--q", _q_text(q)])
    if (refused := cli_outcome(status, doc)) is not None:
        return refused
    full = plain_model(path)
    assert full is not None
    data = full.createData()
    pin.framesForwardKinematics(full, data, plain_q(path, full, dict(zip(mech.joint_names, q))))
    expected = data.oMf[full.getFrameId(mech.output.frame)].homogeneous
    error = float(np.abs(np.array(doc["solutions"][0]["pose"]) - expected).max())
    if error > EXACT:
        return Outcome("failed", f"fk pose differs from plain Pinocchio by {error:.1e}")
    return Outcome("ok", f"|Δ pose| {error:.0e}")


def check_cli(command: list[str]):
    """A CLI command on the robot (``{tool}`` and ``{q}`` filled in): exit 0, 2 or 3 only."""

    def check(path: Path, rng: np.random.Generator) -> Outcome:
        mech = load(path)
        q = _q_text(random_configuration(mech, rng))
        argv = [a.format(tool=mech.output.frame, q=q, path=path) for a in command]
        status, doc = cli(argv)
        return cli_outcome(status, doc) or Outcome("ok", ", ".join(sorted(doc)[:4]))

    check.__name__ = command[0]
    return check


#: The CLI commands of the corpus, each on every robot (``benchmarks/corpus.py``).
COMMANDS = {
    "singularities": check_cli(["singularities", "{path}", "--tool-frame", "{tool}", "--q", "{q}"]),
    "workspace": check_cli(["workspace", "{path}", "--tool-frame", "{tool}", "--samples", "2000"]),
}
