"""What the sync and async clients share: framing, replies, the inbox (what
each method sends and reads: _calls)."""

from __future__ import annotations

import array
import itertools
import json
import os
import re
import socket
from collections import deque
from dataclasses import dataclass
from typing import Any, Iterable, Iterator, Mapping

from .errors import GportError, NoSlot, error_from_reply
from .results import Notification, parse_notification

DEFAULT_SOCKET = "/run/gportd.sock"
SOCKET_ENV = "GPORT_SOCKET"
TOPICS = ("attitude", "link", "motion", "capture")
# Notifications kept per topic while nobody reads them; the oldest go first.
INBOX_LIMIT = 1024
# Bytes of notification lines kept in all (as the C++ client's kQueueBytes):
# a daemon cannot fill memory with long lines (json.loads of such a line can
# take some 24 bytes per byte); the oldest of any topic go first, and the
# newest stays even alone over the bound.
INBOX_BYTES = 16 * 1024 * 1024
# What a sample from the shared-memory ring counts (about its line's length).
RING_SAMPLE_BYTES = 256
# Longest line accepted from the daemon, in bytes without the newline (as the
# C++ client's kLineLimit); a longer one ends the connection.
LINE_LIMIT = 16 * 1024 * 1024
# Deepest nesting of arrays and objects accepted in a line (gportd's replies
# nest 6 deep; as the C++ client's kNestingLimit), checked before json.loads,
# which recurses; a deeper line ends the connection.
NESTING_LIMIT = 64
# Seconds added to the timeout of calls with wait=True, whose reply comes when
# the motion ends: gportd ends it by motion.timeout_ms, at most 600 s.
WAIT_ALLOWANCE = 600.0
# How much of a decoder's message an error quotes (ConnectionLost, a result not read).
_DETAIL_CHARS = 200


class BadLine(Exception):
    """A line from the daemon that the client cannot take: the connection
    ends with ConnectionLost carrying ``reason``."""

    def __init__(self, what: str) -> None:
        self.reason = f"the daemon sent {what}; the connection is closed"
        super().__init__(self.reason)


def short(detail: object) -> str:
    text = str(detail)
    return text if len(text) <= _DETAIL_CHARS else text[:_DETAIL_CHARS] + "..."


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
    """Splits the bytes read into lines (without the newline). It holds at
    most LINE_LIMIT bytes and one read: each byte is looked at a bounded
    number of times, whatever the daemon sends."""

    def __init__(self) -> None:
        self._data = bytearray()

    def feed(self, data: bytes) -> Iterator[bytes]:
        """The lines ``data`` completes, in order; raises BadLine on reaching
        a line longer than LINE_LIMIT (the incomplete one included)."""
        lines: list[bytearray] = []
        self._data += data
        if b"\n" in data:
            *lines, rest = self._data.split(b"\n")
            self._data = bytearray(rest)
        for line in lines:
            _check_length(len(line))
            yield bytes(line)
        _check_length(len(self._data))


def _check_length(length: int) -> None:
    if length > LINE_LIMIT:
        raise BadLine(f"a line longer than {LINE_LIMIT} bytes (the client's line limit)")


_NOT_BRACKETS = bytes(range(256)).translate(None, b"[]{}")
_BRACKET_SIGNS = bytes.maketrans(b"[]{}", b"\x01\xff\x01\xff")  # +1 / -1 as signed bytes
_STRING = re.compile(rb'"[^"]*"')  # once the escapes are gone


def nested_deeper_than(line: bytes, limit: int) -> bool:
    """True when arrays and objects nest deeper than ``limit`` in the JSON
    text ``line`` (brackets in strings do not count). Linear, at C speed:
    the escapes and the strings are removed, then the depth is the running
    sum of +1 per opening and -1 per closing bracket."""
    if line.count(b"[") + line.count(b"{") <= limit:
        return False  # gportd's lines: no scan
    outside = _STRING.sub(b"", line.replace(b"\\\\", b"").replace(b'\\"', b""))
    signs = array.array("b", outside.translate(_BRACKET_SIGNS, _NOT_BRACKETS))
    return max(itertools.accumulate(signs), default=0) > limit


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
    size: int  # the line's length, what the inbox counts


@dataclass(frozen=True)
class Refused:
    """An error with ``id`` null: the daemon closes the connection after it."""

    error: GportError


Message = Reply | Pushed | Refused | None


def decode(line: bytes) -> Message:
    """Classifies one line from the daemon; None for what this client ignores
    (a blank line, a notification of a topic it does not know). Raises
    BadLine naming what is wrong: not UTF-8, nested deeper than
    NESTING_LIMIT, not JSON, not a JSON object, neither a reply nor a
    notification nor a refusal, a notification that does not decode."""
    if line in (b"", b"\r"):
        return None
    try:
        text = line.decode("utf-8")
    except UnicodeDecodeError as error:
        raise BadLine(f"a line that is not UTF-8 ({error.reason} at byte {error.start})") from None
    if nested_deeper_than(line, NESTING_LIMIT):
        raise BadLine(
            f"a line nested deeper than {NESTING_LIMIT} levels (the client's nesting limit)"
        )
    try:
        message = json.loads(text)
    except RecursionError:
        raise BadLine("a line nested too deeply for the JSON decoder (RecursionError)") from None
    except ValueError as error:
        raise BadLine(f"a line that is not JSON ({short(error)})") from None
    if not isinstance(message, dict):
        raise BadLine(f"a line that is not a JSON object ({type(message).__name__})")
    if "method" in message:
        return _notification(message, len(line))
    return _reply(message)


def _notification(message: dict[str, Any], size: int) -> Pushed | None:
    method, params = message["method"], message.get("params")
    if not isinstance(method, str):
        raise BadLine(f"a notification whose method is not a string ({type(method).__name__})")
    if method not in TOPICS:
        return None  # a topic newer than this client
    if not isinstance(params, dict):
        raise BadLine(f"a {method} notification whose params are not an object")
    try:
        item = parse_notification(method, params)
    except (KeyError, TypeError, ValueError, AttributeError, OverflowError) as error:
        raise BadLine(f"a {method} notification this client cannot read ({short(repr(error))})")
    assert item is not None  # every topic of TOPICS parses
    return Pushed(method, item, size)


def _reply(message: dict[str, Any]) -> Reply | Refused:
    if "id" not in message:
        raise BadLine("a message with neither an id nor a method")
    request_id, error = message["id"], message.get("error")
    if request_id is None:
        if not isinstance(error, dict):
            raise BadLine("a message with a null id and no error object")
        return Refused(error_from_reply(error))
    if not isinstance(request_id, int) or isinstance(request_id, bool):
        raise BadLine(f"a reply whose id is not an integer ({type(request_id).__name__})")
    if "error" in message:
        if not isinstance(error, dict):
            raise BadLine(f"a reply whose error is not an object ({type(error).__name__})")
        return Reply(request_id, error=error_from_reply(error))
    if "result" not in message:
        raise BadLine("a reply with neither a result nor an error")
    return Reply(request_id, result=message["result"])


def closed_message(refused: GportError | None, reason: str | None = None) -> str:
    """Why the connection is gone: the client's reason (a bad line, a request
    the daemon did not read), else the refusal the daemon sent, if any."""
    if reason is not None:
        return reason
    if refused is None:
        return "the daemon closed the connection"
    kind = "refused the connection" if isinstance(refused, NoSlot) else "closed the connection"
    return f"the daemon {kind}: {refused.message} ({refused.code})"


def drop_none(**params: Any) -> dict[str, Any]:
    return {k: v for k, v in params.items() if v is not None}


def topic_list(topics: str | Iterable[str]) -> list[str]:
    return [topics] if isinstance(topics, str) else list(topics)


def reply_limit(timeout: float | None, wait: bool) -> float | None:
    """Seconds to wait for a reply: the client's timeout, plus WAIT_ALLOWANCE
    for calls with wait=True; None: no limit."""
    if timeout is None:
        return None
    return timeout + WAIT_ALLOWANCE if wait else timeout


def keepalive_interval(lease_ms: int) -> float:
    """Seconds between re-sends of a ``moving`` speed: three per lease."""
    if lease_ms < 30:
        raise ValueError(f"lease_ms = {lease_ms} is too short for moving(); allowed 30 or more")
    return lease_ms / 3000.0


class Inbox:
    """Notifications waiting to be read, per topic, in arrival order; at most
    INBOX_LIMIT per topic and INBOX_BYTES of lines in all, the oldest dropped
    and counted (not thread-safe)."""

    def __init__(self) -> None:
        self._queues: dict[str, deque[tuple[int, Notification, int]]] = {}
        self._seq = 0
        self._count = 0
        self._bytes = 0
        self.dropped = 0

    def put(self, topic: str, item: Notification, size: int = RING_SAMPLE_BYTES) -> None:
        """Queues ``item``; ``size``: its line's length."""
        queue = self._queues.setdefault(topic, deque())
        if len(queue) == INBOX_LIMIT:
            self._pop(queue)
            self.dropped += 1
        self._seq += 1
        queue.append((self._seq, item, size))
        self._count += 1
        self._bytes += size
        while self._bytes > INBOX_BYTES and self._count > 1:
            self._pop(self._oldest(None) or queue)
            self.dropped += 1

    def take(self, topics: Iterable[str] | None) -> Notification | None:
        """The oldest waiting notification of the topics (all when None), or None."""
        queue = self._oldest(topics)
        return None if queue is None else self._pop(queue)

    def clear(self, topics: Iterable[str] | None = None) -> None:
        for topic, queue in self._queues.items():
            if topics is None or topic in topics:
                while queue:
                    self._pop(queue)

    def _oldest(
        self, topics: Iterable[str] | None
    ) -> deque[tuple[int, Notification, int]] | None:
        best: deque[tuple[int, Notification, int]] | None = None
        for topic, queue in self._queues.items():
            if queue and (topics is None or topic in topics):
                if best is None or queue[0][0] < best[0][0]:
                    best = queue
        return best

    def _pop(self, queue: deque[tuple[int, Notification, int]]) -> Notification:
        _, item, size = queue.popleft()
        self._count -= 1
        self._bytes -= size
        return item
