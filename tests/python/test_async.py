"""gport.AsyncClient against gportd --simulate (asyncio.run per test)."""

from __future__ import annotations

import asyncio

import pytest
from conftest import Daemon, skip_without_wait

import gport


async def connected(daemon: Daemon) -> gport.AsyncClient:
    client = await gport.AsyncClient.open(daemon.socket)
    for _ in range(500):
        if (await client.status()).link.state == "up":
            return client
        await asyncio.sleep(0.02)
    raise AssertionError("the simulated gimbal's link did not come up")


def test_async_methods(daemon: Daemon) -> None:
    async def main() -> None:
        client = await connected(daemon)
        status = await client.status()
        assert status.api_version == 1 and status.client is not None
        assert (await client.attitude()).seq > 0
        speed = await client.speed(yaw=10, duration_ms=3000)
        assert speed.speed == gport.Axes(0, 0, 10)
        await client.stop()
        assert (await client.status()).motion is None
        assert (await client.angle(pitch=-10)).angle == gport.Axes(0, -10, 0)
        assert (await client.center()).sent
        await client.lock()
        await client.photo()
        assert (await client.record(on=True, force=True)).recording == "on"
        held = await client.acquire()
        assert held.you_hold_control
        assert not (await client.release()).you_hold_control
        settings = await client.settings()
        changed = await client.set_settings(follow_speed=(settings.follow_speed + 1) % 256)
        assert changed.follow_speed == (settings.follow_speed + 1) % 256
        with pytest.raises(gport.InvalidParams):
            await client.angle(pitch=400)
        await client.close()
        assert not client.connected

    asyncio.run(main())


def test_async_wait(daemon: Daemon) -> None:
    async def main() -> gport.AngleResult:
        async with gport.AsyncClient(daemon.socket) as client:
            await connected(daemon)
            return await client.angle(yaw=10, wait=True)

    try:
        result = asyncio.run(main())
    except gport.InvalidParams as error:
        skip_without_wait(error)
        raise
    assert result.ended is not None and result.ended.reason == "reached"


def test_async_stream_and_events(daemon: Daemon) -> None:
    async def main() -> None:
        client = await connected(daemon)
        await client.subscribe("motion")
        seqs = []
        async for sample in client.attitude_stream(rate=20):
            seqs.append(sample.seq)
            if len(seqs) == 1:
                await client.speed(roll=3, duration_ms=2000)  # its event waits in the queue
            if len(seqs) == 3:
                break
        assert seqs == sorted(seqs) and len(set(seqs)) == 3
        event = await client.next_notification("motion", timeout=5)
        assert isinstance(event, gport.MotionEvent) and event.change == "started"
        await client.close()

    asyncio.run(main())


def test_async_moving_stops_when_the_block_raises(daemon: Daemon) -> None:
    async def main() -> None:
        client = await connected(daemon)
        stops = (await client.status()).counters.stops_sent
        with pytest.raises(RuntimeError):
            async with client.moving(yaw=15, lease_ms=300) as movement:
                await asyncio.sleep(0.8)  # longer than the lease: the task re-sends
                motion = (await client.status()).motion
                assert motion is not None and motion.speed == gport.Axes(0, 0, 15)
                assert movement.alive
                raise RuntimeError("abort")
        assert (await client.status()).motion is None
        # stops_sent counts zero speeds written: gportd paces its writes at the
        # line rate, so the count follows the reply shortly.
        for _ in range(250):
            if (await client.status()).counters.stops_sent > stops:
                break
            await asyncio.sleep(0.02)
        assert (await client.status()).counters.stops_sent > stops
        await client.close()

    asyncio.run(main())


def test_async_busy_and_control(daemon: Daemon) -> None:
    async def main() -> None:
        first = await connected(daemon)
        second = await connected(daemon)
        async with first.control():
            with pytest.raises(gport.Busy):
                await second.photo()
        await second.photo()
        await first.close()
        await second.close()

    asyncio.run(main())


def test_async_reconnect(daemon: Daemon) -> None:
    async def main() -> None:
        client = await connected(daemon)
        daemon.restart()
        with pytest.raises(gport.ConnectionLost):
            for _ in range(100):
                await client.status()
                await asyncio.sleep(0.05)
        await client.reconnect(retry_for=10)
        assert (await client.status()).api_version == 1
        await client.close()

    asyncio.run(main())


def test_both_clients_offer_the_same_methods() -> None:
    """Every public method of gport.Client is on gport.AsyncClient with the
    same parameters (a coroutine, but for the generators and context
    managers): both carry out the same Calls."""
    import inspect
    from typing import Any, Callable

    def shape(member: Callable[..., Any]) -> list[tuple[str, object, object]]:
        return [
            (p.name, p.kind, None if type(p.default) is object else p.default)  # a sentinel
            for p in inspect.signature(member).parameters.values()
        ]

    def public(cls: type) -> dict[str, Callable[..., Any]]:
        return {n: m for n, m in vars(cls).items() if callable(m) and not n.startswith("_")}

    sync, aio = public(gport.Client), public(gport.AsyncClient)
    assert set(sync) - set(aio) == set()
    streams = ("notifications", "attitude_stream", "control", "moving")
    for name, member in sync.items():
        assert shape(aio[name]) == shape(member), name
        assert inspect.iscoroutinefunction(aio[name]) or name in streams, name
