"""The shared-memory attitude channel against a fake gportd (fake_gportd.py):
the two blocks of a connection, shared by its later requests; the checks
of each block; next/latest/missed/closed; waking one waiter per connection
and passing it on; the transparent ``shared_memory=True`` subscription of
both clients. The attacks of a hostile server are in test_channel_attacks.py."""

from __future__ import annotations

import asyncio
import os
import threading
import time
from typing import Iterator

import pytest

import gport
from fake_gportd import FakeServer, Offer, RingBlock, open_descriptors

# The tests load the built libgport-client, except in a sanitizer build ("none").
FENCED = os.environ.get("GPORT_CLIENT_LIBRARY", "") not in ("", "none")


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
        assert channel.fenced == FENCED  # the built libgport-client (GPORT_CLIENT_LIBRARY)
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
    [
        (0, 0xDEADBEEF, "bad magic"),
        (4, 1, r"version 1 is not supported \(2 is\)"),
        (16, 32, "the block is larger than its ring"),
    ],
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


def test_a_version_1_daemon_is_named(server: FakeServer, block: RingBlock) -> None:
    server.offers.append(Offer(block, result={"version": 1}))
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match=r"version 1; .* \(update gportd\)"):
            client.attitude_channel()


def test_a_reply_without_its_descriptors_raises_bad_channel(server: FakeServer) -> None:
    server.offers.append(Offer(None, result={"descriptors": 2}))
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match=r"carried 0 file descriptor\(s\), not the 2"):
            client.attitude_channel()


def test_descriptors_0_without_a_channel_on_the_connection_is_a_clear_error(
    server: FakeServer,
) -> None:
    with gport.Client(server.path) as client:  # no offer: "descriptors":0
        with pytest.raises(gport.BadChannel, match="this connection has none; reconnect"):
            client.attitude_channel()


def test_later_requests_share_the_connections_mapping_each_with_its_own_cursor(
    server: FakeServer, block: RingBlock
) -> None:
    server.offers.append(block)
    before = open_descriptors()
    with gport.Client(server.path) as client:
        first = client.attitude_channel()
        block.publish(1)
        second = client.attitude_channel()  # "descriptors":0
        assert (first.next(1) or pytest.fail()).seq == 1
        assert (second.next(1) or pytest.fail()).seq == 1
        block.publish(2)
        assert (first.next(1) or pytest.fail()).seq == 2
        first.close()
        assert (second.next(1) or pytest.fail()).seq == 2  # still mapped
        # The client's socket and the fake's end of it; both blocks' descriptors closed.
        assert open_descriptors() == before + 2
    assert settle(before) == before


def test_one_wake_per_connection_reaches_every_waiting_thread_of_the_process(
    server: FakeServer, block: RingBlock
) -> None:
    """gportd wakes ONE waiter on a connection's word; the first thread to
    see the new value passes it on to the others."""
    server.offers.append(block)
    with gport.Client(server.path) as client:
        readers = [client.attitude_channel() for _ in range(4)]
        got: list[int] = []
        lock = threading.Lock()

        def read(channel: gport.AttitudeChannel) -> None:
            sample = channel.next(5)
            with lock:
                got.append(-1 if sample is None else sample.seq)

        threads = [threading.Thread(target=read, args=(r,)) for r in readers]
        for thread in threads:
            thread.start()
        time.sleep(0.3)  # all four in FUTEX_WAIT
        start = time.monotonic()
        block.wake.wakes = 1  # as gportd: one waiter per connection
        block.publish(9)
        for thread in threads:
            thread.join()
        assert sorted(got) == [9, 9, 9, 9]
        assert time.monotonic() - start < 4  # not the 5 s timeout


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
        client.subscribe("attitude", shared_memory=True)  # again: the cached mapping
        block.wake.wakes = 1
        block.publish(4)
        again = client.next_notification(timeout=5)
        assert isinstance(again, gport.Attitude) and again.seq == 4


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
    block.publish(41)
    server.offers += [block]

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


def test_async_client_rejects_a_bad_block(server: FakeServer, block: RingBlock) -> None:
    block.set_header(0, 0)
    server.offers.append(block)

    async def run() -> None:
        async with gport.AsyncClient(server.path) as client:
            with pytest.raises(gport.BadChannel, match="bad magic"):
                await client.attitude_channel()
            assert client.connected

    asyncio.run(run())
