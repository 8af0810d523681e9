"""The speed a ``moving`` block keeps alive: a thread (Movement) for the
blocking client, a task (AsyncMovement) for the asyncio one."""

from __future__ import annotations

import asyncio
import threading
import time
from typing import Any, Awaitable, Callable, Mapping, Protocol

from . import _protocol as p
from ._calls import Call
from .errors import GportError
from .results import SpeedResult


class Caller(Protocol):
    def call(self, method: str, params: Mapping[str, Any] | None = ...) -> Any: ...


class AsyncCaller(Protocol):
    async def call(self, method: str, params: Mapping[str, Any] | None = ...) -> Any: ...


def quietly(action: Callable[[], Any], pending: BaseException) -> None:
    """Runs a clean-up while ``pending`` propagates; its failure becomes a note."""
    try:
        action()
    except GportError as error:
        pending.add_note(f"gport: clean-up failed too: {error}")


class Movement:
    """The speed a ``moving`` block keeps alive; ``update`` changes it."""

    def __init__(self, client: Caller, first: Call[SpeedResult]) -> None:
        self._client = client
        self._parse = first.read
        self._params = dict(first.params or {})
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._deadline: float | None = None
        self.result: SpeedResult | None = None
        self.error: GportError | None = None

    def start(self, interval: float, duration_ms: int | None) -> None:
        if duration_ms is not None:
            self._deadline = time.monotonic() + duration_ms / 1000.0
        self._send()  # the first speed's errors go to the caller
        self._thread = threading.Thread(
            target=self._keep, args=(interval,), name="gport-moving", daemon=True
        )
        self._thread.start()

    def update(
        self, roll: float | None = None, pitch: float | None = None, yaw: float | None = None
    ) -> SpeedResult | None:
        """Changes the given axes' speeds and sends the new speed at once."""
        with self._lock:
            self._params.update(p.drop_none(roll=roll, pitch=pitch, yaw=yaw))
        return self._send()

    @property
    def alive(self) -> bool:
        """True while the re-sends go on."""
        return self._thread is not None and self._thread.is_alive()

    def _send(self) -> SpeedResult | None:
        with self._lock:
            params = dict(self._params)
        if self._deadline is not None:
            left = int((self._deadline - time.monotonic()) * 1000)
            if left <= 0:
                return None
            params["duration_ms"] = left
        self.result = self._parse(self._client.call("speed", params))
        return self.result

    def _keep(self, interval: float) -> None:
        while not self._stop.wait(interval):
            try:
                if self._send() is None:
                    return
            except GportError as error:
                self.error = error
                return

    def halt(self) -> None:
        self._stop.set()
        if self._thread is not None and self._thread is not threading.current_thread():
            self._thread.join()


async def quietly_async(action: Callable[[], Awaitable[Any]], pending: BaseException) -> None:
    try:
        await action()
    except GportError as error:
        pending.add_note(f"gport: clean-up failed too: {error}")


class AsyncMovement:
    """The speed an async ``moving`` block keeps alive; ``update`` changes it."""

    def __init__(self, client: AsyncCaller, first: Call[SpeedResult]) -> None:
        self._client = client
        self._parse = first.read
        self._params = dict(first.params or {})
        self._task: asyncio.Task[None] | None = None
        self._deadline: float | None = None
        self.result: SpeedResult | None = None
        self.error: GportError | None = None

    async def start(self, interval: float, duration_ms: int | None) -> None:
        if duration_ms is not None:
            self._deadline = time.monotonic() + duration_ms / 1000.0
        await self._send()
        self._task = asyncio.create_task(self._keep(interval))

    async def update(
        self, roll: float | None = None, pitch: float | None = None, yaw: float | None = None
    ) -> SpeedResult | None:
        self._params.update(p.drop_none(roll=roll, pitch=pitch, yaw=yaw))
        return await self._send()

    @property
    def alive(self) -> bool:
        return self._task is not None and not self._task.done()

    async def _send(self) -> SpeedResult | None:
        params = dict(self._params)
        if self._deadline is not None:
            left = int((self._deadline - time.monotonic()) * 1000)
            if left <= 0:
                return None
            params["duration_ms"] = left
        self.result = self._parse(await self._client.call("speed", params))
        return self.result

    async def _keep(self, interval: float) -> None:
        while True:
            await asyncio.sleep(interval)
            try:
                if await self._send() is None:
                    return
            except GportError as error:
                self.error = error
                return

    async def halt(self) -> None:
        if self._task is not None:
            self._task.cancel()
            await asyncio.gather(self._task, return_exceptions=True)
