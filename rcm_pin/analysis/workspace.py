"""Workspace of any mechanism: sampled output points, their extent and voxel volume.

The numeric route samples the inputs uniformly within their limits (coordinates of a serial
mechanism; drives of a closed one, whose first assembly mode is kept) and maps them to the
output frame's position by Pinocchio (:func:`rcm_pin.analysis.position.forward`). The
occupied-voxel volume of the point cloud is an upper estimate that converges as the voxels
shrink and the samples grow. A family with closed forms adds its own figures (the RCM
mechanisms' analytic volume and rig specification, the planar mechanisms' areas) through
its :class:`WorkspaceModel`; :func:`workspace_model` returns it, else :class:`NumericWorkspace`.
"""

from __future__ import annotations

import time
from abc import ABC, abstractmethod
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin

from rcm_pin.errors import InvalidInputError, RcmPinError
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.rotations import FloatArray

#: Largest sample count accepted (memory: one (N, nq) array and one (N, 3) array).
MAX_SAMPLES = 5_000_000
#: Largest sample count of a closed mechanism without a closed-form workspace: each sample
#: is a Newton solve of the loops (about 0.3 ms), so this bounds a run to tens of seconds.
MAX_NEWTON_SAMPLES = 50_000
#: Longest projected run of the numeric closed-loop route [s].
MAX_SECONDS = 30.0
#: Fewest samples of a volume estimate (the CLI's lower bound for ``--samples``).
MIN_SAMPLES = 1000
#: Newton samples timed before a numeric closed-loop run is committed to, after one
#: untimed warm-up sample (the first solve builds or loads the mechanism's kernel: timing
#: it, as five samples did, projected 15x the actual cost).
PROBE = 40
#: Largest grid side of a family's workspace grid (n × n cells, several per orientation).
MAX_GRID = 1001


def _box(mech: Mechanism, idx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    lo = np.where(np.isfinite(mech.lower[idx]), mech.lower[idx], -np.pi)
    hi = np.where(np.isfinite(mech.upper[idx]), mech.upper[idx], np.pi)
    return np.maximum(lo, -np.pi), np.minimum(hi, np.pi)


def sample_joints(mech: Mechanism, n: int, seed: int = 0) -> FloatArray:
    """n uniform samples of the inputs within their limits, (n, k) (drives if closed).

    Raises:
        InvalidInputError: n outside 1..MAX_SAMPLES.
    """
    if not 1 <= n <= MAX_SAMPLES:
        raise InvalidInputError(f"sample count {n}; valid: 1..{MAX_SAMPLES}")
    rng = np.random.default_rng(seed)
    if mech.loops is None:  # unbounded, or limits of a turn or more: one turn
        from rcm_pin.analysis.serial_ik import search_box

        lo, hi = search_box(mech)
        return rng.uniform(lo, hi, (n, mech.nq))
    lo, hi = _box(mech, mech.loops.drive_q)
    return rng.uniform(lo, hi, size=(n, mech.loops.dof))


def output_points(mech: Mechanism, inputs: FloatArray) -> FloatArray:
    """World positions (N, 3) of the output frame for each input row (NaN where a closed
    mechanism does not assemble)."""
    from rcm_pin.analysis.position import forward

    out = np.full((len(inputs), 3), np.nan)
    model, data, fid = mech.model, mech.data, mech.output.frame_id
    for i, row in enumerate(inputs):
        if mech.loops is None:
            pin.forwardKinematics(model, data, mech.q_pin(row))
            out[i] = pin.updateFramePlacement(model, data, fid).translation
            continue
        try:
            q = forward(mech, row).solutions[0].q
        except RcmPinError:
            continue
        pin.forwardKinematics(model, data, q)
        out[i] = pin.updateFramePlacement(model, data, fid).translation
    return out


def volume_voxels(points: FloatArray, voxel: float) -> float:
    """Occupied-voxel volume of a point cloud [m³] (voxel edge ``voxel`` [m])."""
    if voxel <= 0:
        raise InvalidInputError(f"voxel edge {voxel}; valid: > 0")
    pts = points[np.all(np.isfinite(points), axis=1)]
    cells = np.unique(np.floor(pts / voxel).astype(np.int64), axis=0)
    return float(len(cells) * voxel**3)


class WorkspaceModel(ABC):
    """A mechanism's workspace figures and figure (the generic code adds the name).

    ``samples`` is ``rcm-pin workspace --samples`` (None: the model's default); ``options``
    are the grid options of :attr:`options` that the CLI passes (``n``, ``phi``,
    ``phi_range``) and ``mode`` where a figure draws one working mode.
    """

    #: Options of ``rcm-pin workspace`` the model uses (``samples``, ``n``, ``phi``,
    #: ``phi_range``); the others are refused, never ignored.
    options: tuple[str, ...] = ("samples",)

    @abstractmethod
    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        """The workspace figures by name (the CLI's JSON, without ``mechanism``)."""

    @abstractmethod
    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        """A PNG of the workspace at ``path``."""


class NumericWorkspace(WorkspaceModel):
    """The default: the sampled cloud's extent and voxel volume, three projections of it.

    ``samples`` defaults to 200 000 (serial) and 1000 for a closed mechanism (each sample
    is a Newton solve).
    """

    def summary(
        self, mech: Mechanism, samples: int | None, seed: int, **options: Any
    ) -> dict[str, Any]:
        if samples is None:
            samples = 200_000 if mech.loops is None else 1000
        if mech.loops is not None and samples > MAX_NEWTON_SAMPLES:
            raise InvalidInputError(
                f"{mech.name}: {samples} samples, each a Newton solve of the loops; valid: at "
                f"most {MAX_NEWTON_SAMPLES} (the family has no closed-form workspace)"
            )
        inputs = sample_joints(mech, samples, seed)
        probe = np.empty((0, 3))
        if mech.loops is not None:  # measure the cost of a Newton sample before committing
            warm = output_points(mech, inputs[:1])
            start = time.perf_counter()
            probe = np.vstack([warm, output_points(mech, inputs[1 : 1 + PROBE])])
            projected = (time.perf_counter() - start) / max(len(probe) - 1, 1) * samples
            if projected > MAX_SECONDS:
                affordable = int(samples * MAX_SECONDS / projected)
                hint = (
                    f"about {affordable} samples"
                    if affordable >= MIN_SAMPLES
                    else f"about {affordable} samples, fewer than the {MIN_SAMPLES} a volume "
                    "estimate needs: this mechanism's workspace needs a closed-form route"
                )
                raise InvalidInputError(
                    f"{mech.name}: {samples} samples would take about {projected:.0f} s (a "
                    f"Newton solve each); valid: at most {MAX_SECONDS:.0f} s of work, i.e. {hint}"
                )
        pts = np.vstack([probe, output_points(mech, inputs[len(probe) :])])
        ok = np.all(np.isfinite(pts), axis=1)
        if not ok.any():
            raise InvalidInputError(f"{mech.name}: no sample assembled; the workspace is empty")
        voxel = 0.004  # [m]
        return {
            "samples": samples,
            "assembled_fraction": float(ok.mean()),
            "volume_voxels": volume_voxels(pts[ok], voxel),
            "voxel_edge": voxel,
            "extent_min": pts[ok].min(axis=0),
            "extent_max": pts[ok].max(axis=0),
        }

    def plot(self, mech: Mechanism, path: Path, samples: int, seed: int, **options: Any) -> Path:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        pts = output_points(mech, sample_joints(mech, min(samples, 20_000), seed))
        pts = pts[np.all(np.isfinite(pts), axis=1)]
        fig, axes = plt.subplots(1, 3, figsize=(15, 5))
        for ax, (i, j) in zip(axes, ((0, 1), (0, 2), (1, 2)), strict=True):
            ax.scatter(pts[:, i], pts[:, j], s=0.3, alpha=0.3)
            ax.set(xlabel=f"{'xyz'[i]} [m]", ylabel=f"{'xyz'[j]} [m]", aspect="equal")
            ax.grid(alpha=0.3)
        fig.suptitle(f"{mech.name}: sampled positions of {mech.output.frame}")
        fig.tight_layout()
        fig.savefig(path, dpi=110)
        plt.close(fig)
        return Path(path)


NUMERIC_WORKSPACE = NumericWorkspace()


def workspace_model(mech: Mechanism) -> WorkspaceModel:
    """The family's :class:`WorkspaceModel`, else :class:`NumericWorkspace`."""
    return mech.family.capability(WorkspaceModel) or NUMERIC_WORKSPACE  # type: ignore[type-abstract]


def summary(
    mech: Mechanism, samples: int | None = None, seed: int = 0, **options: Any
) -> dict[str, Any]:
    """The mechanism's workspace figures (:func:`workspace_model`), its name first.

    Raises:
        InvalidInputError: a grid option ``n`` outside 5..MAX_GRID, or a bad sample count.
    """
    if not 5 <= int(options.get("n", 5)) <= MAX_GRID:
        raise InvalidInputError(f"grid size {options['n']}; valid: 5..{MAX_GRID} points per side")
    return {"mechanism": mech.name, **workspace_model(mech).summary(mech, samples, seed, **options)}


def plot(
    mech: Mechanism, path: Path, samples: int = 200_000, seed: int = 0, **options: Any
) -> Path:
    """The mechanism's workspace figure (:func:`workspace_model`)."""
    return workspace_model(mech).plot(mech, Path(path), samples, seed, **options)


__all__ = [
    "MAX_SAMPLES",
    "NumericWorkspace",
    "WorkspaceModel",
    "output_points",
    "plot",
    "sample_joints",
    "summary",
    "volume_voxels",
    "workspace_model",
]
