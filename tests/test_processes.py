"""rcm_pin.processes: the folder lock, atomic writes, pool workers tied to their run."""

from __future__ import annotations

import os

import pytest

from rcm_pin.errors import InvalidInputError
from rcm_pin.processes import (
    atomic_write,
    folder_lock,
    lock_holder,
    process_pool,
    remove_temporaries,
)


def test_the_lock_records_its_holder_and_is_reentrant(tmp_path):
    with folder_lock(tmp_path):
        assert lock_holder(tmp_path) == os.getpid()
        with folder_lock(tmp_path):  # the same process again: no deadlock, no error
            assert lock_holder(tmp_path) == os.getpid()
    assert lock_holder(tmp_path) is None  # released: the file is emptied


def test_a_folder_without_a_lock_file_is_a_typed_error(tmp_path):
    missing = r"--out .*/missing: cannot open its lock file"
    with pytest.raises(InvalidInputError, match=missing), folder_lock(tmp_path / "missing"):
        pass


def test_an_atomic_write_that_fails_leaves_the_old_file_and_no_temporary(tmp_path):
    path = atomic_write(tmp_path / "table.bin", b"old")
    with pytest.raises(TypeError):
        atomic_write(path, "not bytes")  # type: ignore[arg-type]
    assert path.read_bytes() == b"old" and sorted(tmp_path.iterdir()) == [path]
    assert oct(path.stat().st_mode & 0o777) == oct(0o666 & ~_umask())


def test_temporaries_of_a_killed_write_are_removed_and_nothing_else(tmp_path):
    (tmp_path / ".table.bin.k3j.tmp").write_bytes(b"half")
    (tmp_path / "kept.tmp").write_bytes(b"a user's file")
    atomic_write(tmp_path / "table.bin", b"whole")
    assert remove_temporaries(tmp_path) == 1
    assert sorted(p.name for p in tmp_path.iterdir()) == ["kept.tmp", "table.bin"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _parent_death_signal() -> int:
    """The signal this process gets when its parent dies (prctl PR_GET_PDEATHSIG)."""
    import ctypes

    libc = ctypes.CDLL(None)
    sig = ctypes.c_int()
    libc.prctl(2, ctypes.byref(sig), 0, 0, 0)  # PR_GET_PDEATHSIG
    return sig.value


@pytest.mark.skipif(not os.path.isdir("/proc"), reason="PR_SET_PDEATHSIG is Linux only")
def test_pool_workers_ask_for_sigkill_when_their_parent_dies():
    with process_pool(1, []) as pool:
        assert pool.submit(_parent_death_signal).result() == 9  # SIGKILL
