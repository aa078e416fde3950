"""Loading closed mechanisms: xacro -> URDF tree + loop spec -> :class:`ClosedMechanism`.

Two entry points give the same object:

* :func:`load_closed` renders ``xacro/<name>.urdf.xacro`` with the given arguments and reads
  the closures from the rendered ``<rcm_pin_loops>`` element;
* :func:`from_urdf_and_sidecar` reads a URDF file and its LAAS-format YAML sidecar (what any
  other tool would do with ``urdf/<name>.urdf`` + ``urdf/<name>.yaml``).

:func:`write_rendered` / :func:`check_rendered` keep the committed ``urdf/`` files in sync.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin

from rcm_pin.closed_loop.core import _ROWS, ClosedMechanism, Closure
from rcm_pin.closed_loop.sidecar import LoopSpec, spec_from_urdf, spec_from_yaml, to_yaml
from rcm_pin.errors import InvalidInputError, UnknownFrameError, UnknownMechanismError
from rcm_pin.render import URDF_DIR, XACRO_DIR, render_xacro

#: Closed mechanisms shipped with rcm-pin.
CLOSED_MECHANISMS = ("planar_3rrr", "five_bar")


def _xacro_path(name: str) -> Path:
    if name not in CLOSED_MECHANISMS:
        raise UnknownMechanismError(
            f"unknown closed mechanism {name!r}; valid: {', '.join(CLOSED_MECHANISMS)}"
        )
    return XACRO_DIR / f"{name}.urdf.xacro"


def render_closed(name: str, **xacro_args: object) -> tuple[str, str]:
    """URDF text and YAML sidecar text of a shipped closed mechanism.

    Raises:
        UnknownMechanismError: name not in :data:`CLOSED_MECHANISMS`.
        XacroArgumentError: unknown or malformed xacro argument.
    """
    urdf = render_xacro(_xacro_path(name), xacro_args)
    return urdf, to_yaml(spec_from_urdf(urdf))


def load_closed(name: str, **xacro_args: object) -> ClosedMechanism:
    """Load ``planar_3rrr`` or ``five_bar`` with xacro arguments.

    Args:
        name: ``"planar_3rrr"`` or ``"five_bar"``.
        **xacro_args: overrides of the xacro arguments (lengths [m], angles [deg], masses [kg]).

    Returns:
        The closed mechanism.

    Raises:
        UnknownMechanismError: unknown name.
        XacroArgumentError: bad xacro argument (unknown, non-numeric, or non-positive length).
    """
    from rcm_pin.errors import XacroArgumentError

    for key, value in xacro_args.items():
        if key.startswith(
            ("proximal", "distal", "base_radius", "platform_radius", "base_distance")
        ):
            try:
                ok = float(value) > 0.0  # type: ignore[arg-type]
            except (TypeError, ValueError):
                ok = True  # left to render_xacro's message
            if not ok:
                raise XacroArgumentError(
                    f"xacro argument {key}={value!r} must be a positive length [m]"
                )
    urdf, _ = render_closed(name, **xacro_args)
    return build(name, urdf, spec_from_urdf(urdf))


def from_urdf_and_sidecar(
    urdf_path: str | Path, yaml_path: str | Path | None = None, name: str | None = None
) -> ClosedMechanism:
    """Load a cut-open URDF and its LAAS YAML sidecar (default: same stem, ``.yaml``)."""
    urdf_path = Path(urdf_path)
    yaml_path = Path(yaml_path) if yaml_path else urdf_path.with_suffix(".yaml")
    spec = spec_from_yaml(yaml_path.read_text())
    return build(name or urdf_path.stem, urdf_path.read_text(), spec)


def build(name: str, urdf: str, spec: LoopSpec) -> ClosedMechanism:
    """Build the :class:`ClosedMechanism` from URDF text and a loop spec.

    Each closure pair becomes ``pin.RigidConstraintModel(CONTACT_3D | CONTACT_6D, model,
    parent_joint(a), placement(a), parent_joint(b), placement(b), LOCAL)``.

    Raises:
        UnknownFrameError: a closure frame or drive that the model does not have.
        InvalidInputError: a planar spec whose joints do not all turn about the plane normal.
    """
    model = pin.buildModelFromXML(urdf)
    planar = spec.plane_normal is not None
    if planar:
        normal = np.asarray(spec.plane_normal, dtype=float)
        data = model.createData()
        pin.computeJointJacobians(model, data, pin.neutral(model))
        for jid in range(1, model.njoints):
            col = model.joints[jid].idx_v
            axis = pin.getJointJacobian(model, data, jid, pin.WORLD)[3:, col]
            if model.joints[jid].nq != 1 or abs(abs(axis @ normal) - 1.0) > 1e-12:
                raise InvalidInputError(
                    f"{name}: joint {model.names[jid]} does not turn about the plane normal "
                    f"{normal.tolist()}; a planar closure needs revolute joints about it"
                )
    closures = []
    cmodels = pin.StdVec_RigidConstraintModel()
    cdatas = pin.StdVec_RigidConstraintData()
    for (fa, fb), kind in zip(spec.closed_loop, spec.types, strict=True):
        frames = []
        for fname in (fa, fb):
            if not model.existFrame(fname):
                raise UnknownFrameError(f"closure frame {fname!r} is not in {name}")
            frames.append(model.frames[model.getFrameId(fname)])
        ctype = pin.ContactType.CONTACT_3D if kind == "3d" else pin.ContactType.CONTACT_6D
        cm = pin.RigidConstraintModel(
            ctype,
            model,
            frames[0].parentJoint,
            frames[0].placement,
            frames[1].parentJoint,
            frames[1].placement,
            pin.ReferenceFrame.LOCAL,
        )
        cm.name = f"{fa}__{fb}"
        cmodels.append(cm)
        cdatas.append(cm.createData())
        closures.append(Closure(fa, fb, kind, _ROWS[(kind, planar)], cm))
    driven = tuple(spec.actuated)
    passive = tuple(n for n in model.names[1:] if n not in driven)
    lengths = [v for k, v in spec.params.items() if k.startswith(("proximal", "distal"))]
    return ClosedMechanism(
        name=name,
        model=model,
        data=model.createData(),
        closures=tuple(closures),
        constraint_models=cmodels,
        constraint_datas=cdatas,
        driven=driven,
        passive=passive,
        extra_drives=tuple(spec.extra_actuated),
        output_frame=spec.output_frame,
        output_coords=tuple(spec.output_coords),
        legs=tuple(spec.legs),
        params=dict(spec.params),
        plane_normal=spec.plane_normal,
        length_scale=float(np.mean(lengths)) if lengths else 1.0,
    )


def write_rendered() -> list[Path]:
    """Render the default URDF and YAML sidecar of every closed mechanism into ``urdf/``."""
    written = []
    for name in CLOSED_MECHANISMS:
        urdf, sidecar = render_closed(name)
        for path, text in ((URDF_DIR / f"{name}.urdf", urdf), (URDF_DIR / f"{name}.yaml", sidecar)):
            path.write_text(text)
            written.append(path)
    return written


def check_rendered() -> list[str]:
    """Committed files in ``urdf/`` that differ from a fresh default render."""
    stale = []
    for name in CLOSED_MECHANISMS:
        urdf, sidecar = render_closed(name)
        for path, text in ((URDF_DIR / f"{name}.urdf", urdf), (URDF_DIR / f"{name}.yaml", sidecar)):
            if not path.exists() or path.read_text() != text:
                stale.append(path.name)
    return stale
