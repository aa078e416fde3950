"""Row ``sim``, MuJoCo: the case's mechanism exported by ``rcm_pin.export.to_mjcf``
(timestep 1 ms, Euler), the same task-space computed-torque law from MuJoCo's own M
(``mj_fullM``; MuJoCo 4.0 API), bias (``qfrc_bias``), site Jacobian and J̇q̇ (``mj_jacSite``,
``mj_jacDot``) between ``mj_step1`` and ``mj_step2``; the efforts through the export's
force-limited motors (the drive limits). The export raises the massless bodies' inertia
to rcm-pin's floor (docs/mujoco.md); Δq shows what that and Euler cost."""

from __future__ import annotations

import warnings
from pathlib import Path
from typing import Any

import mujoco
import numpy as np
from common import accuracy_vs, task_space_ct

import rcm_pin
from rcm_pin.export import to_mjcf


def setup(case: dict[str, Any]) -> dict[str, Any]:
    mech = rcm_pin.load(case["mechanism"], **case["xacro_args"])
    path = Path(case["scratch"]) / f"{case['mechanism']}_peers.xml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the inertia floor (module docstring)
        to_mjcf(mech, path, timestep=case["dt_mujoco"])
    m = mujoco.MjModel.from_xml_path(str(path))
    m.opt.integrator = mujoco.mjtIntegrator.mjINT_EULER
    m.opt.timestep = case["dt_mujoco"]
    qadr = [int(m.jnt_qposadr[mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_JOINT, j)])
            for j in case["joints"]]  # fmt: skip
    act = [mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_ACTUATOR, j) for j in case["joints"]]
    site = mujoco.mj_name2id(m, mujoco.mjtObj.mjOBJ_SITE, case["frame"])
    return {"m": m, "d": mujoco.MjData(m), "qadr": qadr, "act": act, "site": site,
            "case": case}  # fmt: skip


def run_once(state: dict[str, Any]) -> dict[str, Any]:
    m, d, qadr, act, site, case = (state[k] for k in ("m", "d", "qadr", "act", "site", "case"))
    mujoco.mj_resetData(m, d)
    d.qpos[qadr] = case["q0"]
    nv, dt = m.nv, m.opt.timestep
    M, jacp, jdot = np.zeros((nv, nv)), np.zeros((3, nv)), np.zeros((3, nv))
    steps = round(case["duration"] / dt)
    every = round(steps / (case["samples"] - 1))
    mujoco.mj_forward(m, d)
    qs, ps = [d.qpos[qadr].copy()], [d.site_xpos[site].copy()]
    for k in range(1, steps + 1):
        mujoco.mj_step1(m, d)  # positions, velocities, M, bias at d.time
        mujoco.mj_fullM(m, d, M)
        mujoco.mj_jacSite(m, d, jacp, None, site)
        mujoco.mj_jacDot(m, d, jdot, None, d.site_xpos[site], m.site_bodyid[site])
        v = d.qvel.copy()
        qdd = task_space_ct(case, d.time, d.site_xpos[site], jacp, jdot @ v, v)
        d.ctrl[act] = M @ qdd + d.qfrc_bias
        mujoco.mj_step2(m, d)
        if k % every == 0:
            mujoco.mj_kinematics(m, d)
            qs.append(d.qpos[qadr].copy())
            ps.append(d.site_xpos[site].copy())
    return {**accuracy_vs(np.array(qs), case, np.array(ps)), "steps": steps}
