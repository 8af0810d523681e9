"""The blocking client: one socket, a reader thread, calls from any thread."""

from __future__ import annotations

import select
import socket
import threading
import time
from contextlib import contextmanager
from typing import Any, Generator, Iterable, Iterator, Mapping, TypeVar

from . import _calls as c
from . import _protocol as p
from .channel import AttitudeChannel, ChannelClaims, RingPump
from .errors import ConnectionLost, GportError, Timeout
from .moving import Movement, quietly
from .results import (
    AngleResult,
    Attitude,
    Captures,
    CenterResult,
    Control,
    Limits,
    Notification,
    PhotoResult,
    RecordResult,
    Settings,
    SpeedResult,
    Status,
    Subscription,
    VehiclePosition,
    VehicleTime,
)

_DEFAULT: Any = object()  # "the client's timeout", distinct from None (no limit)
T = TypeVar("T")


class Client:
    """A connection to gportd. Thread-safe: calls may come from several threads.

    ``path``: the socket (default $GPORT_SOCKET, else /run/gportd.sock).
    ``timeout``: seconds to wait for a reply (None: no limit); calls with
    ``wait=True`` get WAIT_ALLOWANCE (600 s) more, since the daemon's
    motion.timeout_ms ends the motion. The connection opens at once;
    ConnectionLost if it cannot. A line from the daemon that the client
    cannot decode ends the connection (ConnectionLost naming why).
    """

    def __init__(self, path: str | None = None, *, timeout: float | None = 10.0) -> None:
        self.path = p.socket_path(path)
        self.timeout = timeout
        self._cond = threading.Condition()
        self._write_lock = threading.Lock()
        self._pending: dict[int, p.Reply | None] = {}
        self._inbox = p.Inbox()
        self._subs = c.Subscriptions()
        self._next_id = 0
        self._sock: socket.socket | None = None
        self._reader: threading.Thread | None = None
        self._alive = False
        self._refused: GportError | None = None
        self._claims = ChannelClaims()  # received descriptors, the channel
        self._reason: str | None = None  # why the client ended the connection
        self._pump: RingPump | None = None
        self._open()

    # ---- connection -------------------------------------------------------
    def _open(self) -> None:
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        try:
            sock.connect(self.path)
        except OSError as error:
            sock.close()
            raise ConnectionLost(f"cannot connect to {self.path}: {error.strerror}") from error
        with self._cond:
            self._sock = sock
            self._alive = True
            self._refused = None
            self._reason = None
        self._reader = threading.Thread(
            target=self._read, args=(sock,), name="gport-reader", daemon=True
        )
        self._reader.start()

    def _read(self, sock: socket.socket) -> None:
        lines = p.LineBuffer()
        reason: str | None = None
        try:
            while True:
                data, received = p.receive(sock)
                with self._cond:
                    if self._sock is sock:
                        self._claims.received(received)  # none nobody asked for
                    else:
                        _close_all(received)
                if not data:
                    break
                for line in lines.feed(data):
                    self._dispatch(p.decode(line))
        except p.BadLine as error:
            reason = error.reason
        except OSError:
            pass
        except Exception as error:  # never leave a dead reader behind a live-looking client
            reason = f"the client's reader failed: {error!r}; the connection is closed"
        self._end(sock, reason)

    def _end(self, sock: socket.socket, reason: str | None) -> None:
        """The connection on ``sock`` is over: calls and waiters fail at once
        with ConnectionLost (naming ``reason``, when the client ended it)."""
        with self._cond:
            if self._sock is sock:
                self._alive = False
                self._claims.reset()
                if reason is not None and self._reason is None:
                    self._reason = reason
            self._cond.notify_all()
        if reason is not None:
            try:
                sock.shutdown(socket.SHUT_RDWR)  # the daemon sees the end now
            except OSError:
                pass

    def _dispatch(self, message: p.Message) -> None:
        with self._cond:
            if isinstance(message, p.Reply):
                self._claims.reply(message)
                if message.id in self._pending:
                    self._pending[message.id] = message
            elif isinstance(message, p.Pushed):
                self._inbox.put(message.topic, message.item, message.size)
            elif isinstance(message, p.Refused):
                self._refused = message.error
            else:
                return
            self._cond.notify_all()

    def _closed(self) -> str:
        return p.closed_message(self._refused, self._reason)

    @property
    def connected(self) -> bool:
        """False once the connection ended (the daemon closed it, a line it
        sent could not be decoded) or close() was called."""
        with self._cond:
            return self._alive

    @property
    def dropped_notifications(self) -> int:
        """Notifications dropped because nobody took them (INBOX_LIMIT of
        their topic waited); not the daemon's own ``dropped``."""
        with self._cond:
            return self._inbox.dropped

    def close(self) -> None:
        """Closes the connection: the daemon stops this client's motion and releases control."""
        self._stop_ring()
        with self._cond:
            sock, self._sock, self._alive = self._sock, None, False
            self._pending.clear()
            self._claims.reset()
            self._cond.notify_all()
        if sock is not None:
            try:
                sock.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
            sock.close()
        if self._reader is not None and self._reader is not threading.current_thread():
            self._reader.join()

    def reconnect(self, retry_for: float = 5.0) -> None:
        """Opens a new connection (retrying for ``retry_for`` seconds) and
        subscribes again to the topics this client had subscribed to.
        Control and motions are not restored: the daemon ended them."""
        self.close()
        deadline = time.monotonic() + retry_for
        while True:
            try:
                self._open()
                break
            except ConnectionLost:
                if time.monotonic() >= deadline:
                    raise
                time.sleep(0.05)
        with self._cond:
            self._inbox.clear()
            again = self._subs.again()
        if self._subs.shared_attitude:
            self._start_ring()
        for topics, rate in again:
            self.subscribe(topics, max_rate_hz=rate)

    def __enter__(self) -> Client:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ---- requests ---------------------------------------------------------
    def call(
        self, method: str, params: Mapping[str, Any] | None = None, timeout: Any = _DEFAULT
    ) -> Any:
        """Any method by name; returns the decoded ``result`` or raises GportError."""
        limit: float | None = self.timeout if timeout is _DEFAULT else timeout
        return self._await_reply(self._send(method, params, limit), method, limit)

    def _run(self, call: c.Call[T]) -> T:
        """One method of the API: its request, its result read."""
        return call.read(self.call(call.method, call.params, call.limit(self.timeout)))

    def _send(self, method: str, params: Mapping[str, Any] | None, limit: float | None) -> int:
        with self._cond:
            if not self._alive or self._sock is None:
                raise ConnectionLost(self._closed())
            self._next_id += 1
            request_id, sock = self._next_id, self._sock
            self._pending[request_id] = None
            if method == p.CHANNEL_METHOD:
                self._claims.expect(request_id)
        try:
            taken = self._write_whole(sock, p.encode(request_id, method, params), limit)
        except OSError as error:
            taken, failure = False, f"cannot send to {self.path}: {error.strerror}"
        else:
            failure = (
                f"the daemon did not read the request to {method} within {limit} s; "
                "the connection is closed"
            )
        if not taken:
            with self._cond:
                self._pending.pop(request_id, None)
                self._claims.abandon(request_id)
            self._end(sock, failure)  # a part of a line may have gone: the stream is unusable
            raise ConnectionLost(failure)
        return request_id

    def _write_whole(self, sock: socket.socket, line: bytes, limit: float | None) -> bool:
        """Writes a whole line, one thread at a time; waiting for the thread
        that writes counts against ``limit`` too (that thread may be held by
        a daemon that does not read for as long as its own limit)."""
        deadline = None if limit is None else time.monotonic() + limit
        if not self._write_lock.acquire(timeout=-1 if limit is None else limit):
            return False
        try:
            left = None if deadline is None else max(0.0, deadline - time.monotonic())
            return _write(sock, line, left)
        finally:
            self._write_lock.release()

    def _await_reply(self, request_id: int, method: str, limit: float | None) -> Any:
        deadline = None if limit is None else time.monotonic() + limit
        reply: p.Reply | None = None
        with self._cond:
            try:
                while True:
                    reply = self._pending.get(request_id)
                    if reply is not None or request_id not in self._pending or not self._alive:
                        break
                    left = None if deadline is None else deadline - time.monotonic()
                    if left is not None and left <= 0:
                        break
                    self._cond.wait(left)
            finally:  # also when interrupted (Ctrl-C): a late reply is dropped
                self._pending.pop(request_id, None)
            if reply is None and not self._alive:
                raise ConnectionLost(self._closed())
        if reply is None:
            raise Timeout(f"no reply to {method} within {limit} s")
        if reply.error is not None:
            raise reply.error
        return reply.result

    def status(self) -> Status:
        return self._run(c.STATUS)

    def attitude_channel(self) -> AttitudeChannel:
        """Opens gportd's shared-memory attitude channel (docs/api.md): a
        read-only mapping of its ring of the latest samples and of this
        connection's wake block, received with the connection's first
        request and shared by every later one (each call gives a reader with
        its own cursor). BadChannel when a block fails its checks (the
        message names why)."""
        request_id = self._send(p.CHANNEL_METHOD, None, self.timeout)
        try:
            result = self._await_reply(request_id, p.CHANNEL_METHOD, self.timeout)
        except BaseException:  # a late reply's descriptors are closed
            with self._cond:
                self._claims.abandon(request_id)
            raise
        with self._cond:
            return self._claims.channel(request_id, result)

    def attitude(self) -> Attitude:
        return self._run(c.ATTITUDE)

    def speed(
        self,
        roll: float = 0.0,
        pitch: float = 0.0,
        yaw: float = 0.0,
        *,
        duration_ms: int | None = None,
        lease_ms: int | None = None,
        clamp: bool = False,
    ) -> SpeedResult:
        return self._run(c.speed(roll, pitch, yaw, duration_ms, lease_ms, clamp))

    def stop(self) -> None:
        self._run(c.STOP)

    def angle(
        self,
        roll: float = 0.0,
        pitch: float = 0.0,
        yaw: float = 0.0,
        *,
        clamp: bool = False,
        wait: bool = False,
    ) -> AngleResult:
        return self._run(c.angle(roll, pitch, yaw, clamp, wait))

    def center(self, *, wait: bool = False) -> CenterResult:
        return self._run(c.center(wait))

    def lock(self) -> None:
        self._run(c.LOCK)

    def photo(self, *, meta: Mapping[str, Any] | None = None) -> PhotoResult:
        """Takes a photo; ``meta`` (a mapping) is stored with the capture."""
        return self._run(c.photo(meta))

    def record(
        self, on: bool | None = None, force: bool = False, *, meta: Mapping[str, Any] | None = None
    ) -> RecordResult:
        return self._run(c.record(on, force, meta))

    def captures(self, since: int | None = None, limit: int | None = None) -> Captures:
        """The captures gportd kept from index ``since`` on, oldest first."""
        return self._run(c.captures(since, limit))

    def publish_vehicle(
        self, *, position: VehiclePosition | None = None, time: VehicleTime | None = None
    ) -> None:
        """Publishes the vehicle's state, which gportd stamps every capture
        with (only its trusted source may: access.vehicle_uids). ValueError
        before sending for neither part or a member of the wrong type."""
        self._run(c.publish_vehicle(position, time))

    def acquire(self) -> Control:
        return self._run(c.ACQUIRE)

    def release(self) -> Control:
        return self._run(c.RELEASE)

    def limits(self) -> Limits:
        """gportd's configured soft limits (read-only)."""
        return self._run(c.LIMITS)

    def settings(self) -> Settings:
        return self._run(c.SETTINGS)

    def set_settings(
        self,
        *,
        dead_zone: int | None = None,
        follow_speed: int | None = None,
        inverted: bool | None = None,
    ) -> Settings:
        return self._run(c.set_settings(dead_zone, follow_speed, inverted))

    def subscribe(
        self,
        topics: str | Iterable[str],
        max_rate_hz: float | None = None,
        *,
        shared_memory: bool = False,
    ) -> Subscription:
        """Subscribes to ``attitude``, ``link`` and/or ``motion``; read with
        next_notification(), notifications() or attitude_stream().

        ``shared_memory=True``: attitude comes from gportd's shared-memory
        channel (attitude_channel()) instead of the socket, as the same
        Attitude notifications (only samples published from now on;
        ``dropped`` counts skipped ones); a thread of this client sleeps on
        the channel's futex and queues each sample. ``max_rate_hz`` does not
        apply to it."""
        wanted = p.topic_list(topics)
        rest = c.Subscriptions.through_channel(wanted, shared_memory)
        if rest is not None:
            result = self.subscribe(rest) if rest else Subscription((), None)
            self._start_ring()
            self._subs.shared_attitude = True
            return c.Subscriptions.with_channel(result)
        result = self._run(c.subscribe(wanted, max_rate_hz))
        with self._cond:
            self._subs.subscribed(wanted, max_rate_hz, result)
        return result

    def unsubscribe(self, topics: str | Iterable[str] | None = None) -> Subscription:
        """Ends the topics (None: all), the shared-memory attitude too."""
        if c.Subscriptions.ends_channel(topics):
            self._subs.shared_attitude = False
            self._stop_ring()
        result = self._run(c.unsubscribe(topics))
        with self._cond:
            self._subs.unsubscribed(topics, result, self._inbox)
        return result

    def _start_ring(self) -> None:
        if self._pump is not None:
            return
        channel = self.attitude_channel()
        self._pump = RingPump(channel, self._ring_sample)

    def _ring_sample(self, sample: Attitude) -> None:
        with self._cond:
            self._inbox.put("attitude", sample)
            self._cond.notify_all()

    def _stop_ring(self) -> None:
        pump, self._pump = self._pump, None
        if pump is not None:
            pump.stop()

    # ---- notifications ----------------------------------------------------
    def next_notification(
        self, topics: Iterable[str] | None = None, timeout: float | None = None
    ) -> Notification | None:
        """The oldest waiting notification (of ``topics``, default all),
        waiting up to ``timeout`` seconds (None: no limit); None on timeout.
        Raises ConnectionLost once the connection is gone and none waits."""
        want = c.NextNotification(topics, timeout)
        with self._cond:
            while (item := want.take(self._inbox, self._alive, self._closed)) is None:
                left = want.left()
                if left == 0:
                    return None
                self._cond.wait(left)
            return item

    def notifications(
        self, topics: Iterable[str] | None = None
    ) -> Generator[Notification, None, None]:
        """Every notification as it arrives (subscribe first); ends on ConnectionLost."""
        while True:
            item = self.next_notification(topics)
            if item is not None:
                yield item

    def attitude_stream(
        self,
        rate: float | None = 10.0,
        timeout: float | None = None,
        *,
        shared_memory: bool = False,
    ) -> Generator[Attitude, None, None]:
        """Subscribes to attitude at ``rate`` Hz (None: every sample) and yields
        the samples; unsubscribes when the loop ends. Other notifications
        stay queued. ``timeout``: Timeout when no sample comes for that long.
        ``shared_memory=True``: from the shared-memory channel (every sample;
        ``rate`` does not apply), as subscribe()."""
        self.subscribe("attitude", max_rate_hz=rate, shared_memory=shared_memory)
        try:
            while True:
                yield c.streamed(self.next_notification(("attitude",), timeout), timeout)
        finally:
            if self.connected:
                try:
                    self.unsubscribe("attitude")
                except GportError:
                    pass

    # ---- context managers -------------------------------------------------
    @contextmanager
    def control(self) -> Iterator[Control]:
        """``with client.control():`` holds control (acquire) for the block."""
        result = self.acquire()
        try:
            yield result
        except BaseException as error:
            quietly(self.release, error)
            raise
        self.release()

    @contextmanager
    def moving(
        self,
        roll: float = 0.0,
        pitch: float = 0.0,
        yaw: float = 0.0,
        *,
        lease_ms: int = 500,
        duration_ms: int | None = None,
        clamp: bool = False,
    ) -> Iterator[Movement]:
        """``with client.moving(yaw=30):`` moves at that speed for the block.

        A background thread re-sends the speed three times per ``lease_ms``;
        leaving the block (also by an exception) sends ``stop``. If this
        process hangs, the daemon's lease stops the gimbal. ``duration_ms``
        caps the whole movement. An error of a re-send (another client took
        control, the link went down) ends the re-sends and is raised when the
        block ends normally."""
        interval = p.keepalive_interval(lease_ms)
        movement = Movement(self, c.speed(roll, pitch, yaw, None, lease_ms, clamp))
        movement.start(interval, duration_ms)
        try:
            yield movement
        except BaseException as error:
            movement.halt()
            quietly(self.stop, error)
            raise
        movement.halt()
        self.stop()
        if movement.error is not None:
            raise movement.error


def _write(sock: socket.socket, data: bytes, limit: float | None) -> bool:
    """Sends all of ``data`` unless the daemon takes none of it for ``limit``
    seconds (then False): a daemon that does not read cannot hold a call."""
    deadline = None if limit is None else time.monotonic() + limit
    view = memoryview(data)
    poller = select.poll()
    poller.register(sock, select.POLLOUT)
    while view:
        try:
            view = view[sock.send(view, socket.MSG_DONTWAIT) :]
            continue
        except BlockingIOError:
            pass
        left = None if deadline is None else deadline - time.monotonic()
        if left is not None and left <= 0:
            return False
        poller.poll(None if left is None else max(1, int(left * 1000)))
    return True


def _close_all(fds: Iterable[int]) -> None:
    for fd in fds:
        p.close_quietly(fd)
