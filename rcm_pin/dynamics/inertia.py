"""Whether a mechanism carries the inertia its dynamics needs.

A URDF may leave out ``<inertial>`` (a kinematics-only description). Kinematics then work,
but forward dynamics divide by the mass matrix: M(q) (serial) or its restriction Nᵀ M N
to the motions the closures allow (closed, N a basis of null J_c) must be positive
definite. :func:`require_inertia` checks that once, before a simulation, and names the
joints that move no inertia and the links that carry none, instead of a singular solve
deep in the integrator.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

import numpy as np
import scipy.linalg

from rcm_pin.errors import InvalidInputError
from rcm_pin.model.mechanism import Mechanism

#: Relative size [1] below which an eigenvalue of M (or Nᵀ M N) counts as zero, against
#: the largest: the round-off of the recursive algorithms is ~1e-15 of it.
ZERO = 1e-12


def massless_links(mech: Mechanism) -> list[str]:
    """Links of the URDF without an ``<inertial>`` or with zero mass (in file order)."""
    root = ET.fromstring(mech.urdf)
    out = []
    for link in root.iter("link"):
        mass = link.find("inertial/mass")
        if mass is None or float(mass.get("value", "0") or 0) == 0.0:
            out.append(link.get("name", ""))
    return out


def require_inertia(mech: Mechanism, q: np.ndarray) -> None:
    """Refuse a dynamics run on a mechanism whose motions carry no inertia at ``q``.

    Raises:
        InvalidInputError: M(q) (closed: Nᵀ M N) is singular; the message names the
            joints whose motion moves no inertia and the links without ``<inertial>``.
    """
    from rcm_pin.dynamics.tree import mass_matrix

    M = mass_matrix(mech, q)
    N = np.eye(mech.nv)
    if mech.loops is not None:
        N = scipy.linalg.null_space(mech.constraint_jacobian(q))
    reduced = N.T @ M @ N
    if not reduced.size:
        return
    eigen = np.linalg.eigvalsh(reduced)
    if eigen.min() > ZERO * max(eigen.max(), 1.0):
        return
    idle = [mech.joint_names[i] for i in range(mech.nv) if not np.any(np.abs(M[:, i]) > 0)]
    links = massless_links(mech)
    raise InvalidInputError(
        f"{mech.name}: the mass matrix is singular"
        + (f" (joints {', '.join(idle)} move no inertia)" if idle else "")
        + (f"; links without <inertial>: {', '.join(links)}" if links else "")
        + "; dynamics needs a mass and inertia on the links each joint moves; valid: a URDF "
        "with <inertial> elements (kinematic commands work without them)"
    )


__all__ = ["massless_links", "require_inertia"]
