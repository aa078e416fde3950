"""``SymbolicModel``: the CasADi twin of a ``pin.Model``, as named ``casadi.Function`` s.

Built from the model's joint placements, joint axes, mimic couplings and inertias
(:mod:`ocp.joints`), so the one ``pin.Model`` stays the single source of truth. Every
function is built on first use and cached:

========================  =========================  =====================================
name                      inputs -> outputs          meaning
========================  =========================  =====================================
``placement_<frame>``     q -> p (3), R (3x3)        frame pose in the world
``jacobian_<frame>``      q -> J (6 x nv)            LOCAL_WORLD_ALIGNED (``_local``: LOCAL)
``rnea``                  q, v, a -> tau             inverse dynamics (gravity, armature)
``mass_matrix``           q -> M                     joint-space inertia (symmetric)
``gravity``               q -> g                     ``rnea(q, 0, 0)``
``nonlinear_effects``     q, v -> b                  ``rnea(q, v, 0)``
``forward_dynamics``      q, v, tau -> a             ``M^{-1} (tau - b)`` (Cholesky)
``integrate``             q, dv -> q'                ``q (+) dv`` (continuous joints rotate)
========================  =========================  =====================================

``jit=True`` compiles each function with the system C compiler (CasADi ``jit``, compiler
``shell``); ``benchmarks/bench_ocp.py`` measures when that pays off. ``backend="pinocchio"``
would use Pinocchio's own CasADi bindings (``pinocchio.casadi``) behind the same
interface; the PyPI ``pin`` wheel does not ship them, so that backend raises
:class:`~rcm_pin.errors.InvalidInputError` here (see :mod:`ocp.backend_pinocchio`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, Literal

import casadi as ca
import numpy as np
import pinocchio as pin

from ocp import dynamics, kinematics
from ocp.joints import FrameSpec, coupling_matrix, frame_specs, joint_specs
from rcm_pin.errors import InvalidInputError, UnknownFrameError

Reference = Literal["LOCAL_WORLD_ALIGNED", "LOCAL"]
#: Options of every JIT-compiled function (system C compiler through CasADi's "shell"
#: plugin). -O1: on the large OCP stage functions it runs as fast as -O2 and compiles
#: about 1.5x faster.
JIT_OPTIONS: dict[str, Any] = {
    "jit": True,
    "compiler": "shell",
    "jit_cleanup": True,
    "jit_options": {"flags": ["-O1"], "verbose": False},
}


class SymbolicModel:
    """Named CasADi functions of one Pinocchio model (revolute, prismatic, continuous and
    mimic joints; fixed frames). ``q`` has ``nq`` entries (continuous joints: cos, sin)."""

    def __init__(
        self,
        model: pin.Model,
        *,
        sym: Literal["SX", "MX"] = "SX",
        jit: bool = False,
        backend: Literal["native", "pinocchio"] = "native",
    ) -> None:
        if sym not in ("SX", "MX"):
            raise InvalidInputError(f"sym must be 'SX' or 'MX', got {sym!r}")
        if backend not in ("native", "pinocchio"):
            raise InvalidInputError(f"backend must be 'native' or 'pinocchio', got {backend!r}")
        self.model = model
        self.joints = joint_specs(model)
        self.frames: tuple[FrameSpec, ...] = frame_specs(model)
        self.nq, self.nv = int(model.nq), int(model.nv)
        self.coupling = coupling_matrix(model, self.joints)
        self.sym, self.jit, self.backend = sym, jit, backend
        self._sym_type: Any = ca.SX if sym == "SX" else ca.MX
        self._cache: dict[str, ca.Function] = {}
        self._gravity = np.array(model.gravity.linear)
        self._armature = np.array(model.armature, dtype=float).reshape(-1)
        if backend == "pinocchio":
            from ocp.backend_pinocchio import PinocchioCasadiBackend

            self._pin_backend = PinocchioCasadiBackend(model, sym)

    # -- bookkeeping ---------------------------------------------------------------------
    @property
    def continuous(self) -> bool:
        """True when some joint is continuous (q is not a vector space: use ``integrate``)."""
        return any(j.kind == "revolute_unbounded" and not j.mimic for j in self.joints)

    def frame_id(self, frame: str | int) -> int:
        """Pinocchio frame index of ``frame`` (name or index)."""
        if isinstance(frame, (int, np.integer)):
            if not 0 <= int(frame) < len(self.frames):
                raise UnknownFrameError(f"frame index {frame} outside 0..{len(self.frames) - 1}")
            return int(frame)
        if not self.model.existFrame(frame):
            names = sorted({f.name for f in self.frames})
            raise UnknownFrameError(f"no frame {frame!r}; frames: {', '.join(names)}")
        return int(self.model.getFrameId(frame))

    def _symbols(self) -> tuple[Any, Any, Any]:
        st = self._sym_type
        return st.sym("q", self.nq), st.sym("v", self.nv), st.sym("a", self.nv)

    def _function(self, name: str, build: Callable[[], ca.Function]) -> ca.Function:
        if name not in self._cache:
            self._cache[name] = build()
        return self._cache[name]

    def _make(
        self,
        name: str,
        inputs: list[Any],
        outputs: list[Any],
        in_names: list[str],
        out_names: list[str],
    ) -> ca.Function:
        opts: dict[str, Any] = dict(JIT_OPTIONS) if self.jit else {}
        return ca.Function(name, inputs, outputs, in_names, out_names, opts)

    # -- kinematics ----------------------------------------------------------------------
    def _safe(self, frame: str | int) -> str:
        fid = self.frame_id(frame)
        return "".join(ch if ch.isalnum() else "_" for ch in self.frames[fid].name) + f"_{fid}"

    def frame_placement(self, frame: str | int) -> ca.Function:
        """``placement_<frame>(q) -> (p, R)``: position and rotation of ``frame``."""
        fid = self.frame_id(frame)

        def build() -> ca.Function:
            q = self._symbols()[0]
            if self.backend == "pinocchio":
                p, r = self._pin_backend.placement(q, fid)
            else:
                oMi = kinematics.world_placements(self.joints, q)
                r, p = kinematics.frame_placement(self.frames[fid], oMi)
            return self._make(f"placement_{self._safe(fid)}", [q], [p, r], ["q"], ["p", "R"])

        return self._function(f"placement_{fid}", build)

    def frame_jacobian(
        self, frame: str | int, reference: Reference = "LOCAL_WORLD_ALIGNED"
    ) -> ca.Function:
        """``jacobian_<frame>[_local](q) -> J`` (6 x nv; rows linear then angular)."""
        if reference not in ("LOCAL_WORLD_ALIGNED", "LOCAL"):
            raise InvalidInputError(
                f"reference must be 'LOCAL_WORLD_ALIGNED' or 'LOCAL', got {reference!r}"
            )
        fid = self.frame_id(frame)
        suffix = "_local" if reference == "LOCAL" else ""

        def build() -> ca.Function:
            q = self._symbols()[0]
            if self.backend == "pinocchio":
                jac = self._pin_backend.jacobian(q, fid, reference)
            else:
                oMi = kinematics.world_placements(self.joints, q)
                r, p = kinematics.frame_placement(self.frames[fid], oMi)
                jac = kinematics.frame_jacobian_world(
                    self.joints, self.frames[fid], self.nv, oMi, p
                )
                if reference == "LOCAL":
                    jac = kinematics.to_local(jac, r)
            return self._make(f"jacobian_{self._safe(fid)}{suffix}", [q], [jac], ["q"], ["J"])

        return self._function(f"jacobian_{fid}{suffix}", build)

    def integrate(self) -> ca.Function:
        """``integrate(q, dv) -> q (+) dv`` (continuous joints: rotate the (cos, sin) pair)."""

        def build() -> ca.Function:
            q, dv, _ = self._symbols()
            parts = [q[i] for i in range(self.nq)]
            for j in self.joints:
                if j.mimic:
                    continue
                if j.kind == "revolute_unbounded":
                    c, s, d = q[j.idx_q], q[j.idx_q + 1], dv[j.idx_v]
                    parts[j.idx_q] = c * ca.cos(d) - s * ca.sin(d)
                    parts[j.idx_q + 1] = s * ca.cos(d) + c * ca.sin(d)
                else:
                    parts[j.idx_q] = q[j.idx_q] + dv[j.idx_v]
            out = ca.vertcat(*parts) if parts else q
            return self._make("integrate", [q, dv], [out], ["q", "dv"], ["q_next"])

        return self._function("integrate", build)

    # -- dynamics ------------------------------------------------------------------------
    def _rnea_expr(self, q: Any, v: Any, a: Any, gravity: bool = True) -> Any:
        g = self._gravity if gravity else np.zeros(3)
        if self.backend == "pinocchio":
            return self._pin_backend.rnea(q, v, a, g)
        return dynamics.rnea(self.joints, self._armature, g, q, v, a)

    def rnea(self) -> ca.Function:
        """``rnea(q, v, a) -> tau``: inverse dynamics, as ``pin.rnea``."""

        def build() -> ca.Function:
            q, v, a = self._symbols()
            return self._make(
                "rnea", [q, v, a], [self._rnea_expr(q, v, a)], ["q", "v", "a"], ["tau"]
            )

        return self._function("rnea", build)

    def _mass_expr(self, q: Any) -> Any:
        if self.backend == "pinocchio":
            return self._pin_backend.crba(q)
        return dynamics.crba(self.joints, self._armature, q, self.nv)

    def mass_matrix(self) -> ca.Function:
        """``mass_matrix(q) -> M``: symmetric joint-space inertia, as ``pin.crba``."""

        def build() -> ca.Function:
            q = self._symbols()[0]
            return self._make("mass_matrix", [q], [self._mass_expr(q)], ["q"], ["M"])

        return self._function("mass_matrix", build)

    def gravity(self) -> ca.Function:
        """``gravity(q) -> g = rnea(q, 0, 0)``."""

        def build() -> ca.Function:
            q = self._symbols()[0]
            z = ca.DM.zeros(self.nv, 1)
            return self._make("gravity", [q], [self._rnea_expr(q, z, z)], ["q"], ["g"])

        return self._function("gravity", build)

    def nonlinear_effects(self) -> ca.Function:
        """``nonlinear_effects(q, v) -> b = rnea(q, v, 0)``."""

        def build() -> ca.Function:
            q, v, _ = self._symbols()
            z = ca.DM.zeros(self.nv, 1)
            return self._make(
                "nonlinear_effects", [q, v], [self._rnea_expr(q, v, z)], ["q", "v"], ["b"]
            )

        return self._function("nonlinear_effects", build)

    def forward_dynamics(self) -> ca.Function:
        """``forward_dynamics(q, v, tau) -> a``: solves ``M a = tau - b`` (Cholesky)."""

        def build() -> ca.Function:
            q, v, tau = self._symbols()
            tau = self._sym_type.sym("tau", self.nv)
            z = ca.DM.zeros(self.nv, 1)
            rhs = tau - self._rnea_expr(q, v, z)
            acc = dynamics.cholesky_solve(self._mass_expr(q), rhs)
            return self._make("forward_dynamics", [q, v, tau], [acc], ["q", "v", "tau"], ["a"])

        return self._function("forward_dynamics", build)


__all__ = ["JIT_OPTIONS", "Reference", "SymbolicModel"]
