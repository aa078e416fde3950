"""Untrusted xacro files are data, not code (issue 26 item 1; SECURITY.md)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from xml.sax.saxutils import escape

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.errors import UntrustedXacroError
from rcm_pin.model.render import render_xacro
from rcm_pin.model.resources import xacro_dir
from rcm_pin.model.xacro_guard import process_file
from rcm_pin.model.xacro_safety import VALID, check_file, check_text, expression_problem

# the recursive strategies' repr is long; hypothesis warns about it, nothing else
pytestmark = pytest.mark.filterwarnings("ignore::hypothesis.errors.HypothesisWarning")

HEAD = '<?xml version="1.0"?>\n<robot name="m" xmlns:xacro="http://www.ros.org/wiki/xacro">\n'
BODY = """  <link name="base"/>
  <link name="tip"><inertial><mass value="${mass}"/>
    <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="tip"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _payload(marker: Path) -> str:
    """A comprehension that reaches os.system and writes ``marker`` (xacro's own guard lets
    it through: the dunders are inside the comprehension)."""
    return (
        "[c.__init__.__globals__['system']('echo ran > " + str(marker) + "') for _ in [0] "
        "for c in ().__class__.__base__.__subclasses__() if c.__name__ == '_wrap_close']"
    )


def _xacro(tmp_path: Path, lines: str, name: str = "m.urdf.xacro") -> Path:
    path = tmp_path / name
    path.write_text(HEAD + lines + BODY)
    return path


def test_the_exploit_is_refused_and_nothing_runs(tmp_path):
    marker = tmp_path / "ran"
    path = _xacro(tmp_path, f'  <xacro:property name="x" value="${{{_payload(marker)}}}"/>\n'
                  '  <xacro:property name="mass" value="${len(x) + 1}"/>\n')  # fmt: skip
    with pytest.raises(UntrustedXacroError) as info:
        rcm_pin.load(path, tool_frame="tip")
    assert (info.value.file, info.value.line) == (str(path.resolve()), 3)
    assert info.value.expression == _payload(marker)
    assert not marker.exists()


def test_the_cli_refuses_the_exploit_with_one_json_document(tmp_path, capsys):
    marker = tmp_path / "ran"
    path = _xacro(tmp_path, f'  <xacro:property name="mass" value="${{{_payload(marker)}}}"/>\n')
    status = main(["fk", str(path), "--tool-frame", "tip", "--q", "0", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert status == 2
    assert doc["error"]["type"] == "UntrustedXacroError"
    assert not marker.exists()


def test_the_exact_message(tmp_path):
    path = _xacro(tmp_path, '  <xacro:property name="mass" value="${(1).__class__}"/>\n')
    with pytest.raises(UntrustedXacroError) as info:
        render_xacro(path)
    assert str(info.value) == (
        f"{path.resolve()}:3: expression ${{(1).__class__}} in an untrusted xacro: attribute "
        f"access .__class__ is not allowed; valid: {VALID}"
    )
    assert VALID.startswith("numbers, strings, property names, arithmetic, comparisons, ")
    assert VALID.endswith("; a file you trust loads with trusted=True (CLI: --trusted)")


def test_trusted_lets_a_benign_expression_through(tmp_path, capsys):
    path = _xacro(tmp_path, '  <xacro:property name="mass" value="${[2*k for k in [1, 2]][1]}"/>\n')
    with pytest.raises(UntrustedXacroError):
        rcm_pin.load(path, tool_frame="tip")
    assert rcm_pin.load(path, tool_frame="tip", trusted=True).model.inertias[1].mass == 4.0
    assert main(["fk", str(path), "--tool-frame", "tip", "--q", "0", "--json"]) == 2
    capsys.readouterr()
    assert main(["fk", str(path), "--tool-frame", "tip", "--q", "0", "--trusted", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["mechanism"] == "m"


@pytest.mark.parametrize("path", sorted(xacro_dir().glob("*.xacro")), ids=lambda p: p.name)
def test_every_shipped_xacro_passes_untrusted(path):
    checked = check_file(path)
    assert checked[0] == path.resolve()
    if path.name.endswith(".urdf.xacro"):
        assert render_xacro(path, trusted=False) == render_xacro(path, trusted=True)


def test_a_static_include_is_checked_with_its_line(tmp_path):
    (tmp_path / "inc.xacro").write_text(
        HEAD + '\n  <xacro:property name="y" value="${lambda: 1}"/>\n</robot>\n'
    )
    path = _xacro(tmp_path, '  <xacro:include filename="$(dirname)/inc.xacro"/>\n'
                  '  <xacro:property name="mass" value="1"/>\n')  # fmt: skip
    with pytest.raises(UntrustedXacroError, match=r"inc\.xacro:4: expression \$\{lambda: 1\}"):
        render_xacro(path)


def test_an_include_named_by_an_expression_is_checked_when_xacro_reaches_it(tmp_path):
    marker = tmp_path / "ran"
    (tmp_path / "evil.xacro").write_text(
        HEAD + f'  <xacro:property name="y" value="${{{_payload(marker)}}}"/>\n</robot>\n'
    )
    path = _xacro(tmp_path, '  <xacro:property name="inc" value="evil.xacro"/>\n'
                  '  <xacro:include filename="${inc}"/>\n'
                  '  <xacro:property name="mass" value="1"/>\n')  # fmt: skip
    assert [p.name for p in check_file(path)] == ["m.urdf.xacro"]  # not resolvable statically
    with pytest.raises(UntrustedXacroError, match=r"evil\.xacro:3: expression"):
        render_xacro(path)
    assert not marker.exists()


def test_an_expression_spliced_from_an_argument_is_checked_before_it_runs(tmp_path):
    marker = tmp_path / "ran"
    path = _xacro(tmp_path, f'  <xacro:arg name="x" default="{_payload(marker)}"/>\n'
                  '  <xacro:property name="mass" value="${len($(arg x)) + 1}"/>\n')  # fmt: skip
    with pytest.raises(UntrustedXacroError, match=r"\(built at render time\): expression"):
        process_file(path, {}, trusted=False)
    assert not marker.exists()


def test_eval_substitutions_and_evaluated_comments_are_checked(tmp_path):
    path = _xacro(tmp_path, '  <xacro:property name="mass" value="$(eval [k for k in [1]])"/>\n')
    with pytest.raises(UntrustedXacroError, match=r":3: expression \$\(eval \[k for k in"):
        render_xacro(path)
    path = _xacro(tmp_path, '  <!-- xacro:eval-comments -->\n  <!-- ${open("f")} -->\n'
                  '  <xacro:property name="mass" value="1"/>\n')  # fmt: skip
    with pytest.raises(UntrustedXacroError, match=r":4: expression \$\{open\(\"f\"\)\}"):
        render_xacro(path)


# ------------------------------------------------------------------ all expressions
PROPERTIES = {"a": 1.5, "b": -2, "c": 0.25}
NUMBER = st.one_of(
    st.integers(-9, 9).map(str), st.sampled_from(["0.5", "2.25", "1e-3", "pi", "True"])
)
LEAF = st.one_of(NUMBER, st.sampled_from(sorted(PROPERTIES)))


def _extend(inner: st.SearchStrategy[str]) -> st.SearchStrategy[str]:
    two = st.tuples(inner, inner)
    return st.one_of(
        st.builds("({} {} {})".format, inner, st.sampled_from(["+", "-", "*"]), inner),
        inner.map("-({})".format),
        inner.map("({}) / 4".format),
        two.map(lambda t: f"max({t[0]}, {t[1]})"),
        two.map(lambda t: f"atan2({t[0]}, {t[1]})"),
        st.builds("{}({})".format, st.sampled_from(["sin", "cos", "fabs", "math.sin"]), inner),
        inner.map("sqrt(fabs({}))".format),
        inner.map("radians({})".format),
        st.builds("({} if {} < {} else {})".format, inner, inner, inner, inner),
        two.map(lambda t: f"(1 if ({t[0]} >= {t[1]} and not {t[1]} == 3) else 0)"),
        two.map(lambda t: f"[{t[0]}, {t[1]}][1]"),
    )


ALLOWED_EXPR = st.recursive(LEAF, _extend, max_leaves=6)
FORBIDDEN = [
    "[{} for k in [1]][0]", "(lambda: {})()", "({}).real", "__import__('os')", "open({})",
    "x.__class__", "f'{{{}}}'", "round({}, ndigits=1)", "max(*[{}, 1])", "{{1: {}}}[1]",
    "{{{}}}", "(y := {})", "python", "load_yaml({})", "xacro.load_yaml({})", "b'{}'",
    "math.factorial(3)", "list([{}])", "({} for k in [1])", "a['__class__']",
]  # fmt: skip


@settings(
    max_examples=60, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(expr=ALLOWED_EXPR)
def test_allowed_expressions_are_accepted_and_evaluate_like_python(tmp_path, expr):
    assert expression_problem(expr) is None
    namespace = {**vars(math), **PROPERTIES, "math": math, "max": max}
    expected = eval(expr, {"__builtins__": {}}, namespace)  # the test's own expressions
    props = "".join(f'  <xacro:property name="{k}" value="{v}"/>\n' for k, v in PROPERTIES.items())
    mass = f'  <xacro:property name="mass" value="${{{escape(expr)}}}"/>\n'
    path = _xacro(tmp_path, props + mass)
    doc = process_file(path, {}, trusted=False)
    assert doc.getElementsByTagName("mass")[0].getAttribute("value") == str(expected)


@settings(max_examples=60, deadline=None)
@given(form=st.sampled_from(FORBIDDEN), inner=ALLOWED_EXPR)
def test_forbidden_expressions_are_refused(form, inner):
    expr = form.format(inner)
    reason = expression_problem(expr)
    assert reason is not None and reason.endswith("not allowed")
    with pytest.raises(UntrustedXacroError, match=r"^f\.xacro:7: expression "):
        check_text(f"x ${{{expr}}} y", "f.xacro", 7)
