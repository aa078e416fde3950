"""Generic algorithms on any Mechanism (serial or closed); never a mechanism's name.

Position problems (:mod:`.position`, numeric routes :mod:`.closed_position`,
:mod:`.serial_ik`, the proven reach bound :mod:`.reach`), kinematics (:mod:`.kinematics`,
:mod:`.jacobians`), velocity (:mod:`.velocity`, :mod:`.loop_velocity`), singularities
(:mod:`.singularity`, :mod:`.closed_singularity`, :mod:`.screws`, :mod:`.maps`,
:mod:`.singularity_report`), workspace (:mod:`.workspace`), accuracy (:mod:`.accuracy`),
mobility (:mod:`.mobility`), the vectorised planar Newton (:mod:`.batch_planar`) and
whether the joint axes pass through the bodies they join (:mod:`.axis_visuals`).

The re-exports below are the public API of the layer (``docs/api.md``), imported on first
access: ``import rcm_pin`` loads no scipy or matplotlib.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from rcm_pin.lazy import lazy_exports

if TYPE_CHECKING:
    from rcm_pin.analysis.accuracy import (
        AccuracyModel,
        AccuracyReport,
        AccuracyRow,
        PlacementAccuracy,
        accuracy_model,
        sensitivities,
    )
    from rcm_pin.analysis.axis_visuals import AxisMiss, axis_misses
    from rcm_pin.analysis.capabilities import (
        Assemblies,
        Branches,
        DefaultPoses,
        NumericPosition,
        PositionSolver,
        ReferencePoses,
        position_solver,
        reference_poses,
    )
    from rcm_pin.analysis.closed_position import (
        direct_position_multistart,
        direct_position_path,
    )
    from rcm_pin.analysis.closed_singularity import (
        configuration_report,
        drive_singularities,
        pose_singularities,
    )
    from rcm_pin.analysis.jacobians import (
        jacobian_derivative,
        tool_jacobian,
    )
    from rcm_pin.analysis.kinematics import (
        frame_pose,
        rcm_error,
        tool_pose,
        tool_poses,
    )
    from rcm_pin.analysis.loop_velocity import (
        Classification,
        VelocityMatrices,
        classify,
        closure_jacobian,
        passive_velocity,
        velocity_matrices,
    )
    from rcm_pin.analysis.maps import (
        plot_singularity_map,
        singularity_map,
    )
    from rcm_pin.analysis.mobility import (
        MobilityCount,
    )
    from rcm_pin.analysis.position import (
        PositionResult,
        PositionSolution,
        forward,
        inverse,
    )
    from rcm_pin.analysis.reach import reach_bound
    from rcm_pin.analysis.screws import (
        ScrewTest,
        screw_test,
    )
    from rcm_pin.analysis.singularity import (
        JacobianAnalysis,
        analyse,
        analyse_jacobian,
    )
    from rcm_pin.analysis.singularity import (
        causes as singularity_causes,
    )
    from rcm_pin.analysis.singularity import (
        grid as singularity_grid,
    )
    from rcm_pin.analysis.singularity import (
        measure as singularity_measure,
    )
    from rcm_pin.analysis.singularity_model import (
        ABMatrices,
        Cause,
        DetMap,
        NumericSingularity,
        SingularityModel,
    )
    from rcm_pin.analysis.singularity_model import (
        singularity_model as singularity_model_of,
    )
    from rcm_pin.analysis.velocity import (
        ToolMotion,
        inverse_acceleration,
        inverse_velocity,
    )
    from rcm_pin.analysis.velocity import (
        forward as forward_velocity,
    )
    from rcm_pin.analysis.workspace import (
        NumericWorkspace,
        WorkspaceModel,
        output_points,
        sample_joints,
        volume_voxels,
        workspace_model,
    )
    from rcm_pin.analysis.workspace import (
        plot as plot_workspace,
    )
    from rcm_pin.analysis.workspace import (
        summary as workspace_summary,
    )

#: public name -> submodule (or ``submodule:attribute`` where the name differs)
_LAZY = {
    "ABMatrices": "singularity_model",
    "AccuracyModel": "accuracy",
    "AccuracyReport": "accuracy",
    "AccuracyRow": "accuracy",
    "Assemblies": "capabilities",
    "AxisMiss": "axis_visuals",
    "Branches": "capabilities",
    "Cause": "singularity_model",
    "Classification": "loop_velocity",
    "DefaultPoses": "capabilities",
    "DetMap": "singularity_model",
    "JacobianAnalysis": "singularity",
    "MobilityCount": "mobility",
    "NumericPosition": "capabilities",
    "NumericSingularity": "singularity_model",
    "NumericWorkspace": "workspace",
    "PlacementAccuracy": "accuracy",
    "PositionResult": "position",
    "PositionSolution": "position",
    "PositionSolver": "capabilities",
    "ReferencePoses": "capabilities",
    "ScrewTest": "screws",
    "SingularityModel": "singularity_model",
    "ToolMotion": "velocity",
    "VelocityMatrices": "loop_velocity",
    "WorkspaceModel": "workspace",
    "accuracy_model": "accuracy",
    "analyse": "singularity",
    "analyse_jacobian": "singularity",
    "axis_misses": "axis_visuals",
    "classify": "loop_velocity",
    "closure_jacobian": "loop_velocity",
    "configuration_report": "closed_singularity",
    "direct_position_multistart": "closed_position",
    "direct_position_path": "closed_position",
    "drive_singularities": "closed_singularity",
    "forward": "position",
    "forward_velocity": "velocity:forward",
    "frame_pose": "kinematics",
    "inverse": "position",
    "inverse_acceleration": "velocity",
    "inverse_velocity": "velocity",
    "jacobian_derivative": "jacobians",
    "output_points": "workspace",
    "passive_velocity": "loop_velocity",
    "plot_singularity_map": "maps",
    "plot_workspace": "workspace:plot",
    "pose_singularities": "closed_singularity",
    "position_solver": "capabilities",
    "rcm_error": "kinematics",
    "reach_bound": "reach",
    "reference_poses": "capabilities",
    "sample_joints": "workspace",
    "screw_test": "screws",
    "sensitivities": "accuracy",
    "singularity_causes": "singularity:causes",
    "singularity_grid": "singularity:grid",
    "singularity_map": "maps",
    "singularity_measure": "singularity:measure",
    "singularity_model_of": "singularity_model:singularity_model",
    "tool_jacobian": "jacobians",
    "tool_pose": "kinematics",
    "tool_poses": "kinematics",
    "velocity_matrices": "loop_velocity",
    "volume_voxels": "workspace",
    "workspace_model": "workspace",
    "workspace_summary": "workspace:summary",
}

# No re-export is named like a submodule (it would hide the module): ``mobility`` is
# ``rcm_pin.mobility``; the singularity resolver ``singularity_model`` is public as
# ``singularity_model_of`` (the family's SingularityModel of a mechanism).
__getattr__, __dir__ = lazy_exports(__name__, _LAZY)

__all__ = [
    "ABMatrices",
    "AccuracyModel",
    "AccuracyReport",
    "AccuracyRow",
    "Assemblies",
    "AxisMiss",
    "Branches",
    "Cause",
    "Classification",
    "DefaultPoses",
    "DetMap",
    "JacobianAnalysis",
    "MobilityCount",
    "NumericPosition",
    "NumericSingularity",
    "NumericWorkspace",
    "PlacementAccuracy",
    "PositionResult",
    "PositionSolution",
    "PositionSolver",
    "ReferencePoses",
    "ScrewTest",
    "SingularityModel",
    "ToolMotion",
    "VelocityMatrices",
    "WorkspaceModel",
    "accuracy_model",
    "analyse",
    "analyse_jacobian",
    "axis_misses",
    "classify",
    "closure_jacobian",
    "configuration_report",
    "direct_position_multistart",
    "direct_position_path",
    "drive_singularities",
    "forward",
    "forward_velocity",
    "frame_pose",
    "inverse",
    "inverse_acceleration",
    "inverse_velocity",
    "jacobian_derivative",
    "output_points",
    "passive_velocity",
    "plot_singularity_map",
    "plot_workspace",
    "pose_singularities",
    "position_solver",
    "rcm_error",
    "reach_bound",
    "reference_poses",
    "sample_joints",
    "screw_test",
    "sensitivities",
    "singularity_causes",
    "singularity_grid",
    "singularity_map",
    "singularity_measure",
    "singularity_model_of",
    "tool_jacobian",
    "tool_pose",
    "tool_poses",
    "velocity_matrices",
    "volume_voxels",
    "workspace_model",
    "workspace_summary",
]
