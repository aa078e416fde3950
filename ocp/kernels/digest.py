"""What a compiled kernel's cache key is made of: its model's kinematic tree and its code.

Every kernel of :mod:`ocp.kernels` is cached on disk under a key (:mod:`ocp.compiled`)
that must change when the function would: :func:`update_with_tree` feeds a hash the
kinematic tree as :class:`ocp.symbolic.SymbolicModel` reads it (:func:`ocp.joints.joint_specs`,
:func:`ocp.joints.frame_specs`: kinds, axes, placements, mimic scalings and offsets,
indices); :func:`source_digest` hashes the source files of the code that writes the
function, so that editing any of them rebuilds the cache.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from types import ModuleType
from typing import Any

import numpy as np
import pinocchio as pin

from ocp.joints import frame_specs, joint_specs


def update_with_tree(h: Any, model: pin.Model) -> None:
    """Feed ``h`` (a :mod:`hashlib` object) the kinematic tree of ``model`` (masses and
    inertias do not enter)."""
    for j in joint_specs(model):
        h.update(f"{j.index}|{j.parent}|{j.kind}|{j.idx_q}|{j.idx_v}|{j.mimic}|".encode())
        h.update(np.array([j.scaling, j.offset, model.nq, model.nv], dtype=float).tobytes())
        for arr in (j.axis, j.rotation, j.translation):
            h.update(np.ascontiguousarray(arr, dtype=float).tobytes())
    for f in frame_specs(model):
        h.update(f"{f.index}|{f.parent}|".encode())
        for arr in (f.rotation, f.translation):
            h.update(np.ascontiguousarray(arr, dtype=float).tobytes())


def source_digest(here: str, modules: tuple[ModuleType, ...]) -> str:
    """SHA-256 of the file ``here`` (the kernel's own module, ``__file__``) followed by the
    source files of ``modules``."""
    files = [Path(here), *(Path(str(m.__file__)) for m in modules)]
    return hashlib.sha256(b"".join(f.read_bytes() for f in files)).hexdigest()


__all__ = ["source_digest", "update_with_tree"]
