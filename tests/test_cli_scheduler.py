"""``--scheduler`` at a server that is not a Dask scheduler: a typed error (exit status 2)
within seconds, before ``distributed`` reads it (rcm_pin.design.scheduler)."""

from __future__ import annotations

import http.server
import json
import socket
import socketserver
import subprocess
import sys
import threading
import time
from collections.abc import Iterator

import pytest

from rcm_pin.cli import main
from rcm_pin.design.scheduler import HANDSHAKE_TIMEOUT, check_scheduler
from rcm_pin.errors import InvalidInputError

SWEEP = ["sweep", "rcm_bevel", "--vary", "q2_limit=0.8:1.2:2", "--metric", "cone_coverage"]
PREFIX = "no Dask scheduler answered ("
VALID = "valid: the address of a running Dask scheduler, e.g. tcp://127.0.0.1:8786"


class _Garbage(socketserver.BaseRequestHandler):
    def handle(self) -> None:  # what made distributed allocate 2.82 EiB
        self.request.sendall(b"\xfe\xff\xff\xff\xff\xff\xff\x27garbage" * 8)
        time.sleep(0.5)


class _Http(http.server.BaseHTTPRequestHandler):
    def do_GET(self) -> None:
        self.send_response(200)
        self.end_headers()

    def log_message(self, *args: object) -> None:
        pass


def _serve(handler: type) -> Iterator[str]:
    server = socketserver.ThreadingTCPServer(("127.0.0.1", 0), handler)
    server.daemon_threads = True
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"tcp://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


@pytest.fixture
def garbage() -> Iterator[str]:
    yield from _serve(_Garbage)


@pytest.fixture
def http_server() -> Iterator[str]:
    yield from _serve(_Http)


def _closed_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.mark.parametrize(
    ("server", "why"),
    [
        ("garbage", "the server's first bytes are not a Dask handshake: a frame of "),
        ("http_server", f"the server sent no handshake within {HANDSHAKE_TIMEOUT:g} s"),
    ],
)
@pytest.mark.timeout(HANDSHAKE_TIMEOUT + 30)  # a hang fails by the timeout, not a timing
def test_cli_sweep_at_a_non_dask_server_exits_2_within_seconds(capsys, request, server, why):
    address = request.getfixturevalue(server)
    code = main([*SWEEP, "--scheduler", address, "--json"])
    doc = json.loads(capsys.readouterr().out)
    assert code == 2 and doc["error"]["type"] == "InvalidInputError"
    message = doc["error"]["message"]
    assert message.startswith(f"--scheduler {address!r}: {PREFIX}{why}"), message
    assert message.endswith(VALID)


def test_nothing_listening_and_malformed_addresses():
    address = f"tcp://127.0.0.1:{_closed_port()}"
    with pytest.raises(InvalidInputError) as exc:
        check_scheduler(address)
    assert str(exc.value).startswith(f"--scheduler {address!r}: {PREFIX}cannot connect within")
    for bad in ("tcp://127.0.0.1", "tcp://:8786", "tcp://host:99999", "host:port"):
        with pytest.raises(InvalidInputError) as exc:
            check_scheduler(bad)
        assert str(exc.value) == f"--scheduler {bad!r} is not tcp://HOST:PORT; {VALID}"
    assert check_scheduler("inproc://192.168.0.1/1/1") == "inproc://192.168.0.1/1/1"


def test_a_closing_server_is_refused():
    class Close(socketserver.BaseRequestHandler):
        def handle(self) -> None:
            self.request.sendall(b"abc")

    for address in _serve(Close):
        with pytest.raises(InvalidInputError) as exc:
            check_scheduler(address)
        assert f"{PREFIX}the server closed the connection after 3 bytes" in str(exc.value)


def test_a_real_scheduler_passes():
    pytest.importorskip("distributed", reason="the [design] extra's Dask is not installed")
    port = _closed_port()
    cmd = [sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1"]
    proc = subprocess.Popen(
        [*cmd, "--port", str(port), "--no-dashboard"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    try:
        deadline = time.monotonic() + 60
        while True:
            try:
                socket.create_connection(("127.0.0.1", port), timeout=1).close()
                break
            except OSError:
                assert time.monotonic() < deadline and proc.poll() is None, "no scheduler"
                time.sleep(0.2)
        address = f"tcp://127.0.0.1:{port}"
        assert check_scheduler(address) == address
        assert check_scheduler(f"127.0.0.1:{port}") == f"127.0.0.1:{port}"
    finally:
        proc.terminate()
        proc.wait(timeout=30)
