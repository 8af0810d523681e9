"""Subscriptions, streams and notifications interleaved with replies."""

from __future__ import annotations

import os
import subprocess
import time
from typing import Callable

from conftest import Daemon

import gport


def test_motion_events(client: gport.Client) -> None:
    subscription = client.subscribe(["link", "motion"])
    assert set(subscription.topics) == {"link", "motion"}
    client.speed(yaw=10, duration_ms=5000)
    started = client.next_notification("motion", timeout=5)
    assert isinstance(started, gport.MotionEvent)
    assert started.change == "started" and started.mode == "speed"
    assert started.speed == gport.Axes(0, 0, 10) and started.owner is not None
    client.stop()
    ended = client.next_notification("motion", timeout=5)
    assert isinstance(ended, gport.MotionEvent)
    assert ended.change == "ended" and ended.reason == "stop"




def test_attitude_stream_yields_samples_and_unsubscribes(client: gport.Client) -> None:
    samples = []
    for sample in client.attitude_stream(rate=20):
        samples.append(sample)
        if len(samples) == 3:
            break
    assert all(isinstance(s, gport.Attitude) for s in samples)
    assert samples[0].seq < samples[1].seq < samples[2].seq
    assert client.unsubscribe().topics == ()  # the stream already unsubscribed attitude


def test_notifications_arriving_during_a_call_are_kept(client: gport.Client) -> None:
    client.subscribe("motion")
    stream = client.attitude_stream(rate=None)  # every sample
    first = next(stream)
    for _ in range(10):
        client.status()  # samples arrive while these wait for replies
    client.speed(yaw=5, duration_ms=2000)
    second = next(stream)
    assert second.seq > first.seq
    stream.close()
    event = client.next_notification("motion", timeout=5)
    assert isinstance(event, gport.MotionEvent) and event.change == "started"
    client.stop()


def test_next_notification_times_out_with_none(client: gport.Client) -> None:
    client.subscribe("motion")
    assert client.next_notification("motion", timeout=0.1) is None


def test_notifications_iterator_in_arrival_order(client: gport.Client) -> None:
    client.subscribe(["motion"])
    client.subscribe("attitude", max_rate_hz=50)
    client.speed(pitch=5, duration_ms=3000)
    client.stop()
    changes = []
    for item in client.notifications():
        if isinstance(item, gport.MotionEvent):
            changes.append(item.change)
            if item.change == "ended":
                break
    assert changes == ["started", "ended"]


def link_states(client: gport.Client, until: set[str]) -> list[str]:
    """The link notifications' states, up to the first in `until` (10 s at most)."""
    states: list[str] = []
    deadline = time.monotonic() + 10
    while not states or states[-1] not in until:
        left = deadline - time.monotonic()
        event = client.next_notification("link", timeout=max(left, 0))
        if event is None:
            break
        assert isinstance(event, gport.Link)
        states.append(event.state)
    return states


def test_link_events_and_rates_with_gport_sim(
    make_daemon: Callable[..., Daemon], start_sim: Callable[..., subprocess.Popen[bytes]]
) -> None:
    daemon = make_daemon(simulate=False)  # its device does not exist yet
    device = os.path.join(daemon.dir, "no-such-tty")
    with daemon.client() as client:
        client.subscribe("link")
        sim = start_sim(device, "--form", "24")  # the gimbal appears: 24-byte frames
        assert link_states(client, {"up"})[-1:] == ["up"]
        sample = client.attitude()
        assert sample.rates is not None and isinstance(sample.rates.imu, gport.ImuRates)
        sim.terminate()  # the gimbal goes
        sim.wait(timeout=10)
        assert link_states(client, {"stale", "down"})[-1:] in (["stale"], ["down"])
