"""Variable layout, bounds and initial guesses of the tracking OCP (:mod:`ocp.tracking`).

Variables stage-wise ``[x_0, u_0, x_1, u_1, ..., x_N]`` (fatrop's order): node states
``x_k = (q_k, v_k)`` (nx = 2 n), stage controls ``u_k = (Q_1..Q_d)`` (nu = n d);
constraints per stage ``[gap (nx); drive limits (n d); velocity limits (n d)]``.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from ocp.collocation import Collocation
from ocp.symbolic import SymbolicModel
from rcm_pin.errors import InvalidInputError

#: Resident memory per decision variable of the solve [bytes] (the NLP, IPOPT's sparse
#: derivatives and MUMPS's factors; measured on paper 000's OCP, 6 joints, degree 3:
#: 44-48 kB per interval of 30 variables from N = 400 to 6400).
BYTES_PER_VARIABLE = 1500
#: Largest estimated memory of a tracking OCP [bytes] (paper 000's OCP: N <= 23 860).
MAX_BYTES = 1 << 30


def check_size(n_intervals: int, nv: int, degree: int) -> None:
    """Refuse a grid whose estimated memory exceeds :data:`MAX_BYTES`.

    Raises:
        InvalidInputError: N (nx + nu) :data:`BYTES_PER_VARIABLE` > :data:`MAX_BYTES`; the
            message gives the estimate and the largest N.
    """
    per_interval = nv * (2 + degree) * BYTES_PER_VARIABLE
    largest = MAX_BYTES // per_interval
    if n_intervals > largest:
        raise InvalidInputError(
            f"n_intervals {n_intervals} needs about {n_intervals * per_interval / 1e9:.3g} GB "
            f"of memory ({per_interval / 1e3:.0f} kB per interval of {nv * (2 + degree)} "
            f"variables); valid: 1 to {largest} intervals ({MAX_BYTES / 2**30:g} GiB)"
        )


class TrackingGrid:
    """The grid part of :class:`ocp.tracking.TrackingOCP` (set by its constructor)."""

    sm: SymbolicModel
    col: Collocation
    N: int
    h: float
    T: float
    nx: int
    nu: int
    lower: np.ndarray
    upper: np.ndarray
    drive_limits: bool
    velocity_limits: bool

    def _split(self, w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Node states (N + 1, nx) and stage controls (N, nu) of a variable vector."""
        body = w[: -self.nx].reshape(self.N, self.nx + self.nu)
        return np.vstack([body[:, : self.nx], w[-self.nx :]]), body[:, self.nx :]

    def _join(self, x: np.ndarray, u: np.ndarray) -> np.ndarray:
        return np.concatenate([np.hstack([x[:-1], u]).reshape(-1), x[-1]])

    def bounds(
        self,
        x_init: np.ndarray,
        effort_limits: np.ndarray | None,
        velocity_limits: np.ndarray | None,
    ) -> dict[str, np.ndarray]:
        """``lbx, ubx, lbg, ubg``: boundary condition, joint, drive and velocity limits."""
        n, d = self.sm.nv, self.col.degree
        inf = np.full(n, np.inf)
        tmax = inf if effort_limits is None else np.asarray(effort_limits, float)
        vmax = inf if velocity_limits is None else np.asarray(velocity_limits, float)
        for name, lim, on in (
            ("effort", tmax, self.drive_limits),
            ("velocity", vmax, self.velocity_limits),
        ):
            if lim.shape != (n,) or np.any(lim < 0) or (np.isfinite(lim).any() and not on):
                raise InvalidInputError(
                    f"{name}_limits must be ({n},) >= 0 and enabled at "
                    f"construction ({name.replace('effort', 'drive')}"
                    f"_limits=True)"
                )
        xl = np.concatenate([self.lower, np.full(n, -np.inf)])
        xu = np.concatenate([self.upper, inf])
        lbx = self._join(np.tile(xl, (self.N + 1, 1)), np.tile(np.tile(self.lower, d), (self.N, 1)))
        ubx = self._join(np.tile(xu, (self.N + 1, 1)), np.tile(np.tile(self.upper, d), (self.N, 1)))
        lbx[: self.nx] = ubx[: self.nx] = x_init  # boundary condition x_0 = x_init
        path = np.concatenate(
            [np.tile(tmax, d)] * self.drive_limits
            + [np.tile(vmax, d)] * self.velocity_limits
            + [np.zeros(0)]
        )
        ubg = np.tile(np.concatenate([np.zeros(self.nx), path]), self.N)
        lbg = np.tile(np.concatenate([np.zeros(self.nx), -path]), self.N)
        return {"lbx": lbx, "ubx": ubx, "lbg": lbg, "ubg": ubg}

    def keeps(self, res: Any, limits: tuple[np.ndarray | None, np.ndarray | None]) -> bool:
        """Whether ``res`` keeps the joint limits (nodes and collocation points) and the
        drive and velocity limits."""
        for q in (res.q, res.q_colloc):
            if np.any(q < self.lower) or np.any(q > self.upper):
                return False
        return all(
            lim is None or bool(np.all(np.abs(value) <= lim))
            for lim, value in zip(limits, (res.tau, res.v_colloc))
        )

    def parameter_symbols(self) -> tuple[ca.MX, ca.MX]:
        """The stage parameter columns (np, N) as a function of the NLP's parameter
        ``p = (p_ref (N d points, column-major (3, N d)), posture)``: the MX of both."""
        n, d = self.sm.nv, self.col.degree
        pref_all, post_mx = ca.MX.sym("p_ref", 3, self.N * d), ca.MX.sym("posture", n)
        steps = np.tile([[1.0 / self.h], [self.h / self.T]], (1, self.N))
        params = ca.vertcat(
            ca.reshape(pref_all, 3 * d, self.N), ca.repmat(post_mx, 1, self.N), ca.DM(steps)
        )
        return params, ca.vertcat(ca.vec(pref_all), post_mx)

    def stage_parameters(self, pref: np.ndarray, posture: np.ndarray) -> np.ndarray:
        """The stage parameter columns ``(p_ref (3 d), posture, 1/h, h/T)`` (np, N) of a
        reference at the collocation points (N d, 3)."""
        return np.vstack(
            [
                pref.reshape(self.N, 3 * self.col.degree).T,
                np.tile(np.asarray(posture, float)[:, None], (1, self.N)),
                np.full((1, self.N), 1.0 / self.h),
                np.full((1, self.N), self.h / self.T),
            ]
        )

    def collocation_times(self) -> np.ndarray:
        """Times of the ``N d`` collocation points."""
        k = np.arange(self.N)[:, None]
        return ((k + self.col.tau[None, 1:]) * self.h).reshape(-1)

    def guess_from(self, q_colloc: np.ndarray, x_init: np.ndarray) -> np.ndarray:
        """Variable vector from positions at the collocation points (N d, nq); node
        velocities from the collocation polynomials."""
        n, d = self.sm.nv, self.col.degree
        qc = np.asarray(q_colloc, dtype=float).reshape(self.N, d, n)
        qall = np.concatenate([np.vstack([x_init[None, :n], qc[:-1, -1]])[:, None], qc], 1)
        vend = np.einsum("jr,kjn->krn", self.col.D, qall)[:, -1] / self.h
        x = np.vstack([x_init, np.hstack([qc[:, -1], vend])])
        return self._join(x, qc.reshape(self.N, d * n))

    def hold_guess(self, x_init: np.ndarray) -> np.ndarray:
        """``q_init`` at every point and node, node velocities ``v_init``."""
        n = self.sm.nv
        x = np.tile(x_init, (self.N + 1, 1))
        return self._join(x, np.tile(x_init[:n], (self.N, self.col.degree)))


__all__ = ["BYTES_PER_VARIABLE", "MAX_BYTES", "TrackingGrid", "check_size"]
