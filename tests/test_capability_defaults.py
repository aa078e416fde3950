"""Every CLI command on mechanisms that run through the capability defaults.

A throwaway family defined in a temporary module provides only a ``PositionSolver``; a
URDF loaded by path names no family. Each command gives a result or a typed error (exit
0, 2 or 3), never a traceback or an untyped error.
"""

from __future__ import annotations

import importlib
import subprocess
import sys
import textwrap

import pytest

from rcm_pin.catalog import table
from rcm_pin.cli import build_parser, main

FAMILY_MODULE = '''
from rcm_pin.analysis.capabilities import NumericPosition
from rcm_pin.model.family import Family


class OnlyPosition(NumericPosition):
    """The numeric routes, provided as the family's own solver."""


class ThrowawayFamily(Family):
    name = "throwaway"
    description = "provides only a PositionSolver"
    capabilities = (OnlyPosition(),)


FAMILY = ThrowawayFamily()
'''

#: What each subcommand runs with on a serial mechanism at PATH (None: not per mechanism).
SERIAL = {
    "list": [],
    "urdf": None,  # catalogue names only
    "reproduce": None,  # the papers' catalogue mechanisms
    "fourbar": None,  # closed-form four-bar synthesis, no mechanism
    "fk": ["--q=0,0,0,0,0,0"],
    "ik": ["--xyz=0.05,0.02,0.2"],
    "singularities": ["--q=0.1,0.2,0.03,0.1,0.5,0.1"],
    "workspace": ["--samples=200"],
    "accuracy": [],
    "simulate": ["--duration=0.02"],
    "view": ["--html={tmp}/v.html"],
    "ocp": ["--xyz=0.05,0.02,0.2"],
    "sweep": ["--vary=l9=0.1:0.2:2", "--metric=x"],
    "optimize": ["--vary=l9=0.1:0.2", "--metric=x"],
    "rcm-track": ["--path=circle", "--duration=0.05"],
    "vibrations": ["--stiffness=100"],
    "export": ["--mjcf={tmp}/m.xml"],
}
BEFORE = {"ocp": ["ocp", "ik"]}


def subcommands() -> list[str]:
    parser = build_parser()
    action = next(a for a in parser._actions if a.__class__.__name__ == "_SubParsersAction")
    return list(action.choices)


def test_every_subcommand_is_covered():
    assert set(subcommands()) == set(SERIAL)


def render(tmp_path, family: str | None, name: str = "rcm_bevel"):
    text = subprocess.run(
        [sys.executable, "-m", "rcm_pin", "urdf", name],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    old = 'family="rcm"' if name == "rcm_bevel" else f'family="{name}"'
    assert old in text
    text = text.replace(old, f'family="{family}"' if family else "")
    path = tmp_path / f"{name}_{family or 'none'}.urdf"
    path.write_text(text)
    return path


@pytest.fixture
def throwaway(tmp_path, monkeypatch):
    (tmp_path / "throwaway_family.py").write_text(textwrap.dedent(FAMILY_MODULE))
    monkeypatch.syspath_prepend(str(tmp_path))
    module = importlib.import_module("throwaway_family")
    monkeypatch.setitem(table.FAMILIES, "throwaway", module.FAMILY)
    yield module
    sys.modules.pop("throwaway_family", None)


def run(command: str, path, tmp_path, capsys) -> tuple[int, str]:
    extra = SERIAL[command]
    assert extra is not None, f"{command} takes no mechanism by path"
    head = BEFORE.get(command, [command])
    argv = (
        head + ([] if command == "list" else [str(path)]) + [a.format(tmp=tmp_path) for a in extra]
    )
    code = main([*argv, "--json"] if command != "list" else ["list", "--json"])
    out = capsys.readouterr()
    assert "Traceback" not in out.err
    return code, out.err


@pytest.mark.parametrize("command", sorted(c for c, extra in SERIAL.items() if extra is not None))
def test_throwaway_family_runs_every_command(command, throwaway, tmp_path, capsys):
    path = render(tmp_path, "throwaway")
    import rcm_pin

    assert rcm_pin.load(path).family is throwaway.FAMILY
    code, err = run(command, path, tmp_path, capsys)
    assert code in (0, 2, 3), err


@pytest.mark.parametrize(
    "command",
    ["rcm-track", "simulate", "singularities", "workspace", "accuracy", "view", "export"],
)
def test_urdf_without_family_runs_through_the_defaults(command, tmp_path, capsys):
    path = render(tmp_path, None)
    import rcm_pin

    assert type(rcm_pin.load(path).family) is table.Family
    code, err = run(command, path, tmp_path, capsys)
    assert code in (0, 2, 3), err
    assert "KeyError" not in err
