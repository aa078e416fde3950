"""``rcm_pin.load``: a catalogue name or a file path to a :class:`Mechanism`.

Names and paths never mix: a catalogue name always means the catalogue entry (a file or
folder of that name in the working directory is ignored); a path is anything with a path
separator or a ``.urdf`` / ``.xacro`` suffix (or a :class:`pathlib.Path`). A bare word that
is no catalogue name raises :class:`~rcm_pin.errors.UnknownMechanismError` with the valid
names.

A path's tool frame comes from the ``tool_frame`` argument, else the file's ``<rcm_pin>``
element, else its YAML sidecar (same stem, ``.yaml``); otherwise loading fails with the
candidate frames listed, never a guess. The remote centre likewise: ``rcm_frame`` (the
frame at the point A), ``rcm_axis_frame`` and ``rcm_axis`` (the shaft line: that axis of
that frame, default the tool frame's z; set it to the shaft for an instrument with a
wrist), else the ``<rcm_pin>`` element's attributes of the same names.

ROS packages (``$(find pkg)``, ``package://pkg/...``) are found as
:mod:`rcm_pin.model.packages` says, first in ``package_dirs``; mesh files must lie where
the description lives or in ``mesh_dirs`` (:mod:`rcm_pin.model.meshes`).

A closed mechanism's output frame (``output_frame``,
the same as ``tool_frame``, and ``output_coords``) is optional: a LAAS sidecar names none
(:mod:`rcm_pin.model.output_choice`).
"""

from __future__ import annotations

from collections.abc import Iterable
from pathlib import Path
from typing import Any

from rcm_pin.catalog.options import LoadOptions
from rcm_pin.catalog.table import CatalogEntry, family_named, get_entry
from rcm_pin.errors import InvalidInputError, UnknownMechanismError, XacroArgumentError
from rcm_pin.model.build import build_mechanism, is_path_like
from rcm_pin.model.laas_joints import replace_joints
from rcm_pin.model.mechanism import Mechanism
from rcm_pin.model.meshes import resolve_meshes
from rcm_pin.model.output_choice import parse_coords
from rcm_pin.model.packages import PackageSearch
from rcm_pin.model.render import render_xacro, validate_args
from rcm_pin.model.sidecar import Description, description_from_yaml, read_description


def load(
    name_or_path: str | Path,
    *,
    tool_frame: str | None = None,
    rcm_frame: str | None = None,
    rcm_axis_frame: str | None = None,
    rcm_axis: str | None = None,
    # Any, not Mapping[str, str | Path] | None: callers pass **xacro_args of str values
    package_dirs: Any = None,
    mesh_dirs: Iterable[str | Path] = (),
    trusted: bool = False,
    output_frame: str | None = None,
    output_coords: str | tuple[str, ...] | None = None,
    **xacro_args: Any,
) -> Mechanism:
    """Load a shipped mechanism by name, or any URDF / xacro file by path.

    A xacro file loaded by path is data, not code: its expressions must pass the
    allow-list of :mod:`rcm_pin.model.xacro_safety` unless ``trusted`` (the catalogue's
    own xacros are trusted).

    Args:
        name_or_path: a name from :func:`rcm_pin.names` (``rcm_bevel``, ``planar_3rrr``,
            ``panda``, ...) or a path to a ``.urdf`` / ``.xacro`` file.
        tool_frame: the tool (output) frame; required for a file that names none.
        rcm_frame: the frame of the remote centre A, for a file that names none.
        rcm_axis_frame: the frame whose ``rcm_axis`` is the shaft line through A (default:
            the file's, else the tool frame).
        rcm_axis: ``x``, ``y`` or ``z`` (default: the file's, else ``z``).
        package_dirs: a mapping ROS package name -> its folder, searched first for ``$(find pkg)``
            and ``package://pkg/...`` (then ROS_PACKAGE_PATH, AMENT_PREFIX_PATH, the
            folders above the file).
        mesh_dirs: further folders mesh files may come from (beyond the file's own tree
            and the packages).
        trusted: the caller vouches for the xacro file at ``name_or_path``: xacro evaluates
            its expressions unchecked (CLI: ``--trusted``).
        output_frame: closed mechanisms: the output frame (same as ``tool_frame``); a LAAS
            sidecar names none (:mod:`rcm_pin.model.output_choice`).
        output_coords: closed mechanisms: its coordinates, e.g. ``"x y"`` or
            ``("x", "y", "rz")`` (default: the translation the tree moves in).
        **xacro_args: xacro arguments (validated against the file's declarations).

    Returns:
        The :class:`Mechanism`.

    Raises:
        UnknownMechanismError: a bare name that is not in the catalogue (lists the names).
        InvalidInputError: a missing or malformed file.
        XacroArgumentError: unknown, malformed or out-of-range xacro argument.
        UnknownFrameError: the tool, RCM or RCM axis frame is not known (lists the
            candidate frames).
        InvalidInputError: ``rcm_axis`` other than x, y, z, or an RCM axis without an RCM
            point.
        PackageNotFoundError: a ``$(find pkg)`` package found nowhere (names it and
            ``package_dirs`` / ``--package-dir``).
        UntrustedXacroError: an untrusted xacro file with an expression off the allow-list
            (names the file, line and expression).
    """
    if output_frame and tool_frame and output_frame != tool_frame:
        raise InvalidInputError(
            f"output_frame {output_frame!r} conflicts with tool_frame {tool_frame!r}; "
            "valid: one of them (they name the same frame)"
        )
    tool_frame = output_frame or tool_frame
    where = LoadOptions(dict(package_dirs or {}), tuple(mesh_dirs), bool(trusted))
    # the build keywords a rebuild passes on: the RCM axis and the closed output's coordinates
    build: dict[str, Any] = {
        k: v for k, v in (("rcm_axis_frame", rcm_axis_frame), ("rcm_axis", rcm_axis)) if v
    }
    if output_coords:
        build["output_coords"] = parse_coords(output_coords)
    if isinstance(name_or_path, Path):
        return _load_path(name_or_path, tool_frame, rcm_frame, xacro_args, where, build)
    if not isinstance(name_or_path, str) or not name_or_path.strip():
        get_entry(str(name_or_path))  # raises, listing the valid names
    if is_path_like(name_or_path):
        return _load_path(Path(name_or_path), tool_frame, rcm_frame, xacro_args, where, build)
    return _load_entry(get_entry(name_or_path), tool_frame, rcm_frame, xacro_args, where, build)


def from_urdf(
    urdf: str,
    name: str = "urdf",
    *,
    tool_frame: str | None = None,
    rcm_frame: str | None = None,
    rcm_axis_frame: str | None = None,
    rcm_axis: str | None = None,
) -> Mechanism:
    """A Mechanism from URDF text (its ``<rcm_pin>`` element names family and frames; the
    keywords as in :func:`load`).

    Raises:
        InvalidInputError: malformed URDF, a bad ``rcm_axis``.
        UnknownFrameError: the tool frame is not known (lists the candidate frames).
    """
    desc = read_description(urdf)
    urdf = resolve_meshes(urdf, source=None, search=PackageSearch())
    return build_mechanism(
        urdf,
        name=name,
        description=desc,
        family=family_named(desc.family),
        tool_frame=tool_frame,
        rcm_frame=rcm_frame,
        rcm_axis_frame=rcm_axis_frame,
        rcm_axis=rcm_axis,
    )


def _load_entry(
    entry: CatalogEntry,
    tool_frame: str | None,
    rcm_frame: str | None,
    xacro_args: dict[str, Any],
    where: LoadOptions,
    build: dict[str, Any] | None = None,
) -> Mechanism:
    build = build or {}
    if not entry.xacro:
        if xacro_args:
            raise XacroArgumentError(
                f"{entry.name} is a plain URDF ({entry.urdf_path.name}); it takes no xacro "
                f"arguments, got {', '.join(sorted(xacro_args))}"
            )
        search = where.search(entry.urdf_path)
        urdf = where.meshes(_read(entry.urdf_path), entry.urdf_path, search)
        desc = Description(tool_frame=entry.tool_frame)
        return build_mechanism(
            urdf,
            name=entry.name,
            description=desc,
            family=entry.family,
            tool_frame=tool_frame,
            rcm_frame=rcm_frame,
            **build,
        )
    for key in entry.fixed_args:
        if key in xacro_args:
            raise XacroArgumentError(
                f"xacro argument {key!r} is fixed by mechanism {entry.name} "
                f"({key}={entry.fixed_args[key]}); load {entry.xacro} variants by path instead"
            )
    args = validate_args(entry.xacro_path, {**entry.fixed_args, **xacro_args})
    search = where.search(entry.xacro_path)
    urdf = render_xacro(entry.xacro_path, args, search=search, trusted=True)  # our own file
    urdf = where.meshes(urdf, entry.xacro_path, search)

    def rebuild(**more: Any) -> Mechanism:
        merged = {**xacro_args, **more}
        return load(
            entry.name,
            tool_frame=tool_frame,
            rcm_frame=rcm_frame,
            **build,
            **where.keywords(),
            **merged,
        )

    return build_mechanism(
        urdf,
        name=entry.name,
        description=read_description(urdf),
        family=entry.family,
        args=args,
        tool_frame=tool_frame,
        rcm_frame=rcm_frame,
        rebuild=rebuild,
        source=entry.xacro_path,
        **build,
    )


def _read(path: Path) -> str:
    if not path.is_file():
        what = "a folder" if path.is_dir() else "no file"
        raise InvalidInputError(f"{path} is {what}; valid: an existing .urdf or .xacro file")
    try:
        return path.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise InvalidInputError(f"cannot read {path}: {exc}") from None


def _load_path(
    path: Path,
    tool_frame: str | None,
    rcm_frame: str | None,
    xacro_args: dict[str, Any],
    where: LoadOptions,
    build: dict[str, Any] | None = None,
) -> Mechanism:
    build = build or {}
    if path.suffix not in (".urdf", ".xacro"):
        raise UnknownMechanismError(
            f"{str(path)!r} is neither a catalogue name nor a .urdf / .xacro file; valid: "
            "a name from `rcm-pin list` or a path ending in .urdf or .xacro"
        )
    search = where.search(path)
    if path.suffix == ".xacro":
        _read(path)
        urdf = render_xacro(path, xacro_args, search=search, trusted=where.trusted)
        args = dict(validate_args(path, xacro_args))
    else:
        if xacro_args:
            raise XacroArgumentError(
                f"xacro arguments {', '.join(sorted(xacro_args))} given for plain URDF {path}"
            )
        urdf, args = _read(path), {}
    try:
        desc = read_description(urdf)
    except InvalidInputError as exc:
        raise InvalidInputError(f"{path}: {exc}") from None
    sidecar = path.with_suffix(".yaml")
    if desc.loops is None and sidecar.is_file():
        side = description_from_yaml(_read(sidecar))
        urdf = replace_joints(urdf, dict(side.joint_types))  # LAAS joint_name / joint_type
        desc = Description(
            family=desc.family or side.family,
            tool_frame=desc.tool_frame or side.tool_frame,
            rcm_frame=desc.rcm_frame,
            rcm_axis_frame=desc.rcm_axis_frame,
            rcm_axis=desc.rcm_axis,
            coordinates=desc.coordinates,
            loops=side.loops,
        )

    urdf = where.meshes(urdf, path, search)

    def rebuild(**more: Any) -> Mechanism:
        merged = {**xacro_args, **more}
        return load(
            path,
            tool_frame=tool_frame,
            rcm_frame=rcm_frame,
            **build,
            **where.keywords(),
            **merged,
        )

    return build_mechanism(
        urdf,
        name=path.name.split(".")[0],
        description=desc,
        family=family_named(desc.family),
        args=args,
        tool_frame=tool_frame,
        rcm_frame=rcm_frame,
        rebuild=rebuild if path.suffix == ".xacro" else None,
        source=path if path.suffix == ".xacro" else None,
        **build,
    )


__all__ = ["from_urdf", "load"]
