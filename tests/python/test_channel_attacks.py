"""A hostile gportd against the Python client's shared-memory channel (issue
22, items 6 and 8): blocks without seals, truncated or of the wrong size,
a slot count rewritten after the check, more descriptors than announced,
descriptors attached to notifications, and a CPU without fences."""

from __future__ import annotations

import os
import threading
import time
from typing import Iterator

import pytest

import gport
from gport import _ring
from fake_gportd import FakeServer, Offer, RingBlock, open_descriptors


@pytest.fixture
def server() -> Iterator[FakeServer]:
    fake = FakeServer()
    yield fake
    fake.close()


def settle(before: int) -> int:
    deadline = time.monotonic() + 5
    while open_descriptors() != before and time.monotonic() < deadline:
        time.sleep(0.01)
    return open_descriptors()


def test_a_block_without_seals_is_refused(server: FakeServer) -> None:
    unsealed = RingBlock(seals=None)
    server.offers.append(unsealed)
    before = open_descriptors()
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="ring is not sealed against shrinking"):
            client.attitude_channel()
    assert settle(before) == before
    unsealed.release()


def test_a_wake_block_without_seals_is_refused(server: FakeServer) -> None:
    block = RingBlock()
    block.wake.release()
    block.wake = type(block.wake)(seals=None)
    server.offers.append(block)
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="wake block is not sealed"):
            client.attitude_channel()
    block.release()


def test_a_truncated_block_is_refused_before_it_is_mapped(server: FakeServer) -> None:
    """Before: mapped at the announced size, then read past the end: SIGBUS."""
    truncated = RingBlock(seals=None)
    os.ftruncate(truncated.fd, 4096)
    server.offers.append(Offer(truncated, result={"size": 64 + 64 * 128, "slots": 64}))
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="ring is 4096 bytes, not the 8256 expected"):
            client.attitude_channel()
        assert client.connected
    truncated.release()


def test_a_reply_whose_size_does_not_fit_its_slots_is_refused(server: FakeServer) -> None:
    block = RingBlock()
    server.offers.append(Offer(block, result={"size": 1 << 30}))
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="size = 1073741824 does not fit 64 slots"):
            client.attitude_channel()
    block.release()


def test_a_slot_count_rewritten_after_the_check_does_not_crash_the_reader(
    server: FakeServer,
) -> None:
    """The server keeps a writable mapping and rewrites slot_count: 0 and
    2**31 crashed readers that looked again."""
    block = RingBlock()
    server.offers.append(block)
    with gport.Client(server.path) as client:
        channel = client.attitude_channel()
        for seq in range(1, 6):
            block.publish(seq)
        for hostile in (0, 2**31, 3, 2**32 - 1):
            block.set_header(_ring.OFF_SLOT_COUNT, hostile)
            latest = channel.latest()
            assert latest is not None and latest.seq == 5
        block.set_header(_ring.OFF_PUBLISHED, 2**31)  # far beyond the ring
        block.set_header(_ring.OFF_PUBLISHED + 4, 2**30)
        assert channel.latest() is None and channel.next(0) is None
        channel.close()
    block.release()


def test_more_descriptors_than_announced_are_closed_at_once(server: FakeServer) -> None:
    block = RingBlock()
    extras = [os.pipe() for _ in range(3)]
    server.offers.append(
        Offer(block, fds=[block.fd, block.wake.fd] + [r for r, _ in extras] + [extras[0][1]])
    )
    before = open_descriptors()
    with gport.Client(server.path) as client:
        channel = client.attitude_channel()
        block.publish(3)
        assert (channel.next(1) or pytest.fail()).seq == 3
        assert open_descriptors() == before + 2  # both ends of the socket: none of the six kept
    assert settle(before) == before
    for r, w in extras:
        os.close(r)
        os.close(w)
    block.release()


def test_an_announcement_other_than_0_or_2_is_refused_and_its_descriptors_closed(
    server: FakeServer,
) -> None:
    block = RingBlock()
    server.offers.append(Offer(block, result={"descriptors": 5}))
    before = open_descriptors()
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="descriptors = 5; gportd sends 2 or 0"):
            client.attitude_channel()
        assert open_descriptors() == before + 2  # both ends of the socket
    block.release()


@pytest.mark.parametrize("asynchronous", [False, True])
def test_3000_notifications_carrying_pipes_leave_the_descriptor_count_flat(
    server: FakeServer, asynchronous: bool
) -> None:
    """Before: every descriptor stayed open until the connection closed
    (3,000 notifications with a pipe each: 3,006 open descriptors)."""
    r, w = os.pipe()
    note = {"jsonrpc": "2.0", "method": "link", "params": {"state": "up"}}
    before = open_descriptors()
    most = 0

    def flood() -> threading.Thread:
        def push() -> None:
            for _ in range(3000):
                server.push(note, [r, w])

        thread = threading.Thread(target=push)
        thread.start()
        return thread

    if asynchronous:
        import asyncio

        async def run() -> None:
            nonlocal most
            async with gport.AsyncClient(server.path) as client:
                await client.subscribe("link")  # the fake has accepted us
                connected = open_descriptors()  # with the event loop's own
                thread = flood()
                while thread.is_alive() or await client.next_notification(timeout=0.5):
                    most = max(most, open_descriptors() - connected + before + 2)
                    await asyncio.sleep(0)
                thread.join()

        asyncio.run(run())
    else:
        with gport.Client(server.path) as client:
            client.subscribe("link")
            thread = flood()
            while thread.is_alive() or client.next_notification(timeout=0.5):
                most = max(most, open_descriptors())
            thread.join()
    # Both ends of the socket, and at most the pair of the message being
    # received, for the instant before the reader closes it: flat, not 6,000.
    assert most <= before + 4
    assert settle(before) == before
    os.close(r)
    os.close(w)


def test_without_fences_only_x86_64_reads_with_plain_loads(
    server: FakeServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    block = RingBlock()
    server.offers += [block]
    monkeypatch.setattr(_ring, "_fenced", [None])  # libgport-client not found
    monkeypatch.setattr(_ring, "IS_X86_64", False)
    monkeypatch.setattr(_ring, "NAME", "aarch64 (64-bit)")
    with gport.Client(server.path) as client:
        with pytest.raises(
            gport.BadChannel, match=r"needs libgport-client on this CPU \(aarch64 \(64-bit\)\)"
        ):
            client.attitude_channel()
        assert client.connected  # the socket keeps working
    monkeypatch.setattr(_ring, "IS_X86_64", True)
    other = RingBlock()
    server.offers += [other]
    with gport.Client(server.path) as client:
        channel = client.attitude_channel()
        assert not channel.fenced
        other.publish(8)
        assert (channel.next(1) or pytest.fail()).seq == 8
        channel.close()
    block.release()
    other.release()


def test_the_fenced_reader_is_libgport_clients() -> None:
    if os.environ.get(_ring.LIBRARY_ENV) == "none":
        assert _ring.load_fenced_reader() is None
        pytest.skip("GPORT_CLIENT_LIBRARY=none (a sanitizer build): plain loads tested instead")
    read = _ring.load_fenced_reader()
    assert read is not None, "set GPORT_CLIENT_LIBRARY to the built libgport-client.so.1"
