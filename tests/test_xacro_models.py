"""Checks of the parametric xacro models of the RCM mechanism (papers 000/003).

Closed form (docs/conventions.md):
    p = q3 * e4,  e4 = Rx(q1) Ry(q2) z
    R = Rx(q1) Ry(q2) Rz(q4) Ry(q5) Rz(q6)   (zyz, default)
    R = Rx(q1) Ry(q2) Rz(q4) Ry(q5) Rx(q6)   (rpy)
    R = Rx(q1) Ry(q2) Rz(q4)                 (4-DOF)
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yourdfpy

from rcm_pin.mechanisms.rcm import closed_form as cf
from rcm_pin.model.render import render_xacro

ROOT = Path(__file__).resolve().parents[1]
XACRO_DIR = ROOT / "xacro"
URDF_DIR = ROOT / "urdf"
N_SAMPLES = 200
TOL = 1e-12
Q_NAMES = ["pair4", "pair7", "pair24", "pair23", "pair26", "pair27"]

# name -> (xacro file, args, committed urdf or None, wrist kind)
VARIANTS = {
    "bevel": ("rcm_bevel.urdf.xacro", {}, "rcm_bevel.urdf", "zyz"),
    "bevel_4dof": ("rcm_bevel.urdf.xacro", {"wrist": "false"}, "rcm_bevel_4dof.urdf", None),
    "belt": ("rcm_belt.urdf.xacro", {}, "rcm_belt.urdf", "zyz"),
    "bevel_rpy": ("rcm_bevel.urdf.xacro", {"wrist_type": "rpy"}, None, "rpy"),
    "belt_rpy": ("rcm_belt.urdf.xacro", {"wrist_type": "rpy"}, None, "rpy"),
    "belt_4dof": ("rcm_belt.urdf.xacro", {"wrist": "false"}, None, None),
    # non-unit single-stage ratios whose products are still 1 (kinematics unchanged)
    "bevel_ratios": (
        "rcm_bevel.urdf.xacro",
        {
            "z13": "30",
            "z14": "15",
            "z16": "15",
            "z17": "30",
            "z18": "18",
            "z19": "24",
            "z21": "24",
            "z22": "18",
        },
        None,
        "zyz",
    ),
    "bevel_geom": (
        "rcm_bevel.urdf.xacro",
        {"a7_x": "0.13", "a7_z": "-0.04", "l9": "0.27"},
        None,
        "zyz",
    ),
}


def render(xacro_name: str, args: dict[str, str]) -> str:
    return render_xacro(XACRO_DIR / xacro_name, args)


@pytest.fixture(scope="module", params=list(VARIANTS))
def variant(request, tmp_path_factory):
    name = request.param
    xname, args, committed, wrist = VARIANTS[name]
    if committed is not None:
        path = URDF_DIR / committed
    else:
        path = tmp_path_factory.mktemp("urdf") / f"rcm_{name}.urdf"
        path.write_text(render(xname, args))
    return name, path, wrist


def closed_form(q, wrist):
    """Tool position and rotation from rcm_pin.mechanisms.rcm.closed_form (the papers' formulas)."""
    T = cf.tool_pose(np.asarray(q), wrist)
    return T[:3, 3], T[:3, :3]


def random_qs(model, n=N_SAMPLES, seed=0):
    rng = np.random.default_rng(seed)
    lo, hi = model.lowerPositionLimit, model.upperPositionLimit
    assert np.all(np.isfinite(lo)) and np.all(np.isfinite(hi))
    return lo + (hi - lo) * rng.random((n, model.nq))


def test_check_urdf_and_yourdfpy(variant):
    name, path, wrist = variant
    exe = Path(sys.executable).parent / "check_urdf"  # urdfdom's, installed with pin
    r = subprocess.run([str(exe), str(path)], capture_output=True, text=True, check=False)
    assert r.returncode == 0, r.stderr
    u = yourdfpy.URDF.load(str(path))
    ndof = 6 if wrist else 4
    assert len(u.actuated_joint_names) == ndof
    assert {"base", "rcm", "tool", "platform", "working_organ", "holder"} <= set(u.link_map)


def test_pinocchio_dimensions_and_order(variant):
    name, path, wrist = variant
    ndof = 6 if wrist else 4
    m = pin.buildModelFromUrdf(str(path), mimic=True)
    assert (m.nq, m.nv) == (ndof, ndof)
    active = [n for i, n in enumerate(m.names) if i > 0 and m.joints[i].nq > 0]
    assert active == Q_NAMES[:ndof]
    assert [m.idx_qs[m.getJointId(n)] for n in active] == list(range(ndof))
    full = pin.buildModelFromUrdf(str(path), mimic=False)
    u = yourdfpy.URDF.load(str(path))
    n_movable = sum(j.type != "fixed" for j in u.robot.joints)
    assert full.nq == full.nv == full.njoints - 1 == n_movable


def test_tool_pose_closed_form(variant):
    name, path, wrist = variant
    m = pin.buildModelFromUrdf(str(path), mimic=True)
    d = m.createData()
    fid_tool, fid_rcm = m.getFrameId("tool"), m.getFrameId("rcm")
    fid_out = m.getFrameId("output_link")
    l9 = float(yourdfpy.URDF.load(str(path)).joint_map["pair10"].origin[2, 3]) * -1.0
    err_p = err_R = err_line = err_A = 0.0
    for q in random_qs(m):
        pin.framesForwardKinematics(m, d, q)
        p, R = closed_form(q, wrist)
        oMt = d.oMf[fid_tool]
        np.testing.assert_allclose(oMt.translation, p, rtol=0, atol=TOL)
        np.testing.assert_allclose(oMt.rotation, R, rtol=0, atol=TOL)
        err_p = max(err_p, np.abs(oMt.translation - p).max())
        err_R = max(err_R, np.abs(oMt.rotation - R).max())
        # output-link z axis passes through A (the origin), A at (0, 0, l9) in its frame
        oMo = d.oMf[fid_out]
        c, z = oMo.translation, oMo.rotation[:, 2]
        dist = np.linalg.norm(c - (c @ z) * z)
        assert dist < TOL
        err_line = max(err_line, dist)
        np.testing.assert_allclose(oMo.actInv(np.zeros(3)), [0, 0, l9], rtol=0, atol=TOL)
        err_A = max(err_A, np.abs(oMo.actInv(np.zeros(3)) - [0, 0, l9]).max())
        np.testing.assert_allclose(d.oMf[fid_rcm].homogeneous, np.eye(4), rtol=0, atol=0)
    print(
        f"\n{name}: max|dp|={err_p:.2e} max|dR|={err_R:.2e} "
        f"max dist(A, output axis)={err_line:.2e} max|A_out-(0,0,l9)|={err_A:.2e}"
    )


def test_mimic_vs_full_model(variant):
    name, path, wrist = variant
    mm = pin.buildModelFromUrdf(str(path), mimic=True)
    mf = pin.buildModelFromUrdf(str(path), mimic=False)
    dm, df = mm.createData(), mf.createData()
    u = yourdfpy.URDF.load(str(path))
    mimics = {
        j.name: (j.mimic.joint, j.mimic.multiplier, j.mimic.offset)
        for j in u.robot.joints
        if j.mimic is not None
    }
    assert all(prim == "pair7" for prim, _, _ in mimics.values())
    err = 0.0
    for q in random_qs(mm, seed=1):
        qf = np.zeros(mf.nq)
        for jid in range(1, mf.njoints):
            jn = mf.names[jid]
            if jn in mimics:
                prim, mult, off = mimics[jn]
                val = mult * q[mm.idx_qs[mm.getJointId(prim)]] + off
            else:
                val = q[mm.idx_qs[mm.getJointId(jn)]]
            qf[mf.idx_qs[jid]] = val
        pin.framesForwardKinematics(mm, dm, q)
        pin.framesForwardKinematics(mf, df, qf)
        # every frame (links, joints, fixed parts) at the same placement
        for fid in range(1, mf.nframes):
            fr = mf.frames[fid]
            fid_m = mm.getFrameId(fr.name, fr.type)
            np.testing.assert_allclose(
                dm.oMf[fid_m].homogeneous, df.oMf[fid].homogeneous, rtol=0, atol=TOL
            )
            err = max(err, np.abs(dm.oMf[fid_m].homogeneous - df.oMf[fid].homogeneous).max())
    print(f"\n{name}: mimic vs full, max frame difference {err:.2e}")


def test_default_masses():
    for committed in ("rcm_bevel.urdf", "rcm_belt.urdf"):
        u = yourdfpy.URDF.load(str(URDF_DIR / committed))
        mass = {
            n: (l.inertial.mass if l.inertial is not None else 0.0) for n, l in u.link_map.items()
        }
        m_d = mass["intermediate_link"] + mass["initial_link"] / 3 + mass["output_link"] / 3
        np.testing.assert_allclose(m_d, 0.2, rtol=0, atol=1e-15)
        m_tool_side = sum(mass[n] for n in ("working_organ", "holder", "wrist_link", "tool_link"))
        np.testing.assert_allclose(m_tool_side, 0.4, rtol=0, atol=1e-15)
        np.testing.assert_allclose(mass["platform"], 0.3)
        for n, l in u.link_map.items():  # physically valid inertias
            if l.inertial is not None and l.inertial.mass > 0:
                ev = np.linalg.eigvalsh(l.inertial.inertia)
                assert ev.min() > 0 and 2 * ev.max() <= ev.sum() + 1e-15, n


def test_multipliers_from_tooth_counts_and_diameters(tmp_path):
    z = {"z13": 30, "z14": 15, "z16": 16, "z17": 40, "z18": 18, "z19": 24, "z21": 25, "z22": 18}
    path = tmp_path / "b.urdf"
    path.write_text(render("rcm_bevel.urdf.xacro", {k: str(v) for k, v in z.items()}))
    mult = {
        j.name: j.mimic.multiplier for j in yourdfpy.URDF.load(str(path)).robot.joints if j.mimic
    }
    k1 = (30 / 15) * (16 / 40)  # train 2 is driven by link 9 turning k1*q2 relative to link 11
    expected = {
        "pair10": -k1,
        "pair12": (18 / 24) * (25 / 18) * k1,
        "shaft15": -(30 / 15),
        "shaft20": 18 / 24 * k1,
    }
    assert mult.keys() == expected.keys()
    for k, v in expected.items():
        np.testing.assert_allclose(mult[k], v, rtol=1e-15)
    path.write_text(
        render("rcm_belt.urdf.xacro", {"d1": "0.03", "d2": "0.02", "d3": "0.025", "d4": "0.02"})
    )
    mult = {
        j.name: j.mimic.multiplier for j in yourdfpy.URDF.load(str(path)).robot.joints if j.mimic
    }
    expected = {
        "pair10": -1.5,
        "pair12": 1.25 * 1.5,
        "pulley_7": -1.0,
        "pulley_10a": -1.5,
        "pulley_10b": 1.5,
        "pulley_12": 1.25 * 1.5,
    }
    for k, v in expected.items():
        np.testing.assert_allclose(mult[k], v, rtol=1e-15)


def test_mimic_dynamics_consistent(variant):
    """Pinocchio's mimic model: M = G^T M_full G and rnea = G^T rnea_full (G: q -> q_full)."""
    name, path, wrist = variant
    mm = pin.buildModelFromUrdf(str(path), mimic=True)
    mf = pin.buildModelFromUrdf(str(path), mimic=False)
    u = yourdfpy.URDF.load(str(path))
    mim = {j.name: j.mimic.multiplier for j in u.robot.joints if j.mimic is not None}
    G = np.zeros((mf.nv, mm.nv))
    for jid in range(1, mf.njoints):
        n = mf.names[jid]
        G[mf.idx_vs[jid], mm.idx_vs[mm.getJointId("pair7" if n in mim else n)]] = mim.get(n, 1.0)
    rng = np.random.default_rng(2)
    for q in random_qs(mm, n=20, seed=2):
        v, a = rng.standard_normal(mm.nv), rng.standard_normal(mm.nv)
        Mm = pin.crba(mm, mm.createData(), q)
        Mf = pin.crba(mf, mf.createData(), G @ q)
        Mm, Mf = np.triu(Mm) + np.triu(Mm, 1).T, np.triu(Mf) + np.triu(Mf, 1).T
        np.testing.assert_allclose(Mm, G.T @ Mf @ G, rtol=0, atol=1e-12)
        tm = pin.rnea(mm, mm.createData(), q, v, a)
        tf = pin.rnea(mf, mf.createData(), G @ q, G @ v, G @ a)
        np.testing.assert_allclose(tm, G.T @ tf, rtol=0, atol=1e-12)
