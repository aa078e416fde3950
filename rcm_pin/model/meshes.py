"""Mesh files of a URDF: resolved where the description lives, refused anywhere else.

:func:`resolve_meshes` rewrites every ``<mesh filename="...">`` of URDF text to an
absolute path, at load time:

* ``package://pkg/rest``: ``pkg`` found by :mod:`rcm_pin.model.packages`, ``rest`` inside
  it. A package found nowhere is left as written (the viewer draws without it and warns,
  :func:`drawable_urdf`);
* ``file:///abs``, an absolute path, or a relative one (relative to the URDF's folder).

A resolved file must lie inside an allowed folder: the description's own tree (the folder
of the URDF or xacro file, or the package holding it: the nearest folder above with a
``package.xml``), a package the description names (``package://`` or ``$(find)``), a
declared package folder (``package_dirs=``, ``--package-dir``), a package the search
finds (ROS_PACKAGE_PATH, ...) or a declared mesh folder
(``mesh_dirs=``, ``--mesh-dir``). Anything else (``file:///etc/passwd``,
``../../secret.obj``) is never read: the kinematics load, and the viewer (whose HTML
export embeds every mesh it draws) raises :class:`~rcm_pin.errors.MeshLocationError`
naming ``--mesh-dir``: a user's file is data.
"""

from __future__ import annotations

import re
import warnings
from collections.abc import Callable, Iterable
from html import escape, unescape  # xml.sax.saxutils imports urllib, http, email: 30 ms
from pathlib import Path

from rcm_pin.errors import InvalidInputError, MeshLocationError
from rcm_pin.model.packages import PackageSearch, package_name

_MESH = re.compile(r"(<mesh\b[^>]*?\bfilename\s*=\s*)([\"'])(.*?)\2", re.DOTALL)
_VISUAL = re.compile(r"<visual\b[^>]*?(?:/>|>.*?</visual\s*>)", re.DOTALL)


class MissingMeshWarning(UserWarning):
    """A mesh the viewer cannot draw (the message names the file and why)."""


#: Prefix :func:`resolve_meshes` gives a mesh outside the allowed folders (not a URI scheme
#: any reader knows, so no library opens it), followed by the reason.
REFUSED = "rcm-pin-refused:"


def description_root(source: Path) -> Path:
    """The tree a description's meshes may come from: the package holding ``source``
    (nearest folder above with a package.xml), else the folder of ``source``."""
    folder = source.resolve().parent
    for above in (folder, *folder.parents):
        if (above / "package.xml").is_file():
            return above
    return folder


def _user_path(text: str | Path, what: str) -> Path:
    """A folder the user named (``~`` expanded).

    Raises:
        InvalidInputError: a ``~user`` whose home is not known.
    """
    try:
        return Path(text).expanduser()
    except RuntimeError:
        raise InvalidInputError(
            f"{what} {str(text)!r}: its home folder is not known; valid: an absolute path"
        ) from None


def _inside(path: Path, roots: Iterable[Path]) -> bool:
    return any(path == r or r in path.parents for r in roots)


def _memo(search: PackageSearch) -> Callable[[str], Path]:
    """``search.find`` remembering answers and failures (one search per package a load)."""
    answers: dict[str, Path | LookupError] = {}

    def find(name: str) -> Path:
        if name not in answers:
            try:
                answers[name] = search.find(name).resolve()
            except LookupError as exc:
                answers[name] = exc
        answer = answers[name]
        if isinstance(answer, LookupError):
            raise answer
        return answer

    return find


def _in_found_package(path: Path, find: Callable[[str], Path]) -> bool:
    """Whether ``path`` lies in a package the search finds at that folder (a file named
    through ``$(find pkg)``, which xacro renders as an absolute path)."""
    for folder in path.parents:
        name = package_name(folder)
        if name is not None:
            try:
                return find(name) == folder
            except LookupError:
                return False
    return False


def _target(uri: str, base: Path | None, find: Callable[[str], Path]) -> tuple[Path, Path | None]:
    """(resolved file, its package folder) of a mesh URI (LookupError: package not found)."""
    if uri.startswith("package://"):
        name, _, rest = uri[len("package://") :].partition("/")
        folder = find(name)
        return (folder / rest).resolve(), folder
    # a file's mesh name is data: no "~" expansion (the exporter's home is not the author's)
    path = Path(uri[len("file://") :] if uri.startswith("file://") else uri)
    if not path.is_absolute():
        path = (base or Path.cwd()) / path
    return path.resolve(), None


def resolve_meshes(
    urdf: str,
    *,
    source: Path | None,
    search: PackageSearch,
    mesh_dirs: Iterable[str | Path] = (),
) -> str:
    """URDF text with every mesh filename an absolute path inside an allowed folder.

    Args:
        urdf: URDF text.
        source: the URDF or xacro file it came from (None: text, no folder of its own).
        search: where ``package://`` packages are found.
        mesh_dirs: further folders meshes may come from [paths].

    Returns:
        The text, mesh filenames rewritten (unresolvable packages and other schemes kept);
        a mesh outside every allowed folder becomes ``REFUSED`` + the reason, so that
        kinematics still load and :func:`drawable_urdf` (the viewer) refuses it.
    """
    roots = [_user_path(d, "mesh folder").resolve() for d in mesh_dirs]
    roots += [f for _, f in search.declared]
    if source is not None:
        roots.append(description_root(source))
    base = source.resolve().parent if source is not None else None
    find = _memo(search)

    def rewrite(match: re.Match[str]) -> str:
        uri = unescape(match.group(3))
        if re.match(r"[A-Za-z][A-Za-z0-9+.-]*://", uri) and not uri.startswith(
            ("package://", "file://")
        ):
            return match.group(0)  # another scheme: left to the viewer, which warns
        try:
            path, package = _target(uri, base, find)
        except LookupError:
            return match.group(0)
        allowed = roots + ([package] if package is not None else [])
        if not _inside(path, allowed) and not _in_found_package(path, find):
            where = f"the folders of {source}" if source is not None else "no folder (URDF text)"
            refused = f"{REFUSED}{uri} ({path}) is outside the description's folders ({where})"
            return f"{match.group(1)}{match.group(2)}{escape(refused)}{match.group(2)}"
        return f"{match.group(1)}{match.group(2)}{escape(str(path))}{match.group(2)}"

    return _MESH.sub(rewrite, urdf)


def drawable_urdf(urdf: str) -> str:
    """The URDF without the visuals whose mesh is not a local file that exists; each one
    dropped is a :class:`MissingMeshWarning` naming the file and what to do.

    Raises:
        MeshLocationError: a mesh outside every allowed folder (names the file and
            ``--mesh-dir`` / ``mesh_dirs=``): never read, never embedded in a page.
    """

    def keep(match: re.Match[str]) -> str:
        mesh = _MESH.search(match.group(0))
        if mesh is None:
            return match.group(0)
        name = unescape(mesh.group(3))
        if name.startswith(REFUSED):
            raise MeshLocationError(
                f"mesh {name[len(REFUSED) :]} and every declared package or mesh folder; "
                "valid: a mesh inside them, or allow its folder with --mesh-dir PATH "
                "(mesh_dirs=[PATH] in Python)"
            )
        if Path(name).is_absolute() and Path(name).is_file():
            return match.group(0)
        if name.startswith("package://"):
            package = name[len("package://") :].partition("/")[0]
            why = f"package {package!r} not found; valid: --package-dir {package}=PATH"
        elif Path(name).is_absolute():
            why = "no such file"
        else:
            why = "not a local file"
        warnings.warn(f"mesh {name} not drawn ({why})", MissingMeshWarning, stacklevel=4)
        return ""

    return _VISUAL.sub(keep, urdf)


__all__ = ["REFUSED", "MissingMeshWarning", "description_root", "drawable_urdf", "resolve_meshes"]
