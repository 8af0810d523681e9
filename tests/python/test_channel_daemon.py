"""The shared-memory attitude channel end to end: the Python client against
the real gportd (on gport-sim, or --simulate)."""

from __future__ import annotations

import asyncio
import os
import signal
import subprocess
from typing import Callable

import gport
from conftest import Daemon, link_up
from fake_gportd import open_descriptors


def attitude(client: gport.Client) -> gport.Attitude:
    while True:
        item = client.next_notification(timeout=10)
        assert item is not None, "no notification within 10 s"
        if isinstance(item, gport.Attitude):
            return item


def test_ring_samples_match_the_socket_notifications_of_the_same_seq(
    make_daemon: Callable[..., Daemon], start_sim: Callable[..., subprocess.Popen[bytes]]
) -> None:
    daemon = make_daemon(simulate=False)  # its device does not exist yet
    start_sim(os.path.join(daemon.dir, "no-such-tty"), "--form", "24")
    with daemon.client() as on_socket, daemon.client() as on_ring:
        assert link_up(on_socket)
        on_socket.subscribe("attitude")
        result = on_ring.subscribe(["attitude", "link"], shared_memory=True)
        assert result.topics == ("link", "attitude")
        ring = [attitude(on_ring) for _ in range(5)]
        assert [s.seq for s in ring] == sorted({s.seq for s in ring})
        seen: dict[int, gport.Attitude] = {}
        while not seen or max(seen) < ring[-1].seq:
            sample = attitude(on_socket)
            seen[sample.seq] = sample
        assert ring[0].rates is not None  # the 24-byte frames' rates come too
        # A socket subscriber may lose samples on a loaded machine (counted
        # in `dropped`); every one it has must match the ring's.
        common = [sample for sample in ring if sample.seq in seen]
        assert len(common) >= 3, f"ring {[s.seq for s in ring]}, socket {sorted(seen)}"
        for sample in common:
            twin = seen[sample.seq]
            assert (sample.t, sample.imu, sample.hall) == (twin.t, twin.imu, twin.hall)
            assert sample.rates == twin.rates


def test_link_notifications_still_arrive_on_the_socket(
    make_daemon: Callable[..., Daemon], start_sim: Callable[..., subprocess.Popen[bytes]]
) -> None:
    daemon = make_daemon(simulate=False)
    sim = start_sim(os.path.join(daemon.dir, "no-such-tty"))
    with daemon.client() as client:
        assert link_up(client)
        client.subscribe(["attitude", "link"], shared_memory=True)
        attitude(client)
        sim.terminate()  # the gimbal goes away
        while True:
            item = client.next_notification(timeout=10)
            assert item is not None, "no link event"
            if isinstance(item, gport.Link):
                assert item.state != "up"
                break


def test_the_channel_closes_with_the_daemon_and_reconnect_reopens_it(daemon: Daemon) -> None:
    with daemon.client() as client:
        assert link_up(client)
        channel = client.attitude_channel()
        assert channel.next(10) is not None and not channel.closed
        client.subscribe(["attitude", "link"], shared_memory=True)
        attitude(client)
        assert daemon.process is not None
        daemon.process.send_signal(signal.SIGTERM)
        daemon.process.wait(timeout=10)
        assert channel.closed
        assert channel.latest() is not None  # the mapping is ours
        channel.close()
        daemon.start()
        client.reconnect()
        assert link_up(client)
        sample = attitude(client)  # from the new daemon's ring
        assert sample.seq >= 1


def test_opening_and_closing_channels_leaks_no_descriptor(daemon: Daemon) -> None:
    with daemon.client() as warm:
        assert link_up(warm)
        status = warm.status()
        assert status.client is not None and not status.client.attitude_channel
        warm.attitude_channel().close()
        status = warm.status()
        assert status.client is not None and status.client.attitude_channel
        assert status.attitude_channel_clients == 1
    before = open_descriptors()
    for _ in range(5):
        with daemon.client() as client:
            client.attitude_channel().close()
            client.subscribe("attitude", shared_memory=True)
            attitude(client)
    assert open_descriptors() == before


def test_asyncio_shared_memory_subscription(daemon: Daemon) -> None:
    async def run() -> None:
        async with gport.AsyncClient(daemon.socket) as client:
            await client.subscribe(["attitude", "motion"], shared_memory=True)
            seqs = []
            async for sample in client.attitude_stream(shared_memory=True, timeout=10):
                seqs.append(sample.seq)
                if len(seqs) == 3:
                    break
            assert seqs == sorted(set(seqs))

    asyncio.run(run())
