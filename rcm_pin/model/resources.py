"""Where the shipped model sources are: package data inside ``rcm_pin``.

The repository keeps one copy of the design sources at its top level (``xacro/``, the
parametric models, and ``urdf/``, their committed default renderings with the loop
sidecars). ``rcm_pin/_data/xacro`` and ``rcm_pin/_data/urdf`` are symbolic links to
them, so an editable install reads the checkout and a built wheel carries copies as
package data (setuptools follows the links). Nothing here looks at the current working
directory or at a repository path.
"""

from __future__ import annotations

from importlib.resources import files
from pathlib import Path


def data_dir(kind: str) -> Path:
    """Directory of the shipped ``"xacro"`` or ``"urdf"`` files.

    Raises:
        ValueError: ``kind`` is neither (a programming error, not user input).
    """
    if kind not in ("xacro", "urdf"):
        raise ValueError(f"kind {kind!r}; valid: 'xacro', 'urdf'")
    return Path(str(files("rcm_pin") / "_data" / kind))


def xacro_dir() -> Path:
    """The shipped xacro sources (``xacro/`` of the checkout)."""
    return data_dir("xacro")


def urdf_dir() -> Path:
    """The committed default renderings (``urdf/`` of the checkout)."""
    return data_dir("urdf")
