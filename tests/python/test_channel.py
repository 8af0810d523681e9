"""The shared-memory attitude channel against a fake gportd (fake_gportd.py):
the descriptor FIFO, the block's checks, next/latest/missed/closed, and the
transparent ``shared_memory=True`` subscription of both clients."""

from __future__ import annotations

import asyncio
import threading
import time
from typing import Iterator

import pytest

import gport
from fake_gportd import FakeServer, RingBlock, open_descriptors


@pytest.fixture
def server() -> Iterator[FakeServer]:
    fake = FakeServer()
    yield fake
    fake.close()


@pytest.fixture
def block() -> Iterator[RingBlock]:
    ring = RingBlock()
    yield ring
    ring.release()


def settle(before: int) -> int:
    """The descriptor count once the fake server closed its side."""
    deadline = time.monotonic() + 5
    while open_descriptors() != before and time.monotonic() < deadline:
        time.sleep(0.01)
    return open_descriptors()


def test_next_gives_the_newest_first_then_every_sample(
    server: FakeServer, block: RingBlock
) -> None:
    server.offers.append(block)
    with gport.Client(server.path) as client, client.attitude_channel() as channel:
        assert channel.latest() is None
        assert channel.next(0) is None
        block.publish(1)
        block.publish(2, rates=True)
        first = channel.next(1)
        assert first is not None and first.seq == 2
        assert first.rates == gport.Rates(gport.Axes(1, 2, 3), gport.ImuRates(4, 5, 6))
        assert first.imu == gport.Axes(0.2, -2.5, 45) and first.hall.yaw == 44.75
        assert first.dropped is None and first.age_ms is None
        block.publish(3)
        block.publish(4)
        assert [s.seq for s in (channel.next(1), channel.next(1)) if s] == [3, 4]
        assert channel.next(0.02) is None
        latest = channel.latest()
        assert latest is not None and latest.seq == 4 and latest.rates is None
        assert channel.missed == 0 and not channel.closed


def test_next_wakes_for_a_sample_published_while_it_waits(
    server: FakeServer, block: RingBlock
) -> None:
    server.offers.append(block)
    with gport.Client(server.path) as client:
        channel = client.attitude_channel()
        timer = threading.Timer(0.05, block.publish, (7,))
        timer.start()
        sample = channel.next(10)
        timer.join()
        assert sample is not None and sample.seq == 7
        channel.close()


def test_a_reader_more_than_a_ring_behind_counts_what_it_missed(
    server: FakeServer, block: RingBlock
) -> None:
    server.offers.append(block)
    with gport.Client(server.path) as client:
        channel = client.attitude_channel()
    block.publish(1)  # the channel outlives its client
    assert (channel.next(1) or pytest.fail("no sample")).seq == 1
    for seq in range(2, 202):
        block.publish(seq)
    sample = channel.next(1)
    assert sample is not None and sample.seq == 201 - 32
    assert channel.missed == 167 and sample.dropped == 167
    after = channel.next(1)
    assert after is not None and after.seq == 201 - 31
    block.close()
    assert channel.closed
    channel.close()


def test_a_closed_channel_gives_what_is_left_then_none_at_once(
    server: FakeServer, block: RingBlock
) -> None:
    server.offers.append(block)
    with gport.Client(server.path) as client, client.attitude_channel() as channel:
        block.publish(1)
        block.close()
        assert channel.closed
        assert (channel.next(1) or pytest.fail("no sample")).seq == 1
        start = time.monotonic()
        assert channel.next(30) is None
        assert time.monotonic() - start < 20


@pytest.mark.parametrize(
    "offset, value, problem",
    [(0, 0xDEADBEEF, "bad magic"), (4, 9, r"version 9 is not supported \(1 is\)")],
)
def test_a_bad_block_raises_bad_channel_naming_the_problem(
    server: FakeServer, block: RingBlock, offset: int, value: int, problem: str
) -> None:
    block.set_header(offset, value)
    server.offers.append(block)
    before = open_descriptors()
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match=problem):
            client.attitude_channel()
    assert settle(before) == before


def test_a_reply_without_a_descriptor_raises_bad_channel(server: FakeServer) -> None:
    server.offers.append(None)
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="no file descriptor"):
            client.attitude_channel()


def test_descriptors_are_claimed_in_order_and_unclaimed_ones_closed(server: FakeServer) -> None:
    first, second, stray = RingBlock(), RingBlock(), RingBlock()
    first.publish(100)
    second.publish(200)
    server.offers += [first, second]
    before = open_descriptors()
    with gport.Client(server.path) as client:
        with client.attitude_channel() as a, client.attitude_channel() as b:
            assert (a.latest() or pytest.fail()).seq == 100
            assert (b.latest() or pytest.fail()).seq == 200
        connected = open_descriptors()
        server.push({"jsonrpc": "2.0", "method": "link", "params": {"state": "up"}}, stray.fd)
        assert isinstance(client.next_notification(timeout=5), gport.Link)
        assert open_descriptors() == connected + 1  # the stray one, held
    assert settle(before) == before
    for ring in (first, second, stray):
        ring.release()


def test_shared_memory_subscription_delivers_samples_and_socket_notifications(
    server: FakeServer, block: RingBlock
) -> None:
    block.publish(1)  # before subscribing: not delivered
    server.offers.append(block)
    with gport.Client(server.path) as client:
        result = client.subscribe(["attitude", "link"], shared_memory=True)
        assert result.topics == ("link", "attitude") and server.subscribed == ["link"]
        assert client.next_notification(timeout=0.05) is None
        block.publish(2)
        sample = client.next_notification(timeout=5)
        assert isinstance(sample, gport.Attitude) and sample.seq == 2
        server.push({"jsonrpc": "2.0", "method": "link", "params": {"state": "stale"}})
        link = client.next_notification(timeout=5)
        assert isinstance(link, gport.Link) and link.state == "stale"
        client.unsubscribe("attitude")
        block.publish(3)
        assert client.next_notification(timeout=0.1) is None


def test_attitude_stream_from_shared_memory(server: FakeServer, block: RingBlock) -> None:
    server.offers.append(block)
    with gport.Client(server.path) as client:
        stream = client.attitude_stream(shared_memory=True, timeout=5)
        def publish() -> None:
            for n in (1, 2, 3):
                block.publish(n)

        threading.Timer(0.05, publish).start()
        seqs = [next(stream).seq for _ in range(3)]
        stream.close()
        assert seqs == [1, 2, 3]
        assert server.subscribed is None  # nothing asked of the socket


def test_async_client_channel_and_shared_memory_subscription(
    server: FakeServer, block: RingBlock
) -> None:
    other = RingBlock()
    other.publish(41)
    server.offers += [other, block]

    async def run() -> None:
        async with gport.AsyncClient(server.path) as client:
            with await client.attitude_channel() as channel:
                assert (channel.latest() or pytest.fail()).seq == 41
            result = await client.subscribe(["attitude", "motion"], shared_memory=True)
            assert result.topics == ("motion", "attitude")
            asyncio.get_running_loop().call_later(0.05, block.publish, 5)
            sample = await client.next_notification(timeout=5)
            assert isinstance(sample, gport.Attitude) and sample.seq == 5
            server.push({"jsonrpc": "2.0", "method": "link", "params": {"state": "up"}})
            assert isinstance(await client.next_notification(timeout=5), gport.Link)

    before = open_descriptors()
    asyncio.run(run())
    assert settle(before) == before
    other.release()


def test_async_client_rejects_a_bad_block(server: FakeServer, block: RingBlock) -> None:
    block.set_header(0, 0)
    server.offers.append(block)

    async def run() -> None:
        async with gport.AsyncClient(server.path) as client:
            with pytest.raises(gport.BadChannel, match="bad magic"):
                await client.attitude_channel()
            assert client.connected

    asyncio.run(run())
