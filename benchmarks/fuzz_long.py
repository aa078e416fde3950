"""Fuzz suite, long profile (issue 11): >= 10^4 cases per entry point, a JSON summary.

Runs the strategies and checks of ``tests/test_fuzz.py`` (the bounded profile) with many
more examples and without stopping at the first failure. Per entry point it counts the
cases, the valid results confirmed by a second route, the typed errors (``RcmPinError``;
CLI exit 2 / 3 with the JSON error), the wrong results (a second route disagrees), the
tracebacks (any other exception or a failed
check), the hangs (a call over ``--timeout`` seconds) and the warnings (a warning turned
into an error), and keeps the first few failures of each kind.

Usage::

    .venv/bin/python benchmarks/fuzz_long.py [--cases 10000] [--arm-cases 1000]
        [--only forward,cli_fk] [--timeout 30]
"""

from __future__ import annotations

import argparse
import json
import signal
import sys
import time
import traceback
from collections.abc import Callable
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
import test_fuzz as fz
import test_fuzz_files as ff
import test_xacro_safety as xs


class HangError(Exception):
    """A call that did not return within the timeout."""


class BudgetSpentError(BaseException):
    """The entry point's time budget is spent (a BaseException: hypothesis stops at once)."""


def _alarm(signum: int, frame: Any) -> None:
    raise HangError


#: Families whose inverse problem is numeric (multistart LM): slow entry points of their own.
NUMERIC_IK = ("arm",)


def _entry_points() -> dict[str, tuple[st.SearchStrategy[Any], Callable[[Any], str]]]:
    # The numeric IK of the arms (multistart LM, ~0.4 s a reachable target) has its own
    # entry points, so that the others reach 10^4 cases within minutes.
    fast = [n for n in fz.NAMES if fz.MECHS[n].family.name not in NUMERIC_IK]
    names = st.sampled_from(fz.NAMES)
    quick = st.sampled_from(fast)
    arms = st.sampled_from([n for n in fz.NAMES if n not in fast])
    serial = st.sampled_from([n for n in fz.NAMES if fz.MECHS[n].loops is None])
    xyz = st.sampled_from([n for n in fast if fz.MECHS[n].output.coords[:1] == ("x",)])

    def cli(command: str, among: Any = names) -> st.SearchStrategy[Any]:
        return among.flatmap(lambda n: fz.cli_argv(n, command))

    return {
        "forward": (
            names.flatmap(lambda n: st.tuples(st.just(n), fz.mech_inputs(fz.MECHS[n]))),
            lambda c: fz.check_forward(fz.MECHS[c[0]], c[1]),
        ),
        "tool_pose": (
            serial.flatmap(lambda n: st.tuples(st.just(n), fz.mech_inputs(fz.MECHS[n]))),
            lambda c: fz.check_tool_pose(fz.MECHS[c[0]], c[1]),
        ),
        "inverse": (
            quick.flatmap(lambda n: st.tuples(st.just(n), fz.mech_targets(fz.MECHS[n]))),
            lambda c: fz.check_inverse(fz.MECHS[c[0]], c[1]),
        ),
        "inverse_arms": (
            arms.flatmap(lambda n: st.tuples(st.just(n), fz.mech_targets(fz.MECHS[n]))),
            lambda c: fz.check_inverse(fz.MECHS[c[0]], c[1]),
        ),
        "inverse_xyz": (
            st.tuples(xyz, st.lists(fz.numbers(), min_size=3, max_size=3)),
            lambda c: fz.check_inverse(fz.MECHS[c[0]], c[1], ("x", "y", "z")),
        ),
        "load": (fz.load_args(), lambda c: fz.check_load(*c)),
        **{f"cli_{c}": (cli(c), fz.check_cli) for c in ("fk", "singularities", "workspace")},
        "cli_ik": (cli("ik", quick), fz.check_cli),
        "cli_ik_arms": (cli("ik", arms), fz.check_cli),
        "cli_fourbar": (fz.fourbar_argv(), fz.check_fourbar),
        "cli_bounds": (fz.bounds_argv(), fz.check_cli),
        "cli_view_meshes": (ff.mesh_names(), ff.check_view),
        "cli_rcm_track": (ff.rcm_track_argv(), fz.check_cli),
        "xacro_allowed": (xs.ALLOWED_EXPR, _check_allowed),
        "xacro_forbidden": (
            st.tuples(st.sampled_from(xs.FORBIDDEN), xs.ALLOWED_EXPR),
            _check_forbidden,
        ),
    }


def _check_allowed(expr: str) -> str:
    """An allowed expression passes the allow-list ("valid"): a refusal is wrong."""
    from rcm_pin.model.xacro_safety import expression_problem

    problem = expression_problem(expr)
    assert problem is None, f"{expr!r} refused: {problem}"
    return "valid"


def _check_forbidden(case: tuple[str, str]) -> str:
    """A forbidden form around any expression is refused with UntrustedXacroError ("typed")."""
    from rcm_pin.errors import UntrustedXacroError
    from rcm_pin.model.xacro_safety import check_text

    expr = case[0].format(case[1])
    try:
        check_text(f"x ${{{expr}}} y", "f.xacro", 7)
    except UntrustedXacroError:
        return "typed"
    raise AssertionError(f"{expr!r} passed the allow-list")


def run(
    name: str,
    strategy: Any,
    check: Callable[[Any], str],
    cases: int,
    timeout: float,
    budget: float = float("inf"),
) -> dict:
    """Counts of one entry point (module docstring); cases after ``budget`` [s] are skipped."""
    counts = {"cases": 0, "valid": 0, "typed": 0, "wrong": 0, "tracebacks": 0, "hangs": 0}
    counts["warnings"] = 0
    failures: list[str] = []
    start = time.perf_counter()

    @settings(
        max_examples=cases,
        deadline=None,
        database=None,
        derandomize=False,
        suppress_health_check=list(HealthCheck),
    )
    @given(case=strategy)
    def body(case: Any) -> None:
        if time.perf_counter() - start > budget:
            raise BudgetSpentError
        counts["cases"] += 1
        signal.setitimer(signal.ITIMER_REAL, timeout)
        try:
            counts[fz_outcome(check, case)] += 1
        except HangError:
            counts["hangs"] += 1
            failures.append(f"hang > {timeout} s: {fz_short(case)}")
        except Warning as exc:
            counts["warnings"] += 1
            failures.append(f"warning {exc!r}: {fz_short(case)}")
        except AssertionError:  # a second route disagrees: a silent wrong result
            counts["wrong"] += 1
            failures.append(f"wrong: {fz_short(case)}\n{traceback.format_exc(limit=-3)}")
        except BaseException:
            counts["tracebacks"] += 1
            failures.append(f"{fz_short(case)}\n{traceback.format_exc(limit=-4)}")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)

    try:
        body()
    except BudgetSpentError:
        pass
    except Exception:  # a strategy that failed to generate: reported, the run goes on
        counts["tracebacks"] += 1
        failures.append(f"generation failed:\n{traceback.format_exc(limit=-4)}")
    return {
        **counts,
        "seconds": round(time.perf_counter() - start, 1),
        "stopped_by_budget": counts["cases"] < cases,
        "first_failures": failures[:5],
    }


def fz_outcome(check: Callable[[Any], str], case: Any) -> str:
    outcome = check(case)
    assert outcome in ("valid", "typed"), outcome
    return outcome


def fz_short(case: Any) -> str:
    text = repr(case)
    return text if len(text) < 400 else text[:397] + "..."


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=10_000, help="cases per entry point")
    parser.add_argument(
        "--arm-cases", type=int, default=1_000, help="cases of the *_arms entry points"
    )
    parser.add_argument("--only", help="comma-separated entry points (default: all)")
    parser.add_argument("--timeout", type=float, default=30.0, help="hang bound per call [s]")
    parser.add_argument("--budget", type=float, default=float("inf"), help="[s] per entry point")
    args = parser.parse_args()
    signal.signal(signal.SIGALRM, _alarm)
    points = _entry_points()
    chosen = args.only.split(",") if args.only else list(points)
    summary = {}
    for name in chosen:
        strategy, check = points[name]
        cases = args.arm_cases if name.endswith("_arms") else args.cases
        summary[name] = run(name, strategy, check, cases, args.timeout, args.budget)
        print(json.dumps({name: summary[name]}), file=sys.stderr, flush=True)
    keys = ("cases", "valid", "typed", "wrong", "tracebacks", "hangs", "warnings")
    total = {k: sum(s[k] for s in summary.values()) for k in keys}
    print(json.dumps({"per_entry_point": summary, "total": total}, indent=2))


if __name__ == "__main__":
    main()
