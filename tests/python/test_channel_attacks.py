"""A hostile gportd against the Python client's shared-memory channel (issue
22, items 6 and 8): blocks without seals, truncated or of the wrong size,
a slot count rewritten after the check, more descriptors than announced,
descriptors attached to notifications, late replies to timed-out
attitude_channel calls, and a CPU without fences."""

from __future__ import annotations

import ctypes
import fcntl
import gc
import os
import threading
import time
import weakref
from typing import Any, Callable, Iterator

import pytest

import gport
from gport import _ring
from fake_gportd import (
    F_ADD_SEALS,
    SEALS,
    FakeServer,
    Offer,
    RingBlock,
    WakeBlock,
    open_descriptors,
)


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
    fcntl.fcntl(truncated.fd, F_ADD_SEALS, SEALS)
    server.offers.append(Offer(truncated, result={"size": 64 + 64 * 128, "slots": 64}))
    with gport.Client(server.path) as client:
        with pytest.raises(gport.BadChannel, match="ring is 4096 bytes, not the 8256 expected"):
            client.attitude_channel()
        assert client.connected
    truncated.release()


def test_a_block_that_may_shrink_is_refused_before_its_size_is_looked_at(
    server: FakeServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    """The server shrinks the block to nothing and seals it right after the
    client's first look at it (an fstat), as one holding another descriptor
    could. Before: the size was looked at first, then the seals (now
    there), and the block was mapped at its old size: SIGBUS at the first
    read. Now the seals come first: refused, fstat never called."""
    block = RingBlock(seals=None)
    fcntl.fcntl(block.fd, F_ADD_SEALS, SEALS & ~_ring.F_SEAL_SHRINK)
    block.wake.release()
    block.wake = WakeBlock()  # sealed as gportd's
    server.offers.append(block)
    real_fstat = os.fstat
    raced: list[int] = []

    def racing_fstat(fd: int) -> os.stat_result:
        info = real_fstat(fd)
        if not raced:
            os.ftruncate(block.fd, 0)
            fcntl.fcntl(block.fd, F_ADD_SEALS, _ring.F_SEAL_SHRINK)
            raced.append(fd)
        return info

    with gport.Client(server.path) as client:
        monkeypatch.setattr(os, "fstat", racing_fstat)
        with pytest.raises(gport.BadChannel, match=r"ring is not sealed .* \(seals 0x14;"):
            client.attitude_channel()
        monkeypatch.undo()
        assert not raced, "fstat came before the seals"
        assert client.connected
    block.release()


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


LINK_UP = {"jsonrpc": "2.0", "method": "link", "params": {"state": "up"}}


@pytest.mark.parametrize("asynchronous", [False, True])
def test_timed_out_channel_calls_leave_no_room_for_descriptors(
    server: FakeServer, asynchronous: bool
) -> None:
    """Review finding 6. Before: a timed-out call's id stayed awaited, so
    three timeouts let the six pipes of one notification stay open until
    disconnect."""
    block = RingBlock()
    server.offers.extend(Offer(block, late=True) for _ in range(3))
    r, w = os.pipe()
    counts: list[int] = []

    def attack(channel: Callable[[], object], note: Callable[[], object]) -> None:
        connected = open_descriptors()
        for _ in range(3):
            with pytest.raises(gport.Timeout):
                channel()
        server.push(LINK_UP, [r, w, r, w, r, w])
        assert note()
        counts.append(open_descriptors() - connected)
        server.release_held()  # the three late replies, two descriptors each
        server.push(LINK_UP)
        assert note()
        counts.append(open_descriptors() - connected)

    if asynchronous:
        import asyncio

        async def run() -> None:
            async with gport.AsyncClient(server.path) as client:
                await client.subscribe("link")  # the fake has accepted us
                client.timeout = 0.05
                loop = asyncio.get_running_loop()
                await loop.run_in_executor(
                    None,
                    lambda: attack(
                        lambda: asyncio.run_coroutine_threadsafe(
                            client.attitude_channel(), loop
                        ).result(),
                        lambda: asyncio.run_coroutine_threadsafe(
                            client.next_notification(timeout=5), loop
                        ).result(),
                    ),
                )

        asyncio.run(run())
    else:
        with gport.Client(server.path) as client:
            client.subscribe("link")
            client.timeout = 0.05
            attack(client.attitude_channel, lambda: client.next_notification(timeout=5))
    assert counts == [0, 0]
    os.close(r)
    os.close(w)
    block.release()


@pytest.mark.parametrize("asynchronous", [False, True])
def test_a_late_channel_reply_is_closed_and_the_awaited_one_mapped(
    server: FakeServer, asynchronous: bool
) -> None:
    abandoned, awaited = RingBlock(), RingBlock()
    server.offers.extend([Offer(abandoned, late=True), awaited])  # the late one answered first
    opened: list[gport.AttitudeChannel] = []
    extra: list[int] = []

    if asynchronous:
        import asyncio

        async def run() -> None:
            async with gport.AsyncClient(server.path) as client:
                await client.subscribe("link")
                connected = open_descriptors()
                client.timeout = 0.05
                with pytest.raises(gport.Timeout):
                    await client.attitude_channel()
                client.timeout = 5
                opened.append(await client.attitude_channel())
                extra.append(open_descriptors() - connected)

        asyncio.run(run())
    else:
        with gport.Client(server.path) as client:
            client.subscribe("link")
            connected = open_descriptors()
            client.timeout = 0.05
            with pytest.raises(gport.Timeout):
                client.attitude_channel()
            client.timeout = 5
            opened.append(client.attitude_channel())
            extra.append(open_descriptors() - connected)
    assert extra == [0]
    awaited.publish(7)
    assert (opened[0].next(1) or pytest.fail()).seq == 7
    opened[0].close()
    abandoned.release()
    awaited.release()


def test_without_fences_only_x86_64_reads_with_plain_loads(
    server: FakeServer, monkeypatch: pytest.MonkeyPatch
) -> None:
    block = RingBlock()
    server.offers += [block]
    monkeypatch.setattr(_ring, "_fenced", [(None, None)])  # libgport-client not found
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
    # Review finding 10: the wake word, published and the flags are read
    # with the library's acquire loads (1.3), not plain ctypes loads.
    loads = _ring.load_fenced_loads()
    assert loads is not None, "libgport-client 1.3 exports gport_ring_published and co."
    block = RingBlock()
    mapping = _ring.Mapping(block.fd, block.wake.fd, block.slots, block.size)
    assert mapping._loads is not None
    block.publish(5)
    block.close()
    assert (mapping.published(), mapping.closed()) == (1, True)  # one sample
    assert mapping.wake_word() == ctypes.c_uint32.from_buffer_copy(block.wake.map, 16).value
    del mapping
    block.release()


def test_readers_in_two_threads_never_get_each_others_samples(server: FakeServer) -> None:
    """Two threads read one connection's channel (two readers of one
    mapping) while the server publishes. Before: the fenced read copied the
    sample out of one buffer per mapping, with the GIL released while the
    library wrote into it, so a thread could return the other's sample, or
    a mix of two (a few hundred in 2 s on x86_64)."""
    block = RingBlock()
    server.offers.append(block)
    stop = time.monotonic() + 2.0
    wrong: list[str] = []
    taken = [0, 0]

    def read(channel: gport.AttitudeChannel, index: int) -> None:
        last = 0
        while time.monotonic() < stop:
            sample = channel.next(0.05)
            if sample is None:
                continue
            taken[index] += 1
            whole = sample.imu.roll == sample.seq / 10 and sample.t == 1.7e9 + sample.seq / 100
            if sample.seq <= last or not whole:
                wrong.append(f"after {last}: seq {sample.seq}, roll {sample.imu.roll}")
            last = sample.seq

    def publish() -> None:
        seq = 0
        while time.monotonic() < stop:
            seq += 1
            block.publish(seq)

    with gport.Client(server.path) as client:
        channels = [client.attitude_channel(), client.attitude_channel()]
        threads = [threading.Thread(target=read, args=(c, i)) for i, c in enumerate(channels)]
        threads.append(threading.Thread(target=publish))
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join()
        for channel in channels:
            channel.close()
    block.release()
    assert all(taken), f"each reader took samples: {taken}"
    assert not wrong, f"{len(wrong)} of {sum(taken)} samples were not the one asked for: {wrong[:3]}"


def test_the_wake_relay_only_moves_forward(monkeypatch: pytest.MonkeyPatch) -> None:
    """Review finding 8. Before: a thread with an older value of the word
    moved the relay back and woke every waiter again, once per stale value."""
    block = RingBlock()
    mapping = _ring.Mapping(block.fd, block.wake.fd, block.slots, block.size)
    wakes: list[int] = []
    monkeypatch.setattr(mapping, "wake_all", lambda: wakes.append(1))
    word = mapping.wake_word()
    assert not mapping.relay(word)  # nothing new
    assert mapping.relay(word + 2)
    assert not mapping.relay(word + 1)  # stale: no wake, not moved back ...
    assert not mapping.relay(word + 2)  # ... so this is no news either
    assert mapping.relay(word + 3)
    assert len(wakes) == 2
    del mapping
    block.release()


def test_the_wake_relay_follows_the_word_around_its_wrap() -> None:
    block = RingBlock()
    mapping = _ring.Mapping(block.fd, block.wake.fd, block.slots, block.size)
    word = mapping.wake_word()
    for step in range(1, 5):  # forward to 2**32 - 1 in steps the relay takes as news
        assert mapping.relay(word + step * (2**32 - 1 - word) // 4)
    assert not mapping.relay(0xFFFFFFFF)
    assert mapping.relay(0)
    assert not mapping.relay(0xFFFFFFFF)
    del mapping
    block.release()


def read_only_memfd_maps() -> int:
    with open("/proc/self/maps") as maps:
        return sum(1 for line in maps if " r--s " in line and "memfd:" in line)


@pytest.mark.parametrize("asynchronous", [False, True])
def test_a_mapping_is_unmapped_with_its_last_reference_without_the_collector(
    server: FakeServer, asynchronous: bool
) -> None:
    """Review finding 9. Before: the mapping's reader was a closure (or a
    bound method) referring back to it, a cycle only the collector frees:
    with gc disabled the blocks stayed mapped for good."""
    block = RingBlock()
    server.offers.append(block)
    before = read_only_memfd_maps()
    refs: list[weakref.ref[Any]] = []
    gc.disable()
    try:
        if asynchronous:
            import asyncio

            async def run() -> None:
                async with gport.AsyncClient(server.path) as client:
                    channel = await client.attitude_channel()
                    refs.append(weakref.ref(channel._mapping))
                    assert read_only_memfd_maps() == before + 2
                    del channel

            asyncio.run(run())
        else:
            with gport.Client(server.path) as client:
                channel = client.attitude_channel()
                refs.append(weakref.ref(channel._mapping))
                assert read_only_memfd_maps() == before + 2
                del channel
        assert refs[0]() is None
        assert read_only_memfd_maps() == before
    finally:
        gc.enable()
    block.release()
