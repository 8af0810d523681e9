"""What the sync and async clients share: framing, params, replies, the inbox."""

from __future__ import annotations

import array
import json
import os
import socket
from collections import deque
from dataclasses import dataclass
from typing import Any, Iterable, Mapping

from .errors import GportError, NoSlot, error_from_reply
from .results import Notification, parse_notification

DEFAULT_SOCKET = "/run/gportd.sock"
SOCKET_ENV = "GPORT_SOCKET"
TOPICS = ("attitude", "link", "motion")
# Notifications kept per topic while nobody reads them; the oldest go first.
INBOX_LIMIT = 1024
# Longest line accepted from the daemon.
LINE_LIMIT = 16 * 1024 * 1024


# Descriptors accepted per recvmsg (gportd sends two, with a connection's
# first attitude_channel reply); the kernel closes any beyond.
MAX_DESCRIPTORS = 8
_CONTROL_SPACE = socket.CMSG_SPACE(MAX_DESCRIPTORS * array.array("i").itemsize)
CHANNEL_METHOD = "attitude_channel"


def announced_descriptors(reply: Reply) -> int:
    """How many descriptors an attitude_channel reply says it carries (0 or
    2; anything else claims none and the result is refused later)."""
    result = reply.result
    if reply.error is not None or not isinstance(result, dict):
        return 0
    count = result.get("descriptors")
    return 2 if count == 2 and not isinstance(count, bool) else 0


def receive(sock: socket.socket, size: int = 65536) -> tuple[bytes, list[int]]:
    """One recvmsg (MSG_CMSG_CLOEXEC): the bytes and the descriptors that
    came with them (SCM_RIGHTS), in order. Empty bytes: the peer closed."""
    data, ancillary, _flags, _address = sock.recvmsg(
        size, _CONTROL_SPACE, socket.MSG_CMSG_CLOEXEC
    )
    fds: list[int] = []
    for level, kind, payload in ancillary:
        if level == socket.SOL_SOCKET and kind == socket.SCM_RIGHTS:
            numbers = array.array("i")
            numbers.frombytes(payload[: len(payload) - len(payload) % numbers.itemsize])
            fds.extend(numbers)
    return data, fds


class LineBuffer:
    """Splits the bytes read into lines (without the newline)."""

    def __init__(self) -> None:
        self._data = bytearray()

    def feed(self, data: bytes) -> list[bytes]:
        self._data += data
        if b"\n" not in data:
            if len(self._data) > LINE_LIMIT:
                raise ValueError(f"a line from the daemon is longer than {LINE_LIMIT} bytes")
            return []
        *lines, rest = self._data.split(b"\n")
        self._data = bytearray(rest)
        return [bytes(line) for line in lines]


class Descriptors:
    """Descriptors received on one connection, in arrival order, until an
    ``attitude_channel`` reply claims the ones it announced; keep() closes
    any beyond what the requests awaiting their reply may bring (two each),
    close() what nobody claimed (not thread-safe)."""

    def __init__(self) -> None:
        self._fds: deque[int] = deque()

    def extend(self, fds: Iterable[int]) -> None:
        self._fds.extend(fds)

    def take(self, count: int) -> list[int]:
        """Up to ``count`` of the oldest, now the caller's."""
        return [self._fds.popleft() for _ in range(min(count, len(self._fds)))]

    def keep(self, count: int) -> None:
        """Closes the newest beyond the first ``count`` (nobody asked for them)."""
        while len(self._fds) > count:
            close_quietly(self._fds.pop())

    def __len__(self) -> int:
        return len(self._fds)

    def close(self) -> None:
        while self._fds:
            close_quietly(self._fds.popleft())


def close_quietly(fd: int | None) -> None:
    if fd is not None:
        try:
            os.close(fd)
        except OSError:
            pass


def socket_path(path: str | os.PathLike[str] | None) -> str:
    """The path given, else $GPORT_SOCKET, else /run/gportd.sock."""
    if path is not None:
        return os.fspath(path)
    return os.environ.get(SOCKET_ENV) or DEFAULT_SOCKET


def encode(request_id: int, method: str, params: Mapping[str, Any] | None) -> bytes:
    message: dict[str, Any] = {"jsonrpc": "2.0", "id": request_id, "method": method}
    if params:
        message["params"] = dict(params)
    return (json.dumps(message, separators=(",", ":")) + "\n").encode()


@dataclass(frozen=True)
class Reply:
    """A reply to one of our requests: ``result`` or ``error``."""

    id: int
    result: Any = None
    error: GportError | None = None


@dataclass(frozen=True)
class Pushed:
    """A notification the daemon pushed."""

    topic: str
    item: Notification


@dataclass(frozen=True)
class Refused:
    """An error with ``id`` null: the daemon closes the connection after it."""

    error: GportError


Message = Reply | Pushed | Refused | None


def decode(line: bytes) -> Message:
    """Classifies one line from the daemon; None for what this client ignores."""
    try:
        message = json.loads(line)
    except ValueError:
        return None
    if not isinstance(message, dict):
        return None
    method = message.get("method")
    if isinstance(method, str):
        params = message.get("params")
        item = parse_notification(method, params) if isinstance(params, dict) else None
        return None if item is None else Pushed(method, item)
    request_id = message.get("id")
    error = message.get("error")
    if isinstance(request_id, int) and not isinstance(request_id, bool):
        if isinstance(error, dict):
            return Reply(request_id, error=error_from_reply(error))
        return Reply(request_id, result=message.get("result"))
    if isinstance(error, dict):
        return Refused(error_from_reply(error))
    return None


def closed_message(refused: GportError | None) -> str:
    if refused is None:
        return "the daemon closed the connection"
    kind = "refused the connection" if isinstance(refused, NoSlot) else "closed the connection"
    return f"the daemon {kind}: {refused.message} ({refused.code})"


def drop_none(**params: Any) -> dict[str, Any]:
    return {k: v for k, v in params.items() if v is not None}


def speed_params(
    roll: float,
    pitch: float,
    yaw: float,
    duration_ms: int | None,
    lease_ms: int | None,
    clamp: bool,
) -> dict[str, Any]:
    return drop_none(
        roll=roll,
        pitch=pitch,
        yaw=yaw,
        duration_ms=duration_ms,
        lease_ms=lease_ms,
        clamp=True if clamp else None,
    )


def angle_params(roll: float, pitch: float, yaw: float, clamp: bool, wait: bool) -> dict[str, Any]:
    # `wait` is sent only when true, so that daemons without it still answer.
    return drop_none(
        roll=roll, pitch=pitch, yaw=yaw, clamp=True if clamp else None, wait=True if wait else None
    )


def record_params(on: bool | None, force: bool) -> dict[str, Any]:
    if force and on is None:
        raise ValueError("record(force=True) needs on=True or on=False")
    return drop_none(on=on, force=True if force else None)


def settings_params(
    dead_zone: int | None, follow_speed: int | None, inverted: bool | None
) -> dict[str, Any]:
    params = drop_none(dead_zone=dead_zone, follow_speed=follow_speed, inverted=inverted)
    if not params:
        raise ValueError("set_settings needs at least one of dead_zone, follow_speed, inverted")
    return params


def topic_list(topics: str | Iterable[str]) -> list[str]:
    return [topics] if isinstance(topics, str) else list(topics)


def subscribe_params(topics: str | Iterable[str], max_rate_hz: float | None) -> dict[str, Any]:
    return drop_none(topics=topic_list(topics), max_rate_hz=max_rate_hz)


def keepalive_interval(lease_ms: int) -> float:
    """Seconds between re-sends of a ``moving`` speed: three per lease."""
    if lease_ms < 30:
        raise ValueError(f"lease_ms = {lease_ms} is too short for moving(); allowed 30 or more")
    return lease_ms / 3000.0


class Inbox:
    """Notifications waiting to be read, per topic, in arrival order (not thread-safe)."""

    def __init__(self) -> None:
        self._queues: dict[str, deque[tuple[int, Notification]]] = {}
        self._seq = 0

    def put(self, topic: str, item: Notification) -> None:
        queue = self._queues.setdefault(topic, deque(maxlen=INBOX_LIMIT))
        self._seq += 1
        queue.append((self._seq, item))

    def take(self, topics: Iterable[str] | None) -> Notification | None:
        """The oldest waiting notification of the topics (all when None), or None."""
        best: deque[tuple[int, Notification]] | None = None
        for topic, queue in self._queues.items():
            if queue and (topics is None or topic in topics):
                if best is None or queue[0][0] < best[0][0]:
                    best = queue
        return None if best is None else best.popleft()[1]

    def clear(self, topics: Iterable[str] | None = None) -> None:
        for topic, queue in self._queues.items():
            if topics is None or topic in topics:
                queue.clear()
