"""The shared-memory attitude channel (docs/api.md, "Shared-memory attitude
channel"): gportd hands a connection two read-only memory blocks, a ring of
the latest attitude samples and a wake block of the connection's own, and
wakes one of the connection's waiting threads per sample; the readers of
this process pass the wake on to each other (_ring.py has the layouts, the
checks and the reads).

A connection receives the blocks once, with its first ``attitude_channel``
reply (``"descriptors":2``); the client caches the mapping, and every later
``attitude_channel()`` (``"descriptors":0``) is a new reader of it, with its
own cursor.
"""

from __future__ import annotations

import threading
import time
from typing import Any, Callable, Iterable, Sequence

from . import _protocol as p
from . import _ring
from ._ring import FLAG_CLOSED, HEADER_SIZE, MAGIC, SLOT_SIZE, VERSION, futex_available
from .errors import BadChannel
from .results import Attitude, Axes, ImuRates, Rates

__all__ = [
    "AttitudeChannel",
    "ChannelClaims",
    "RingPump",
    "channel_from",
    "futex_available",
    "FLAG_CLOSED",
    "HEADER_SIZE",
    "MAGIC",
    "SLOT_SIZE",
    "VERSION",
]

_PUMP_SLICE = 0.5  # RingPump looks at its stop flag at least this often


def channel_from(
    result: Any, fds: Sequence[int], cached: _ring.Mapping | None
) -> tuple[AttitudeChannel, _ring.Mapping]:
    """The channel an attitude_channel result announces, and the mapping the
    connection caches from now on: with ``"descriptors":2`` a new mapping of
    ``fds`` (the ring, then the wake block), with 0 the cached one. Closes
    every descriptor in ``fds``; BadChannel naming what is wrong."""
    try:
        slots, size, descriptors = _ring.reply_fields(result)
        if descriptors == 0:
            if cached is None:
                raise BadChannel(
                    'attitude channel: gportd sent no descriptors ("descriptors":0: this '
                    "connection should have them already) and this connection has none; "
                    "reconnect to get them"
                )
            return AttitudeChannel(cached), cached
        if len(fds) < 2:
            raise BadChannel(
                f"attitude channel: gportd's reply carried {len(fds)} file descriptor(s), "
                "not the 2 it announced"
            )
        mapping = _ring.Mapping(fds[0], fds[1], slots, size)
        return AttitudeChannel(mapping), mapping
    finally:
        for fd in fds:
            _close(fd)


def _close(fd: int) -> None:
    import os

    try:
        os.close(fd)
    except OSError:
        pass


class ChannelClaims:
    """The descriptors of one connection's attitude_channel replies, for
    both clients: which may be kept, which reply claims them, and the
    connection's mapping once it has one (not thread-safe: the client holds
    its lock).

    gportd attaches the two descriptors of a connection's channel to that
    connection's first attitude_channel result and to no other message, so
    two are kept only while the connection has no mapping and at least one
    attitude_channel request has a caller waiting for its reply; any other
    is closed as soon as it is received. A request whose caller gave up (a
    timeout, an interruption) no longer counts, and the descriptors its late
    reply carries are closed."""

    def __init__(self) -> None:
        self._fds = p.Descriptors()
        self._waiting: set[int] = set()
        self._abandoned: set[int] = set()
        self._claimed: dict[int, list[int]] = {}
        self._mapping: _ring.Mapping | None = None

    def expect(self, request_id: int) -> None:
        """An attitude_channel request goes out with this id."""
        self._waiting.add(request_id)

    def received(self, fds: Iterable[int]) -> None:
        """Descriptors one recvmsg received (before its lines are handled)."""
        self._fds.extend(fds)
        self._keep()

    def reply(self, reply: p.Reply) -> None:
        """Every reply, in arrival order: an awaited attitude_channel reply
        claims the descriptors it announced (they came with its first
        byte), an abandoned one's are closed."""
        if reply.id in self._waiting:
            self._waiting.discard(reply.id)
            self._claimed[reply.id] = self._fds.take(p.announced_descriptors(reply))
        elif reply.id in self._abandoned:
            self._abandoned.discard(reply.id)
            _close_all(self._fds.take(p.announced_descriptors(reply)))
        self._keep()

    def abandon(self, request_id: int) -> None:
        """The caller of ``request_id`` stopped waiting (or got an error)."""
        if request_id in self._waiting:
            self._waiting.discard(request_id)
            self._abandoned.add(request_id)
        _close_all(self._claimed.pop(request_id, []))
        self._keep()

    def channel(self, request_id: int, result: Any) -> AttitudeChannel:
        """The channel the reply to ``request_id`` gives (see channel_from)."""
        fds = self._claimed.pop(request_id, [])
        try:
            channel, self._mapping = channel_from(result, fds, self._mapping)
        finally:
            self._keep()
        return channel

    def reset(self) -> None:
        """The connection ended: closes every descriptor, forgets the mapping
        (a new connection gets new blocks)."""
        self._fds.close()
        for fds in self._claimed.values():
            _close_all(fds)
        self._claimed.clear()
        self._waiting.clear()
        self._abandoned.clear()
        self._mapping = None

    def _keep(self) -> None:
        self._fds.keep(2 if self._mapping is None and self._waiting else 0)


def _close_all(fds: Iterable[int]) -> None:
    for fd in fds:
        _close(fd)


class AttitudeChannel:
    """A reader of gportd's attitude ring (``Client.attitude_channel()``).

    ``next(timeout)`` gives the sample after the last one taken (the first
    call: the newest), waiting for it; ``latest()`` the newest; ``missed``
    counts samples skipped because this reader fell more than a ring behind;
    ``closed`` turns true when gportd stops. The mapping is this process's:
    it outlives the connection; ``close()`` (or ``with``) ends this reader
    (the blocks are unmapped once no reader or client holds them). One
    thread should call next() at a time; several readers of one connection
    may wait in several threads."""

    def __init__(self, mapping: _ring.Mapping) -> None:
        self._mapping: _ring.Mapping | None = mapping
        self._cursor = 0
        self._from_first = False
        self.missed = 0

    @property
    def fenced(self) -> bool:
        """True when slots are read through libgport-client (fences), False
        for plain loads (x86_64 only)."""
        return self._mapping is not None and self._mapping.fenced

    def _published(self) -> int:
        return self._mapping.published() if self._mapping else 0

    def _wake_word(self) -> int:
        return self._mapping.wake_word() if self._mapping else 0

    def _read(self, n: int) -> tuple[Any, ...] | None:
        return self._mapping.read_words(n) if self._mapping else None

    def _attitude(self, w: tuple[Any, ...]) -> Attitude:
        rates = None
        if w[8]:
            rates = Rates(Axes(w[9], w[10], w[11]), ImuRates(w[12], w[13], w[14]))
        return Attitude(
            seq=int(w[0]),
            t=w[1],
            imu=Axes(w[2], w[3], w[4]),
            hall=Axes(w[5], w[6], w[7]),
            rates=rates,
            dropped=self.missed or None,
        )

    # ---- the reader ---------------------------------------------------------
    def take(self) -> Attitude | None:
        """The next sample without waiting (as base::RingReader::next)."""
        mapping = self._mapping
        if mapping is None:
            return None
        if self._from_first and mapping.published() > 0:
            self._from_first = False
            first = self._read(1)
            if first is not None:
                self._cursor = 1
                return self._attitude(first)
        lapped = False
        for _ in range(4):  # bounded: a writer stopped inside a slot never hangs us
            newest = mapping.published()
            if newest <= self._cursor:
                return None
            want = self._cursor + 1
            if self._cursor == 0:
                want = newest
            elif lapped or newest - self._cursor > mapping.slots:
                want = max(self._cursor + 1, newest - mapping.slots // 2)
            words = self._read(want)
            if words is not None:
                self.missed += 0 if self._cursor == 0 else want - self._cursor - 1
                self._cursor = want
                return self._attitude(words)
            # Overwritten between the two looks, or being overwritten: the
            # writer lapped this reader.
            lapped = True
        return None

    def skip_to_newest(self) -> None:
        """From now on, take() gives only samples published after this call."""
        self._cursor = self._published()
        self._from_first = self._cursor == 0

    def next(self, timeout: float | None = None) -> Attitude | None:
        """The next sample, waiting up to ``timeout`` seconds (None: until
        one comes or the channel closes); None on timeout or once closed."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            seen = self.relay()
            sample = self.take()
            if sample is not None:
                return sample
            left = None if deadline is None else deadline - time.monotonic()
            if self.closed or (left is not None and left <= 0):
                return None
            self.wait(seen, 1.0 if left is None else min(left, 1.0))

    def relay(self) -> int:
        """Loads the futex word and passes a new value on to this process's
        other waiters (gportd wakes one per connection); returns the value."""
        mapping = self._mapping
        if mapping is None:
            return 0
        seen = mapping.wake_word()
        mapping.relay(seen)
        return seen

    def wait(self, seen: int, timeout: float) -> None:
        """Sleeps while the futex word still holds ``seen``, at most ``timeout`` s."""
        mapping = self._mapping
        if mapping is not None:
            mapping.wait(seen, timeout)

    def wake(self) -> None:
        """Wakes every waiter of this process on the connection's word (a
        read-only mapping is enough): used to stop a thread blocked in next()."""
        mapping = self._mapping
        if mapping is not None:
            mapping.wake_all()

    def latest(self) -> Attitude | None:
        """The newest sample (next()'s cursor does not move); None before the first."""
        for _ in range(4):
            words = self._read(self._published())
            if words is not None:
                return self._attitude(words)
        return None

    @property
    def closed(self) -> bool:
        """gportd stopped publishing (or close() was called)."""
        mapping = self._mapping
        return mapping is None or mapping.closed()

    def close(self) -> None:
        """Ends this reader; the blocks are unmapped once nobody holds them."""
        self._mapping = None

    def __enter__(self) -> AttitudeChannel:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


class RingPump:
    """A thread that hands each new sample of a channel to ``deliver`` (the
    transparent ``subscribe(..., shared_memory=True)`` of both clients): it
    sleeps on the connection's futex word, passes wakes on like any reader,
    and wakes once per sample. stop() wakes it, joins it and ends the
    channel. The cost is this thread, in the client."""

    def __init__(self, channel: AttitudeChannel, deliver: Callable[[Attitude], None]) -> None:
        self.channel = channel
        self._deliver = deliver
        self._stopping = threading.Event()
        channel.skip_to_newest()
        self._thread = threading.Thread(target=self._run, name="gport-attitude", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            self._pump()
        finally:
            if self._stopping.is_set():
                self.channel.close()  # also when stop() came from deliver (no join)

    def _pump(self) -> None:
        channel = self.channel
        while not self._stopping.is_set():
            seen = channel.relay()
            sample = channel.take()
            if sample is not None:
                try:
                    self._deliver(sample)
                except RuntimeError:  # the event loop is closed
                    return
                continue
            if channel.closed:
                return
            channel.wait(seen, _PUMP_SLICE)

    def stop(self) -> None:
        self._stopping.set()
        self.channel.wake()
        if self._thread is not threading.current_thread():
            self._thread.join()
            self.channel.close()
