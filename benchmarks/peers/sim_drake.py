"""Row ``sim``, Drake: the same URDF as a continuous MultibodyPlant, the same task-space
computed-torque law (Drake's own M, bias, Jacobian and J̇q̇ on a second context of the
plant: the controller's model), RungeKutta5 with error control at the case's accuracy,
advanced sample by sample to the case's 101 times."""

from __future__ import annotations

from typing import Any

import numpy as np
from common import accuracy_vs, task_space_ct
from pydrake.multibody.parsing import Parser
from pydrake.multibody.plant import MultibodyPlant
from pydrake.multibody.tree import JacobianWrtVariable
from pydrake.systems.analysis import ResetIntegratorFromFlags, Simulator
from pydrake.systems.framework import BasicVector, DiagramBuilder, LeafSystem


class TaskComputedTorque(LeafSystem):
    """τ = M q̈* + C(q, q̇)q̇ − τ_g, clipped to the drive limits (rcm-pin's law)."""

    def __init__(self, plant: MultibodyPlant, case: dict[str, Any]) -> None:
        super().__init__()
        self.plant, self.case = plant, case
        self.ctx = plant.CreateDefaultContext()
        self.frame = plant.GetFrameByName(case["frame"])
        self.world = plant.world_frame()
        self.lim = np.asarray(case["limits"])
        n = plant.num_positions()
        self.DeclareVectorInputPort("x", BasicVector(2 * n))
        self.DeclareVectorOutputPort("tau", BasicVector(n), self.calc)

    def calc(self, context: Any, output: Any) -> None:
        plant, ctx, n = self.plant, self.ctx, self.plant.num_positions()
        x = self.get_input_port(0).Eval(context)
        plant.SetPositionsAndVelocities(ctx, x)
        v = x[n:]
        p = plant.CalcPointsPositions(ctx, self.frame, np.zeros(3), self.world)[:, 0]
        J = plant.CalcJacobianTranslationalVelocity(
            ctx, JacobianWrtVariable.kV, self.frame, np.zeros(3), self.world, self.world
        )
        Jdv = plant.CalcBiasTranslationalAcceleration(
            ctx, JacobianWrtVariable.kV, self.frame, np.zeros(3), self.world, self.world
        )[:, 0]
        qdd = task_space_ct(self.case, context.get_time(), p, J, Jdv, v)
        tau = plant.CalcMassMatrix(ctx) @ qdd + plant.CalcBiasTerm(ctx)
        tau -= plant.CalcGravityGeneralizedForces(ctx)
        output.SetFromVector(np.clip(tau, -self.lim, self.lim))


def setup(case: dict[str, Any]) -> dict[str, Any]:
    builder = DiagramBuilder()
    plant = builder.AddSystem(MultibodyPlant(0.0))
    (model,) = Parser(plant).AddModels(case["urdf"])
    root = plant.get_body(plant.GetBodyIndices(model)[0])  # the URDF's root link, fixed
    plant.WeldFrames(plant.world_frame(), root.body_frame())
    plant.Finalize()
    ctrl = builder.AddSystem(TaskComputedTorque(plant, case))
    builder.Connect(plant.get_state_output_port(), ctrl.get_input_port(0))
    builder.Connect(ctrl.get_output_port(0), plant.get_applied_generalized_force_input_port())
    diagram = builder.Build()
    order = [plant.GetJointByName(j).position_start() for j in case["joints"]]
    return {"diagram": diagram, "plant": plant, "order": order, "case": case}


def run_once(state: dict[str, Any]) -> dict[str, Any]:
    diagram, plant, order, case = state["diagram"], state["plant"], state["order"], state["case"]
    context = diagram.CreateDefaultContext()
    pctx = plant.GetMyMutableContextFromRoot(context)
    n = plant.num_positions()
    x0 = np.zeros(2 * n)
    x0[order] = case["q0"]
    plant.SetPositionsAndVelocities(pctx, x0)
    sim = Simulator(diagram, context)
    integ = ResetIntegratorFromFlags(sim, "runge_kutta5", 0.1)
    integ.set_fixed_step_mode(False)
    integ.set_target_accuracy(case["accuracy_drake"])
    sim.Initialize()
    frame, world = plant.GetFrameByName(case["frame"]), plant.world_frame()
    qs, ps = [], []
    for t in case["t"]:
        sim.AdvanceTo(t)
        q = plant.GetPositions(pctx)
        qs.append(q[order])
        ps.append(plant.CalcPointsPositions(pctx, frame, np.zeros(3), world)[:, 0])
    steps = integ.get_num_steps_taken()
    return {**accuracy_vs(np.array(qs), case, np.array(ps)), "steps": int(steps),
            "derivative_evaluations": int(integ.get_num_derivative_evaluations())}  # fmt: skip
