"""Disk-cached compiled CasADi functions (ocp.compiled): same values, one compilation."""

from __future__ import annotations

import casadi as ca
import numpy as np
import pytest

from ocp import compiled as cc


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("RCM_PIN_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def _function(name: str = "cc_test") -> ca.Function:
    x, p = ca.SX.sym("x", 3), ca.SX.sym("p", 2)
    y = ca.vertcat(ca.sin(x[0]) * x[1] ** 2, ca.exp(p[0] * x[2]) / (1 + x[0] ** 2), p[1])
    return ca.Function(name, [x, p], [y, ca.jacobian(y, x)], ["x", "p"], ["y", "J"])


def _check_same(fun: ca.Function, other: ca.Function) -> None:
    rng = np.random.default_rng(0)
    for _ in range(5):
        x, p = rng.normal(size=3), rng.normal(size=2)
        for want, got in zip(fun(x, p), other(x, p)):
            np.testing.assert_allclose(np.asarray(got), np.asarray(want), rtol=1e-12, atol=1e-12)


def test_cache_hit_gives_the_same_values_without_recompiling(cache):
    fun = _function()
    first = cc.compile_function(fun)
    assert first.path is not None and not first.cached and first.path.parent == cache
    mtime = first.path.stat().st_mtime_ns
    before = cc.STATS["compiled"]
    second = cc.compile_function(_function())  # rebuilt: the same expression
    assert second.cached and second.path == first.path
    assert cc.STATS["compiled"] == before and first.path.stat().st_mtime_ns == mtime
    assert second.function.name() == "cc_test"
    assert second.function.sparsity_out(1) == fun.sparsity_out(1)
    _check_same(fun, first.function)
    _check_same(fun, second.function)


def test_lazy_builds_only_on_a_miss(cache):
    calls = []

    def build() -> ca.Function:
        calls.append(1)
        return _function()

    first = cc.compile_lazy("cc_test", "model A", build, opt="-O0")
    second = cc.compile_lazy("cc_test", "model A", build, opt="-O0")
    assert len(calls) == 1 and not first.cached and second.cached
    _check_same(_function(), second.function)
    with pytest.raises(ValueError, match="expected 'other'"):
        cc.compile_lazy("other", "model A", build, opt="-O0")


def test_key_and_flags_select_different_libraries(cache):
    fun = _function()
    paths = {
        cc.compile_function(fun).path,
        cc.compile_function(fun, key="other model").path,
        cc.compile_function(fun, opt="-O0").path,
    }
    assert len(paths) == 3 and all(p is not None and p.exists() for p in paths)
    assert not list(cache.glob(".build_*"))  # temporary build folders are removed


def test_cache_dir_default_is_the_user_cache(monkeypatch, tmp_path):
    monkeypatch.delenv("RCM_PIN_CACHE", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path))
    assert cc.cache_dir() == tmp_path / "rcm-pin" / "casadi"


def test_without_a_compiler_the_original_function_is_returned(cache, monkeypatch):
    fun = _function()
    monkeypatch.setattr(cc, "c_compiler", lambda: None)
    with pytest.warns(cc.CompileWarning, match="no C compiler found"):
        res = cc.compile_function(fun)
    assert res.function is fun and res.path is None and not res.cached


def test_a_failing_compiler_falls_back(cache, monkeypatch):
    fun = _function()
    monkeypatch.setattr(cc, "c_compiler", lambda: "/bin/false")
    with pytest.warns(cc.CompileWarning, match="/bin/false failed"):
        out = cc.compiled(fun)
    assert out is fun and not list(cache.glob("*.so"))
