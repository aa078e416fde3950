"""The compiled-function cache never loads a damaged entry (ocp.so_cache, ocp.compiled).

Each load runs in a subprocess: a truncated shared library kills the process that maps it
with SIGBUS, which would otherwise take pytest down instead of failing the test.
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from ocp import so_cache

ROOT = Path(__file__).resolve().parents[1]

# Compiles (or loads) a tiny function through the cache; prints the outcome as JSON.
SCRIPT = """
import json, sys, warnings
import casadi as ca
from ocp import compiled as cc
x = ca.SX.sym("x", 3)
fun = ca.Function("so_cache_test", [x], [ca.sin(x) * 2 + x[0] * x[2]])
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    res = cc.compile_function(fun, opt="-O0")
value = [float(v) for v in ca.DM(res.function([0.1, 0.2, 0.3])).full().ravel()]
print(json.dumps({
    "value": value, "cached": res.cached, "path": None if res.path is None else str(res.path),
    "warnings": [f"{w.category.__name__}: {w.message}" for w in caught],
}))
"""
EXPECTED = [2 * __import__("math").sin(v) + 0.1 * 0.3 for v in (0.1, 0.2, 0.3)]


def _run(cache: Path, wrap: list[str] | None = None) -> dict:
    env = {**os.environ, "RCM_PIN_CACHE": str(cache), "PYTHONPATH": str(ROOT)}
    cmd = [*(wrap or []), sys.executable, "-c", SCRIPT]
    run = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=120)
    assert run.returncode == 0, f"exit {run.returncode} (-7: SIGBUS): {run.stderr[-2000:]}"
    out: dict = json.loads(run.stdout.strip().splitlines()[-1])
    assert out["value"] == pytest.approx(EXPECTED, rel=1e-12)
    return out


def _truncate(lib: Path) -> None:
    os.truncate(lib, lib.stat().st_size // 2)


def _empty(lib: Path) -> None:
    lib.write_bytes(b"")


def _flip(lib: Path) -> None:
    data = bytearray(lib.read_bytes())
    data[len(data) // 2] ^= 0xFF
    lib.write_bytes(bytes(data))


def _no_record(lib: Path) -> None:
    so_cache.sidecar(lib).unlink()


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> tuple[Path, Path]:
    """A cache with the compiled library in it, and the library's path."""
    cache = tmp_path_factory.mktemp("so_cache") / "cache"
    first = _run(cache)
    assert not first["cached"] and first["path"] and not first["warnings"]
    lib = Path(first["path"])
    assert so_cache.verify(lib) is None and so_cache.sidecar(lib).exists()
    assert _run(cache)["cached"]  # a verified hit
    return cache, lib


@pytest.mark.parametrize(
    ("damage", "why"),
    [
        (_truncate, "bytes; its record says"),
        (_empty, "it has 0 bytes"),
        (_flip, "its SHA-256 differs from its record"),
        (_no_record, "it has no checksum record"),
    ],
)
def test_a_damaged_library_is_rebuilt_not_loaded(built, tmp_path, damage, why):
    cache = tmp_path / "cache"
    shutil.copytree(built[0], cache)
    lib = cache / built[1].name
    damage(lib)
    assert so_cache.verify(lib) is not None
    out = _run(cache)
    assert not out["cached"] and out["path"] == str(lib)
    if why == so_cache.NO_RECORD:  # an older version's entry: rebuilt like a miss
        assert not out["warnings"], out
    else:
        assert any(w.startswith("CacheWarning") and why in w for w in out["warnings"]), out
    assert so_cache.verify(lib) is None  # rebuilt and recorded
    assert _run(cache)["cached"]


def _read_only(folder: Path) -> list[str]:
    """A command prefix under which ``folder`` cannot be written (mode 0555; for root, to
    whom modes do not apply, a read-only bind mount in a private mount namespace)."""
    folder.mkdir(parents=True, exist_ok=True)
    if os.geteuid() != 0:
        folder.chmod(0o555)
        return []
    if shutil.which("unshare") is None:
        pytest.skip("running as root without unshare(1): no way to make a folder read-only")
    f = str(folder)
    probe = ["unshare", "-m", "sh", "-c", f"mount --bind {f} {f} && mount -o remount,bind,ro {f}"]
    if subprocess.run(probe, capture_output=True).returncode != 0:
        pytest.skip("running as root without CAP_SYS_ADMIN: no read-only bind mount")
    script = f'mount --bind {f} {f} && mount -o remount,bind,ro {f} && exec "$@"'
    return ["unshare", "-m", "sh", "-c", script, "sh"]


def test_a_read_only_empty_folder_gives_the_uncompiled_function(tmp_path):
    cache = tmp_path / "cache"
    wrap = _read_only(cache)
    out = _run(cache, wrap)
    assert out["path"] is None and not out["cached"]
    assert any(w.startswith("CompileWarning") and "is not writable" in w for w in out["warnings"])
    assert not list(cache.iterdir())
    cache.chmod(0o755)


def test_a_read_only_folder_with_a_damaged_entry_falls_back(built, tmp_path):
    cache = tmp_path / "cache"
    shutil.copytree(built[0], cache)
    _truncate(cache / built[1].name)
    out = _run(cache, _read_only(cache))
    assert out["path"] is None
    kinds = {w.split(":")[0] for w in out["warnings"]}
    assert kinds == {"CacheWarning", "CompileWarning"}, out
    cache.chmod(0o755)


def test_a_read_only_folder_with_a_verified_entry_is_used(built, tmp_path):
    cache = tmp_path / "cache"
    shutil.copytree(built[0], cache)
    out = _run(cache, _read_only(cache))
    assert out["cached"] and not out["warnings"]
    cache.chmod(0o755)


def test_verify_and_publish(tmp_path):
    entry, tmp = tmp_path / "f.bin", tmp_path / ".f.tmp"
    assert so_cache.verify(entry) == "missing" and not so_cache.usable(entry)
    tmp.write_bytes(b"abc")
    so_cache.publish(tmp, entry)
    assert not tmp.exists() and so_cache.verify(entry) is None
    assert json.loads(so_cache.sidecar(entry).read_text())["size"] == 3
    so_cache.sidecar(entry).write_text("not json")
    assert so_cache.verify(entry).startswith("its checksum record is unreadable")
    with pytest.warns(so_cache.CacheWarning, match="is not used: its checksum record"):
        assert not so_cache.usable(entry)


# The closure kernel at its compile point (the 1000th solve by default; here the first).
KERNEL = """
import json, warnings
import rcm_pin
from ocp.kernels import CHUNK, provider
from ocp.kernels.closure_kernel import ClosureNewtonKernel, SharedFunction
mech = rcm_pin.load("five_bar")
shared = provider.shared_function(mech)
fresh = SharedFunction(provider.newton_function(mech, vm=True), shared.key, 1)
kernel = ClosureNewtonKernel(fresh, CHUNK)
home = mech.home
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    out = kernel(home + 0.01, home[mech.loops.drive_q] + 0.02, max_iter=60, max_step=0.5)
print(json.dumps({
    "compiled": fresh.compiled, "q": out.q.tolist(),
    "warnings": [f"{w.category.__name__}: {w.message}" for w in caught],
}))
"""


def _kernel(cache: Path) -> dict:
    env = {**os.environ, "RCM_PIN_CACHE": str(cache), "PYTHONPATH": str(ROOT)}
    run = subprocess.run(
        [sys.executable, "-c", KERNEL], capture_output=True, text=True, env=env, timeout=600
    )
    assert run.returncode == 0, f"exit {run.returncode} (-7: SIGBUS): {run.stderr[-2000:]}"
    out: dict = json.loads(run.stdout.strip().splitlines()[-1])
    return out


def test_the_closure_kernel_rebuilds_a_truncated_library(tmp_path):
    cache = tmp_path / "cache"
    first = _kernel(cache)
    assert first["compiled"] and not first["warnings"], first
    (lib,) = cache.glob("closure_newton_*.so")
    _truncate(lib)
    again = _kernel(cache)
    assert again["compiled"] and again["q"] == first["q"]
    assert any(w.startswith("CacheWarning") for w in again["warnings"]), again
    assert so_cache.verify(lib) is None
