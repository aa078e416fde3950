"""A local Meshcat server: on 127.0.0.1 unless asked otherwise, and dying with its parent.

``meshcat-server`` (and ``meshcat.Visualizer()``, which starts one) binds its web server
to every interface (tornado's ``listen(port)``) and runs in a session of its own, so it
outlives a parent stopped by a signal. :func:`start_server` runs this module instead: the
web server listens on ``host`` only (default 127.0.0.1), the ZMQ command socket always on
127.0.0.1, and on Linux the server gets SIGTERM when the process that started it dies
(``prctl(PR_SET_PDEATHSIG)``); elsewhere it is stopped at exit.

Run as ``python -m rcm_pin.viz.server --host HOST`` it prints ``zmq_url=...`` and
``web_url=...`` lines, as ``meshcat-server`` does.
"""

from __future__ import annotations

import argparse
import atexit
import contextlib
import ctypes
import os
import signal
import socket
import subprocess
import sys
import tempfile
import warnings
from collections.abc import Sequence
from typing import Any

from rcm_pin.errors import InvalidInputError

#: Default host of every server rcm-pin starts: this machine only.
LOCAL_HOST = "127.0.0.1"
_PR_SET_PDEATHSIG = 1
_LIBC: Any = None
if sys.platform.startswith("linux"):
    try:
        _LIBC = ctypes.CDLL(None, use_errno=True)
    except OSError:  # no libc symbols in this process: fall back on atexit
        _LIBC = None


def _die_with_parent(parent: int) -> None:
    """In the child before exec: SIGTERM when the parent dies (Linux)."""
    if _LIBC is not None:
        _LIBC.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM)
    if os.getppid() != parent:  # the parent died before prctl took effect
        os.kill(os.getpid(), signal.SIGTERM)


def url_host(host: str) -> str:
    """``host`` as written in a URL (IPv6 addresses in brackets)."""
    return f"[{host}]" if ":" in host else host


def start_server(host: str = LOCAL_HOST) -> tuple[subprocess.Popen[bytes], str, str]:
    """Start a Meshcat server whose web viewer listens on ``host``.

    Args:
        host: the address the web server binds (127.0.0.1: this machine only).

    Returns:
        (process, zmq_url, web_url).

    Raises:
        InvalidInputError: the server could not listen on ``host`` (the message has its
            error output).
    """
    cmd = [sys.executable, "-u", "-m", "rcm_pin.viz.server", "--host", host]
    parent, errors = os.getpid(), tempfile.TemporaryFile()  # noqa: SIM115 (closed below)
    proc = subprocess.Popen(
        cmd,
        stdin=subprocess.DEVNULL,
        stdout=subprocess.PIPE,
        stderr=errors,
        start_new_session=True,  # a Ctrl-C meant for a notebook cell does not stop it
        preexec_fn=lambda: _die_with_parent(parent),
    )
    atexit.register(stop_server, proc)
    assert proc.stdout is not None
    lines: dict[str, str] = {}
    while len(lines) < 2:
        line = proc.stdout.readline().decode().strip()
        if not line:
            stop_server(proc)
            errors.seek(0)
            err = errors.read().decode(errors="replace").strip()
            last = err.splitlines()[-1] if err else f"exit status {proc.returncode}"
            raise InvalidInputError(
                f"the Meshcat server could not listen on host {host!r} ({last}); valid: an "
                f"address of this machine, e.g. {LOCAL_HOST} (the default)"
            )
        key, sep, value = line.partition("=")
        if sep and key in ("zmq_url", "web_url"):
            lines[key] = value
    errors.close()  # the server keeps writing to the (now unnamed) file
    return proc, lines["zmq_url"], lines["web_url"]


def stop_server(proc: subprocess.Popen[bytes]) -> None:
    """Stop a server of :func:`start_server` (no-op when it has already exited)."""
    if proc.poll() is None:
        proc.kill()
    proc.wait()
    if proc.stdout is not None:
        proc.stdout.close()


def main(argv: Sequence[str] | None = None) -> None:
    """Serve Meshcat with the web server on ``--host`` and ZMQ on 127.0.0.1."""
    parser = argparse.ArgumentParser(prog="python -m rcm_pin.viz.server")
    parser.add_argument("--host", default=LOCAL_HOST, help="web server address (127.0.0.1)")
    host = parser.parse_args(argv).host
    try:  # fail at once (not after 1000 ports) on an address that is not this machine's
        family = socket.getaddrinfo(host, None)[0][0]
        with socket.socket(family, socket.SOCK_STREAM) as probe:
            probe.bind((host, 0))
    except OSError as exc:
        sys.exit(f"cannot listen on {host!r}: {exc}")
    with warnings.catch_warnings():  # meshcat imports pyzmq's deprecated zmq.eventloop.ioloop
        warnings.simplefilter("ignore", DeprecationWarning)
        from meshcat.servers.zmqserver import ZMQWebSocketBridge

    class Bridge(ZMQWebSocketBridge):  # type: ignore[misc]
        def make_app(self) -> Any:
            app = super().make_app()
            listen = app.listen
            app.listen = lambda port, **kw: listen(port, address=host, **kw)
            return app

    bridge = Bridge(host=LOCAL_HOST)  # host: the ZMQ socket (web server: make_app)
    bridge.web_url = f"http://{url_host(host)}:{bridge.fileserver_port}/static/"
    print(f"zmq_url={bridge.zmq_url}")
    print(f"web_url={bridge.web_url}")
    with contextlib.suppress(KeyboardInterrupt):
        bridge.run()


if __name__ == "__main__":
    main()


__all__ = ["LOCAL_HOST", "main", "start_server", "stop_server", "url_host"]
