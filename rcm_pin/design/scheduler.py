"""A Dask scheduler address checked before ``distributed.Client`` is given it.

``distributed`` trusts the first bytes a server sends: a TCP server that sends anything
else made it allocate what they announce (2.82 EiB for some garbage), and an HTTP server,
which waits for a request, made it wait past a minute. :func:`check_scheduler` connects
first with a timeout (:data:`CONNECT_TIMEOUT`) and reads the handshake that a Dask
scheduler sends as soon as a connection opens (:data:`HANDSHAKE_TIMEOUT`): an 8-byte
little-endian length N (at most :data:`MAX_HANDSHAKE`), then N bytes of frames (a frame
count, the frame lengths, and a msgpack map as the first frame). Anything else is an
:class:`~rcm_pin.errors.InvalidInputError` (exit status 2: the address is bad input, not
a failed computation), raised within a few seconds.

Only ``tcp://HOST:PORT`` and ``HOST:PORT`` are checked; other Dask transports (``tls://``,
``ws://``, ``ucx://``, ``inproc://``) are passed on as given.
"""

from __future__ import annotations

import socket
import struct

from rcm_pin.errors import InvalidInputError

#: Seconds to open the TCP connection.
CONNECT_TIMEOUT = 3.0
#: Seconds to receive the scheduler's handshake once connected.
HANDSHAKE_TIMEOUT = 3.0
#: Largest handshake accepted [bytes] (a scheduler's is about 60).
MAX_HANDSHAKE = 1 << 16
#: Transports passed on unchecked.
UNCHECKED = ("tls://", "ws://", "wss://", "ucx://", "inproc://")

_VALID = "valid: the address of a running Dask scheduler, e.g. tcp://127.0.0.1:8786"


def _host_port(address: str) -> tuple[str, int]:
    rest = address.removeprefix("tcp://")
    host, sep, port = rest.rpartition(":")
    host = host.strip("[]")
    if not sep or not host or not port.isdigit() or not 0 < int(port) < 65536:
        raise InvalidInputError(f"--scheduler {address!r} is not tcp://HOST:PORT; {_VALID}")
    return host, int(port)


def _read(sock: socket.socket, n: int) -> bytes:
    data = b""
    while len(data) < n:
        block = sock.recv(n - len(data))
        if not block:
            break
        data += block
    return data


def _frames_ok(body: bytes) -> bool:
    """Whether ``body`` is a frame count, frame lengths that add up, and a msgpack map."""
    if len(body) < 8:
        return False
    (count,) = struct.unpack("<Q", body[:8])
    head = 8 * (1 + count)
    if not 1 <= count <= 64 or len(body) < head:
        return False
    lengths = struct.unpack(f"<{count}Q", body[8:head])
    first = body[head : head + 1]
    return (
        head + sum(lengths) == len(body)
        and first != b""
        and (0x80 <= first[0] <= 0x8F or first[0] in (0xDE, 0xDF))
    )


def check_scheduler(address: str) -> str:
    """``address`` once a Dask scheduler has answered there with its handshake.

    Raises:
        InvalidInputError: a malformed address, nothing listening, no answer within
            :data:`HANDSHAKE_TIMEOUT` (e.g. an HTTP server), or an answer that is not a
            Dask handshake: "--scheduler ADDR: no Dask scheduler answered (why); valid: ...".
    """
    if address.startswith(UNCHECKED):
        return address
    host, port = _host_port(address)
    why = _why_not(host, port)
    if why is not None:
        raise InvalidInputError(
            f"--scheduler {address!r}: no Dask scheduler answered ({why}); {_VALID}"
        )
    return address


def _why_not(host: str, port: int) -> str | None:
    """Why no Dask scheduler answered at (host, port), or None when one did."""
    try:
        sock = socket.create_connection((host, port), timeout=CONNECT_TIMEOUT)
    except OSError as exc:
        return f"cannot connect within {CONNECT_TIMEOUT:g} s: {exc}"
    with sock:
        sock.settimeout(HANDSHAKE_TIMEOUT)
        try:
            head = _read(sock, 8)
            size = struct.unpack("<Q", head)[0] if len(head) == 8 else None
            body = _read(sock, size) if size is not None and size <= MAX_HANDSHAKE else b""
        except TimeoutError:
            return (
                f"the server sent no handshake within {HANDSHAKE_TIMEOUT:g} s: an HTTP or "
                "other server that waits for a request"
            )
        except OSError as exc:
            return f"the connection failed: {exc}"
    if size is None:
        return f"the server closed the connection after {len(head)} bytes, before a handshake"
    if size > MAX_HANDSHAKE or len(body) != size or not _frames_ok(body):
        return (
            f"the server's first bytes are not a Dask handshake: a frame of {size} bytes "
            f"announced, a handshake has at most {MAX_HANDSHAKE}"
            if size > MAX_HANDSHAKE
            else "the server's first bytes are not a Dask handshake"
        )
    return None


__all__ = ["CONNECT_TIMEOUT", "HANDSHAKE_TIMEOUT", "MAX_HANDSHAKE", "check_scheduler"]
