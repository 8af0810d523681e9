"""The asyncio client: the same methods as gport.Client, as coroutines."""

from __future__ import annotations

import asyncio
import socket
import threading
import time
from collections import deque
from contextlib import asynccontextmanager
from typing import Any, AsyncGenerator, AsyncIterator, Iterable, Mapping, TypeVar

from . import _calls as c
from . import _protocol as p
from .channel import AttitudeChannel, ChannelClaims, RingPump
from .errors import ConnectionLost, GportError, Timeout
from .moving import AsyncMovement, quietly_async
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

_DEFAULT: Any = object()
T = TypeVar("T")


class AsyncClient:
    """A connection to gportd for asyncio programs (one event loop).

    ``client = await AsyncClient.open(path)`` or ``async with AsyncClient(path)
    as client:``; then ``await client.status()`` and so on. Arguments,
    results, timeouts and limits are those of gport.Client.
    """

    def __init__(self, path: str | None = None, *, timeout: float | None = 10.0) -> None:
        self.path = p.socket_path(path)
        self.timeout = timeout
        self._pending: dict[int, asyncio.Future[p.Reply]] = {}
        self._inbox = p.Inbox()
        self._changed = asyncio.Event()
        self._subs = c.Subscriptions()
        self._next_id = 0
        self._sock: socket.socket | None = None
        self._lines = p.LineBuffer()
        self._send_lock: asyncio.Lock | None = None
        self._claims = ChannelClaims()  # received descriptors, the channel
        self._pump: RingPump | None = None
        self._alive = False
        self._refused: GportError | None = None
        self._reason: str | None = None  # why the client ended the connection

    @classmethod
    async def open(cls, path: str | None = None, *, timeout: float | None = 10.0) -> AsyncClient:
        client = cls(path, timeout=timeout)
        await client.connect()
        return client

    # ---- connection -------------------------------------------------------
    async def connect(self) -> None:
        """Connects. The socket is read by a reader callback (loop.add_reader)
        with recvmsg, which also receives the descriptor of attitude_channel
        replies (StreamReader and loop.sock_recv drop ancillary data)."""
        loop = asyncio.get_running_loop()
        sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        sock.setblocking(False)
        try:
            await loop.sock_connect(sock, self.path)
        except OSError as error:
            sock.close()
            raise ConnectionLost(f"cannot connect to {self.path}: {error.strerror}") from error
        self._sock, self._alive, self._refused, self._reason = sock, True, None, None
        self._lines, self._claims = p.LineBuffer(), ChannelClaims()
        self._send_lock = asyncio.Lock()
        loop.add_reader(sock.fileno(), self._readable, sock)

    def _readable(self, sock: socket.socket) -> None:
        if sock is not self._sock:
            return
        try:
            data, fds = p.receive(sock)
        except (BlockingIOError, InterruptedError):
            return
        except OSError:
            data, fds = b"", []
        self._claims.received(fds)  # none nobody asked for
        if not data:
            self._detach(sock)
            self._lost()
            return
        try:
            for line in self._lines.feed(data):
                if sock is not self._sock:
                    return  # a handler closed the connection
                self._dispatch(p.decode(line))
        except p.BadLine as error:
            self._end(sock, error.reason)
        except Exception as error:  # never leave a dead reader behind a live-looking client
            self._end(sock, f"the client's reader failed: {error!r}; the connection is closed")

    def _end(self, sock: socket.socket, reason: str) -> None:
        """The client ends the connection on ``sock``: pending and later calls
        fail with ConnectionLost naming ``reason``."""
        if sock is not self._sock:
            return
        self._reason = reason
        self._detach(sock)
        self._lost()

    def _detach(self, sock: socket.socket) -> None:
        """Stops reading ``sock`` and closes it and the received descriptors."""
        if self._sock is sock:
            self._sock = None
        try:
            asyncio.get_running_loop().remove_reader(sock.fileno())
        except (RuntimeError, ValueError):
            pass
        sock.close()
        self._claims.reset()

    def _lost(self) -> None:
        self._alive = False
        for future in self._pending.values():
            if not future.done():
                future.set_exception(ConnectionLost(self._closed()))
        self._pending.clear()
        self._claims.reset()
        self._changed.set()

    def _dispatch(self, message: p.Message) -> None:
        if isinstance(message, p.Reply):
            future = self._pending.pop(message.id, None)
            self._claims.reply(message)
            if future is not None and not future.done():
                future.set_result(message)
            else:  # the caller gave up waiting
                self._claims.abandon(message.id)
        elif isinstance(message, p.Pushed):
            self._inbox.put(message.topic, message.item, message.size)
            self._changed.set()
        elif isinstance(message, p.Refused):
            self._refused = message.error

    def _closed(self) -> str:
        return p.closed_message(self._refused, self._reason)

    @property
    def connected(self) -> bool:
        return self._alive

    @property
    def dropped_notifications(self) -> int:
        """As gport.Client.dropped_notifications."""
        return self._inbox.dropped

    async def close(self) -> None:
        """Closes the connection: the daemon stops this client's motion and releases control."""
        self._stop_ring()
        sock = self._sock
        self._lost()
        if sock is not None:
            self._detach(sock)

    async def reconnect(self, retry_for: float = 5.0) -> None:
        """As gport.Client.reconnect: a new connection, the same subscriptions."""
        await self.close()
        deadline = time.monotonic() + retry_for
        while True:
            try:
                await self.connect()
                break
            except ConnectionLost:
                if time.monotonic() >= deadline:
                    raise
                await asyncio.sleep(0.05)
        self._inbox.clear()
        if self._subs.shared_attitude:
            await self._start_ring()
        for topics, rate in self._subs.again():
            await self.subscribe(topics, max_rate_hz=rate)

    async def __aenter__(self) -> AsyncClient:
        if not self._alive:
            await self.connect()
        return self

    async def __aexit__(self, *exc: object) -> None:
        await self.close()

    # ---- requests ---------------------------------------------------------
    async def call(
        self, method: str, params: Mapping[str, Any] | None = None, timeout: Any = _DEFAULT
    ) -> Any:
        """Any method by name; returns the decoded ``result`` or raises GportError."""
        limit: float | None = self.timeout if timeout is _DEFAULT else timeout
        return (await self._request(method, params, limit))[1]

    async def _run(self, call: c.Call[T]) -> T:
        """One method of the API: its request, its result read."""
        return call.read(await self.call(call.method, call.params, call.limit(self.timeout)))

    async def _request(
        self, method: str, params: Mapping[str, Any] | None, limit: float | None
    ) -> tuple[int, Any]:
        """The request's id and the result of its reply, at most ``limit``
        seconds after it was sent (Timeout), or the daemon's error."""
        started = time.monotonic()
        request_id, future = await self._send(method, params, limit)
        left = None if limit is None else max(0.0, limit - (time.monotonic() - started))
        return request_id, await self._await_reply(request_id, future, method, limit, left)

    async def _send(
        self, method: str, params: Mapping[str, Any] | None, limit: float | None
    ) -> tuple[int, asyncio.Future[p.Reply]]:
        """Sends a request; its id and the future of its reply. Not taken
        within ``limit``: the connection is closed (ConnectionLost)."""
        sock, lock = self._sock, self._send_lock
        if not self._alive or sock is None or lock is None:
            raise ConnectionLost(self._closed())
        self._next_id += 1
        request_id = self._next_id
        future: asyncio.Future[p.Reply] = asyncio.get_running_loop().create_future()
        self._pending[request_id] = future
        if method == p.CHANNEL_METHOD:
            self._claims.expect(request_id)
        try:
            line = p.encode(request_id, method, params)
            await asyncio.wait_for(self._send_line(sock, lock, line), limit)
        except (OSError, asyncio.TimeoutError, ConnectionLost) as error:
            self._pending.pop(request_id, None)
            self._claims.abandon(request_id)
            if future.done():
                future.exception()  # seen: the error raised here tells it
            if isinstance(error, ConnectionLost):
                raise
            self._end(sock, _send_failure(error, method, limit, self.path))
            raise ConnectionLost(self._closed()) from None
        return request_id, future

    async def _await_reply(
        self,
        request_id: int,
        future: asyncio.Future[p.Reply],
        method: str,
        limit: float | None,
        left: float | None,
    ) -> Any:
        try:
            reply = await asyncio.wait_for(future, left)
        except BaseException as error:  # a late reply's descriptors are closed
            self._pending.pop(request_id, None)
            self._claims.abandon(request_id)
            if isinstance(error, asyncio.TimeoutError):
                raise Timeout(f"no reply to {method} within {limit} s") from None
            raise
        if reply.error is not None:
            self._claims.abandon(request_id)
            raise reply.error
        return reply.result

    async def _send_line(self, sock: socket.socket, lock: asyncio.Lock, line: bytes) -> None:
        async with lock:  # whole lines: one sendall at a time
            if sock is not self._sock:
                raise ConnectionLost(self._closed())
            await asyncio.get_running_loop().sock_sendall(sock, line)

    async def status(self) -> Status:
        return await self._run(c.STATUS)

    async def attitude_channel(self) -> AttitudeChannel:
        """As gport.Client.attitude_channel: gportd's shared-memory attitude
        channel, received once per connection and shared by later calls."""
        request_id, result = await self._request(p.CHANNEL_METHOD, None, self.timeout)
        return self._claims.channel(request_id, result)

    async def attitude(self) -> Attitude:
        return await self._run(c.ATTITUDE)

    async def speed(
        self,
        roll: float = 0.0,
        pitch: float = 0.0,
        yaw: float = 0.0,
        *,
        duration_ms: int | None = None,
        lease_ms: int | None = None,
        clamp: bool = False,
    ) -> SpeedResult:
        return await self._run(c.speed(roll, pitch, yaw, duration_ms, lease_ms, clamp))

    async def stop(self) -> None:
        await self._run(c.STOP)

    async def angle(
        self,
        roll: float = 0.0,
        pitch: float = 0.0,
        yaw: float = 0.0,
        *,
        clamp: bool = False,
        wait: bool = False,
    ) -> AngleResult:
        return await self._run(c.angle(roll, pitch, yaw, clamp, wait))

    async def center(self, *, wait: bool = False) -> CenterResult:
        return await self._run(c.center(wait))

    async def lock(self) -> None:
        await self._run(c.LOCK)

    async def photo(self, *, meta: Mapping[str, Any] | None = None) -> PhotoResult:
        """Takes a photo; ``meta`` (a mapping) is stored with the capture."""
        return await self._run(c.photo(meta))

    async def record(
        self, on: bool | None = None, force: bool = False, *, meta: Mapping[str, Any] | None = None
    ) -> RecordResult:
        return await self._run(c.record(on, force, meta))

    async def captures(self, since: int | None = None, limit: int | None = None) -> Captures:
        """The captures gportd kept from index ``since`` on, oldest first."""
        return await self._run(c.captures(since, limit))

    async def publish_vehicle(
        self, *, position: VehiclePosition | None = None, time: VehicleTime | None = None
    ) -> None:
        """Publishes the vehicle's state, which gportd stamps every capture
        with (only its trusted source may: access.vehicle_uids). ValueError
        before sending for neither part or a member of the wrong type."""
        await self._run(c.publish_vehicle(position, time))

    async def acquire(self) -> Control:
        return await self._run(c.ACQUIRE)

    async def release(self) -> Control:
        return await self._run(c.RELEASE)

    async def limits(self) -> Limits:
        """gportd's configured soft limits (read-only)."""
        return await self._run(c.LIMITS)

    async def settings(self) -> Settings:
        return await self._run(c.SETTINGS)

    async def set_settings(
        self,
        *,
        dead_zone: int | None = None,
        follow_speed: int | None = None,
        inverted: bool | None = None,
    ) -> Settings:
        return await self._run(c.set_settings(dead_zone, follow_speed, inverted))

    async def subscribe(
        self,
        topics: str | Iterable[str],
        max_rate_hz: float | None = None,
        *,
        shared_memory: bool = False,
    ) -> Subscription:
        """As gport.Client.subscribe. With ``shared_memory=True`` a thread
        sleeps on the channel's futex and hands each sample to this event
        loop (call_soon_threadsafe), which queues it like a socket one."""
        wanted = p.topic_list(topics)
        rest = c.Subscriptions.through_channel(wanted, shared_memory)
        if rest is not None:
            result = (await self.subscribe(rest)) if rest else Subscription((), None)
            await self._start_ring()
            self._subs.shared_attitude = True
            return c.Subscriptions.with_channel(result)
        result = await self._run(c.subscribe(wanted, max_rate_hz))
        self._subs.subscribed(wanted, max_rate_hz, result)
        return result

    async def unsubscribe(self, topics: str | Iterable[str] | None = None) -> Subscription:
        if c.Subscriptions.ends_channel(topics):
            self._subs.shared_attitude = False
            self._stop_ring()
        result = await self._run(c.unsubscribe(topics))
        self._subs.unsubscribed(topics, result, self._inbox)
        return result

    async def _start_ring(self) -> None:
        if self._pump is not None:
            return
        channel = await self.attitude_channel()
        loop = asyncio.get_running_loop()
        # Samples wait here (bounded like the inbox) and one drain at a time
        # is posted to the loop, so a busy loop never piles up callbacks.
        waiting: deque[Attitude] = deque(maxlen=p.INBOX_LIMIT)
        posted = threading.Event()

        def drain() -> None:
            posted.clear()
            while waiting:
                self._ring_sample(waiting.popleft())

        def deliver(sample: Attitude) -> None:
            waiting.append(sample)
            if not posted.is_set():
                posted.set()
                loop.call_soon_threadsafe(drain)

        self._pump = RingPump(channel, deliver)

    def _ring_sample(self, sample: Attitude) -> None:
        if self._pump is not None:
            self._inbox.put("attitude", sample)
            self._changed.set()

    def _stop_ring(self) -> None:
        pump, self._pump = self._pump, None
        if pump is not None:
            pump.stop()  # wakes the thread at once: a short join

    # ---- notifications ----------------------------------------------------
    async def next_notification(
        self, topics: Iterable[str] | None = None, timeout: float | None = None
    ) -> Notification | None:
        """As gport.Client.next_notification."""
        want = c.NextNotification(topics, timeout)
        while (item := want.take(self._inbox, self._alive, self._closed)) is None:
            left = want.left()
            if left == 0:
                return None
            self._changed.clear()
            try:
                await asyncio.wait_for(self._changed.wait(), left)
            except asyncio.TimeoutError:
                return None
        return item

    async def notifications(
        self, topics: Iterable[str] | None = None
    ) -> AsyncGenerator[Notification, None]:
        while True:
            item = await self.next_notification(topics)
            if item is not None:
                yield item

    async def attitude_stream(
        self,
        rate: float | None = 10.0,
        timeout: float | None = None,
        *,
        shared_memory: bool = False,
    ) -> AsyncGenerator[Attitude, None]:
        """``async for sample in client.attitude_stream(rate=10):``; as gport.Client's."""
        await self.subscribe("attitude", max_rate_hz=rate, shared_memory=shared_memory)
        try:
            while True:
                yield c.streamed(await self.next_notification(("attitude",), timeout), timeout)
        finally:
            if self._alive:
                try:
                    await self.unsubscribe("attitude")
                except GportError:
                    pass

    # ---- context managers -------------------------------------------------
    @asynccontextmanager
    async def control(self) -> AsyncIterator[Control]:
        """``async with client.control():`` holds control for the block."""
        result = await self.acquire()
        try:
            yield result
        except BaseException as error:
            await quietly_async(self.release, error)
            raise
        await self.release()

    @asynccontextmanager
    async def moving(
        self,
        roll: float = 0.0,
        pitch: float = 0.0,
        yaw: float = 0.0,
        *,
        lease_ms: int = 500,
        duration_ms: int | None = None,
        clamp: bool = False,
    ) -> AsyncIterator[AsyncMovement]:
        """``async with client.moving(yaw=30):`` as gport.Client.moving, with
        a task re-sending the speed."""
        interval = p.keepalive_interval(lease_ms)
        movement = AsyncMovement(self, c.speed(roll, pitch, yaw, None, lease_ms, clamp))
        await movement.start(interval, duration_ms)
        try:
            yield movement
        except BaseException as error:
            await movement.halt()
            await quietly_async(self.stop, error)
            raise
        await movement.halt()
        await self.stop()
        if movement.error is not None:
            raise movement.error


def _send_failure(error: BaseException, method: str, limit: float | None, path: str) -> str:
    """Why a request that could not be sent ends the connection."""
    if isinstance(error, asyncio.TimeoutError):  # (an OSError since 3.11: first)
        # A part of a line may have gone: the stream is unusable.
        return (
            f"the daemon did not read the request to {method} within {limit} s; "
            "the connection is closed"
        )
    return f"cannot send to {path}: {getattr(error, 'strerror', None) or error}"
