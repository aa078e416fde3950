"""The live viewer's server: local by default, gone with its parent (issue 26 items 2, 3),
and ``view`` of a one-joint URDF (item 7).

Addresses are read from the kernel's socket tables (/proc/net/tcp, tcp6), never from what
the command prints.
"""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import rcm_pin
from rcm_pin.cli import main
from rcm_pin.model.constraints import plane_normal

pytestmark = pytest.mark.skipif(
    not sys.platform.startswith("linux"), reason="reads Linux's /proc socket tables"
)
ROOT = Path(__file__).resolve().parents[1]
ONE_JOINT = """<?xml version="1.0"?>
<robot name="one">
  <link name="base"/>
  <link name="tip"><visual><geometry><box size="0.1 0.1 0.1"/></geometry></visual></link>
  <joint name="j1" type="revolute"><parent link="base"/><child link="tip"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


def _address(hex_address: str) -> tuple[str, int]:
    """(ip, port) of a /proc/net/tcp{,6} ``ADDR:PORT`` field."""
    ip_hex, port_hex = hex_address.split(":")
    raw = bytes.fromhex(ip_hex)
    words = [raw[i : i + 4][::-1] for i in range(0, len(raw), 4)]  # host-order 32-bit words
    packed = b"".join(words)
    import ipaddress

    ip = ipaddress.ip_address(packed)
    return str(ip), int(port_hex, 16)


def listening(pid: int) -> set[tuple[str, int]]:
    """The (ip, port) of every TCP socket process ``pid`` listens on."""
    inodes = set()
    for fd in Path(f"/proc/{pid}/fd").iterdir():
        try:
            target = os.readlink(fd)
        except OSError:
            continue
        if target.startswith("socket:["):
            inodes.add(target[8:-1])
    found = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for row in Path(table).read_text().splitlines()[1:]:
            cols = row.split()
            if cols[3] == "0A" and cols[9] in inodes:  # 0A: LISTEN
                found.add(_address(cols[1]))
    return found


def _listened_ports() -> set[int]:
    ports = set()
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for row in Path(table).read_text().splitlines()[1:]:
            cols = row.split()
            if cols[3] == "0A":
                ports.add(_address(cols[1])[1])
    return ports


def _children(pid: int) -> list[int]:
    out = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[1]) == pid:
            out.append(int(stat.parent.name))
    return out


def _alive(pid: int) -> bool:
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return False
    return state != "Z"


def _start_view(*extra: str) -> tuple[subprocess.Popen[str], dict, int]:
    """``rcm-pin view four_bar`` live in a subprocess: (process, its JSON, server pid)."""
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen(
        [sys.executable, "-m", "rcm_pin", "view", "four_bar", "--seconds", "120", "--json", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
        env=env,
    )
    assert proc.stdout is not None
    lines = []
    while not lines or lines[-1] != "}":
        line = proc.stdout.readline()
        assert line, "view exited before printing its JSON"
        lines.append(line.rstrip("\n"))
    servers = _children(proc.pid)
    assert len(servers) == 1
    return proc, json.loads("\n".join(lines)), servers[0]


def _gone_within(pid: int, port: int, seconds: float = 5.0) -> bool:
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        if not _alive(pid) and port not in _listened_ports():
            return True
        time.sleep(0.1)
    return False


def _port(url: str) -> int:
    return int(url.rsplit(":", 1)[1].split("/")[0])


@pytest.mark.parametrize("stop", [signal.SIGTERM, signal.SIGINT, signal.SIGKILL])
def test_the_live_viewer_is_local_and_its_server_dies_with_it(stop):
    proc, doc, server = _start_view()
    try:
        port = _port(doc["url"])
        bound = listening(server)
        assert (("127.0.0.1", port)) in bound
        assert {ip for ip, _ in bound} == {"127.0.0.1"}  # the web and the ZMQ sockets
        proc.send_signal(stop)
        proc.wait(timeout=10)
        assert _gone_within(server, port)
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode == {signal.SIGTERM: 143, signal.SIGINT: 0}.get(stop, -stop)


def test_host_opts_into_another_address():
    proc, doc, server = _start_view("--host", "127.0.0.2")
    try:
        port = _port(doc["url"])
        assert doc["url"] == f"http://127.0.0.2:{port}/static/"
        bound = listening(server)
        assert ("127.0.0.2", port) in bound  # the web viewer
        assert {ip for ip, p in bound if p != port} == {"127.0.0.1"}  # ZMQ stays local
    finally:
        proc.terminate()
        proc.wait()


def test_a_host_that_is_not_this_machines_is_a_typed_error(capsys):
    status = main(["view", "four_bar", "--host", "192.0.2.1", "--seconds", "0", "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert status == 2
    assert doc["error"]["type"] == "InvalidInputError"
    assert doc["error"]["message"].startswith(
        "the Meshcat server could not listen on host '192.0.2.1' ("
    )


def test_view_of_a_one_joint_urdf(tmp_path, capsys):
    path = tmp_path / "one.urdf"
    path.write_text(ONE_JOINT)
    mech = rcm_pin.load(path, tool_frame="tip")
    assert np.allclose(plane_normal(mech.model), [0.0, 0.0, 1.0])
    html = tmp_path / "one.html"
    status = main(["view", str(path), "--tool-frame", "tip", "--html", str(html), "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert status == 0
    assert doc["joint_names"] == ["j1"] and doc["html"] == str(html)
    assert "new MeshCat.Viewer" in html.read_text()
