"""The CasADi twin (ocp.symbolic) against numeric Pinocchio on 10^3 random states.

Models: the mimic test tree (every supported joint kind, armature) and every catalogue
entry (``rcm_pin.names()``: the RCM mechanisms, the cut-open trees of the closed planar
mechanisms, and the example-robot-data arms ur5 and panda through ``rcm_pin.load``).
Numeric mass matrices use
``pin.crba(..., Convention.WORLD)``: with the default (LOCAL) convention Pinocchio 4.1
returns a wrong M on mimic models from the second call on a reused Data.
"""

from __future__ import annotations

from pathlib import Path

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

import rcm_pin
from ocp import SymbolicModel
from ocp.models import model_from_urdf
from rcm_pin.errors import InvalidInputError, UnknownFrameError

N_STATES = 1000
KIN_TOL = 1e-12
DYN_TOL = 1e-10
DATA = Path(__file__).parent / "data"
MODELS = ["mimic_tree", *rcm_pin.names()]


def _load(name: str) -> pin.Model:
    """A fresh model (tests may change its armature)."""
    if name == "mimic_tree":
        model = model_from_urdf(DATA / "mimic_tree.urdf")
        model.armature[:] = np.linspace(0.01, 0.08, model.nv)
        return model
    return pin.Model(rcm_pin.load(name).model)


def test_every_arm_of_the_catalogue_is_covered():
    assert {"panda", "ur5", "rcm_bevel", "planar_3rrr"} <= set(MODELS)


@pytest.fixture(scope="module", params=MODELS)
def states(request):
    """(name, model, SymbolicModel, q, v, a) with N_STATES random states as columns."""
    model = _load(request.param)
    rng = np.random.default_rng(7)
    q = np.column_stack([pin.randomConfiguration(model) for _ in range(N_STATES)])
    v = rng.normal(size=(model.nv, N_STATES))
    a = rng.normal(size=(model.nv, N_STATES))
    return request.param, model, SymbolicModel(model), q, v, a


def _mapped(fun: ca.Function, *args: np.ndarray) -> list[np.ndarray]:
    out = fun.map(args[0].shape[1])(*args)
    return [np.array(o) for o in (out if isinstance(out, tuple) else (out,))]


def test_frames_and_jacobians(states):
    _, model, sm, q, _, _ = states
    data = model.createData()
    frames = range(1, model.nframes)
    num_p = np.empty((len(frames), N_STATES, 3))
    num_r = np.empty((len(frames), N_STATES, 3, 3))
    num_j = np.empty((len(frames), 2, N_STATES, 6, model.nv))
    for k in range(N_STATES):
        pin.computeJointJacobians(model, data, q[:, k])
        pin.updateFramePlacements(model, data)
        for i, fid in enumerate(frames):
            num_p[i, k] = data.oMf[fid].translation
            num_r[i, k] = data.oMf[fid].rotation
            for r, ref in enumerate((pin.LOCAL_WORLD_ALIGNED, pin.LOCAL)):
                num_j[i, r, k] = pin.getFrameJacobian(model, data, fid, ref)
    for i, fid in enumerate(frames):
        p, rot = _mapped(sm.frame_placement(fid), q)
        assert np.abs(p.T - num_p[i]).max() < KIN_TOL
        assert np.abs(rot.reshape(3, N_STATES, 3).transpose(1, 0, 2) - num_r[i]).max() < KIN_TOL
        for r, ref in enumerate(("LOCAL_WORLD_ALIGNED", "LOCAL")):
            (jac,) = _mapped(sm.frame_jacobian(fid, ref), q)
            jac = jac.reshape(6, N_STATES, model.nv).transpose(1, 0, 2)
            assert np.abs(jac - num_j[i, r]).max() < KIN_TOL, (model.frames[fid].name, ref)


def test_dynamics(states):
    _, model, sm, q, v, a = states
    data = model.createData()
    num: dict[str, list[np.ndarray]] = {k: [] for k in ("tau", "M", "g", "b", "fd")}
    for k in range(N_STATES):
        qk, vk, ak = q[:, k], v[:, k], a[:, k]
        tau = pin.rnea(model, data, qk, vk, ak).copy()
        mass = pin.crba(model, data, qk, pin.Convention.WORLD)
        mass = np.triu(mass) + np.triu(mass, 1).T
        b = pin.nonLinearEffects(model, data, qk, vk).copy()
        num["tau"].append(tau)
        num["M"].append(mass)
        num["g"].append(pin.computeGeneralizedGravity(model, data, qk).copy())
        num["b"].append(b)
        num["fd"].append(np.linalg.solve(mass, tau - b))
    ref = {k: np.array(x) for k, x in num.items()}
    (tau,) = _mapped(sm.rnea(), q, v, a)
    (mass,) = _mapped(sm.mass_matrix(), q)
    (grav,) = _mapped(sm.gravity(), q)
    (nle,) = _mapped(sm.nonlinear_effects(), q, v)
    (acc,) = _mapped(sm.forward_dynamics(), q, v, ref["tau"].T)
    assert np.abs(tau.T - ref["tau"]).max() < DYN_TOL
    assert (
        np.abs(mass.reshape(model.nv, N_STATES, model.nv).transpose(1, 0, 2) - ref["M"]).max()
        < DYN_TOL
    )
    assert np.abs(grav.T - ref["g"]).max() < DYN_TOL
    assert np.abs(nle.T - ref["b"]).max() < DYN_TOL
    # Forward dynamics: backward error to DYN_TOL; forward error to DYN_TOL plus what the
    # conditioning of M allows (the RCM wrists give cond(M) ~ 1e7).
    resid = np.einsum("kij,kj->ki", ref["M"], acc.T) - (ref["tau"] - ref["b"])
    assert np.abs(resid).max() < DYN_TOL
    bound = DYN_TOL + 1e-15 * np.linalg.cond(ref["M"]) * np.abs(a).max(0)
    assert (np.abs(acc.T - ref["fd"]).max(1) < bound).all()
    assert (np.abs(acc - a).max(0) < bound).all()  # forward dynamics inverts RNEA


def test_forward_dynamics_matches_aba_without_mimic():
    model = _load("ur5")
    model.armature[:] = 0.05
    data, sm, rng = model.createData(), SymbolicModel(model), np.random.default_rng(3)
    fd = sm.forward_dynamics()
    for _ in range(50):
        q, v, tau = pin.randomConfiguration(model), rng.normal(size=6), rng.normal(size=6)
        assert (
            np.abs(np.array(fd(q, v, tau)).ravel() - pin.aba(model, data, q, v, tau)).max() < 1e-10
        )


def test_integrate_matches_pinocchio_with_continuous_joint():
    model = _load("mimic_tree")
    sm, rng = SymbolicModel(model), np.random.default_rng(5)
    assert sm.continuous
    integrate = sm.integrate()
    for _ in range(20):
        q, dv = pin.randomConfiguration(model), rng.normal(size=model.nv)
        assert (
            np.abs(np.array(integrate(q, dv)).ravel() - pin.integrate(model, q, dv)).max() < 1e-14
        )


def test_mx_twin_equals_sx_twin():
    model = _load("mimic_tree")
    sx, mx = SymbolicModel(model), SymbolicModel(model, sym="MX")
    q = pin.randomConfiguration(model)
    v = np.random.default_rng(0).normal(size=model.nv)
    for name in ("rnea", "mass_matrix", "forward_dynamics"):
        args = {"rnea": (q, v, v), "mass_matrix": (q,), "forward_dynamics": (q, v, v)}[name]
        assert (
            np.abs(
                np.array(getattr(sx, name)()(*args)) - np.array(getattr(mx, name)()(*args))
            ).max()
            < 1e-12
        )
    assert (
        np.abs(
            np.array(sx.frame_jacobian("marker")(q)) - np.array(mx.frame_jacobian("marker")(q))
        ).max()
        < 1e-14
    )


def test_functions_are_named():
    sm = SymbolicModel(_load("mimic_tree"))
    assert sm.rnea().name() == "rnea"
    assert sm.frame_placement("marker").name().startswith("placement_marker")
    assert sm.frame_jacobian("marker", "LOCAL").name().endswith("_local")
    assert sm.frame_placement("marker").name_out() == ["p", "R"]


@pytest.mark.parametrize(
    "joint",
    [
        pin.JointModelFreeFlyer(),
        pin.JointModelSpherical(),
        pin.JointModelHZ(0.1),
        pin.JointModelPlanar(),
        pin.JointModelUniversal(np.array([1.0, 0, 0]), np.array([0, 1.0, 0])),
    ],
)
def test_unsupported_joints_raise(joint):
    model = pin.Model()
    model.addJoint(0, joint, pin.SE3.Identity(), "j")
    with pytest.raises(InvalidInputError, match=r"unsupported|not a revolute"):
        SymbolicModel(model)


def test_bad_arguments_raise():
    sm = SymbolicModel(_load("mimic_tree"))
    with pytest.raises(UnknownFrameError, match="marker"):
        sm.frame_placement("no_such_frame")
    with pytest.raises(InvalidInputError):
        sm.frame_jacobian("marker", "WORLD")  # type: ignore[arg-type]
    with pytest.raises(InvalidInputError):
        SymbolicModel(_load("mimic_tree"), sym="DM")  # type: ignore[arg-type]


def test_pinocchio_backend_is_guarded():
    from ocp.backend_pinocchio import AVAILABLE

    if AVAILABLE:  # pragma: no cover - not with the PyPI wheel
        pytest.skip("pinocchio.casadi present: backend usable")
    with pytest.raises(InvalidInputError, match=r"pinocchio\.casadi"):
        SymbolicModel(_load("mimic_tree"), backend="pinocchio")
