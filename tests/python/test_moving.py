"""`with client.moving(...)`: the speed kept alive, and stopped on leaving."""

from __future__ import annotations

import subprocess
import sys
import time

import pytest

import gport
from conftest import Daemon, eventually


def test_moving_keeps_the_speed_alive_past_its_lease(client: gport.Client) -> None:
    with client.moving(yaw=10, lease_ms=600) as movement:
        time.sleep(1.5)  # several leases: the re-sends keep it running
        motion = client.status().motion
        assert motion is not None and motion.mode == "speed"
        assert motion.speed == gport.Axes(0, 0, 10)
        assert movement.alive and movement.error is None
    status = client.status()
    assert status.motion is None
    assert status.counters.motion_updates > 0


def test_moving_stops_when_the_block_raises(client: gport.Client) -> None:
    stops = client.status().counters.stops_sent
    with pytest.raises(RuntimeError, match="lost the target"):
        with client.moving(yaw=20, pitch=-5, lease_ms=500):
            motion = client.status().motion
            assert motion is not None and motion.speed == gport.Axes(0, -5, 20)
            raise RuntimeError("lost the target")
    assert client.status().motion is None
    # Counted once the stop frame is written to the line, which may come just
    # after the reply (the write is asynchronous): wait for it, never assume.
    assert eventually(lambda: client.status().counters.stops_sent > stops)


def test_moving_update_changes_the_speed(client: gport.Client) -> None:
    with client.moving(yaw=10) as movement:
        result = movement.update(yaw=-10, roll=2)
        assert result is not None and result.speed == gport.Axes(2, 0, -10)
        motion = client.status().motion
        assert motion is not None and motion.speed == gport.Axes(2, 0, -10)
    assert client.status().motion is None


def test_moving_duration_caps_the_movement(client: gport.Client) -> None:
    with client.moving(yaw=10, lease_ms=300, duration_ms=400) as movement:
        deadline = time.monotonic() + 10
        while client.status().motion is not None and time.monotonic() < deadline:
            time.sleep(0.05)
        assert client.status().motion is None  # ended by its duration, not by the block
        assert movement.error is None




def test_moving_refused_speed_raises_at_once(client: gport.Client) -> None:
    with pytest.raises(gport.InvalidParams):
        with client.moving(yaw=500):
            pytest.fail("the block must not run")
    with pytest.raises(ValueError):
        with client.moving(yaw=5, lease_ms=10):
            pytest.fail("the block must not run")


def test_moving_raises_the_keepalive_error_when_control_is_taken(
    daemon: Daemon, client: gport.Client
) -> None:
    with daemon.client() as other:
        with pytest.raises(gport.Busy):
            with client.moving(yaw=10, lease_ms=300) as movement:
                other.acquire()  # preempts the motion; the re-sends are refused
                assert eventually(lambda: not movement.alive)
                assert isinstance(movement.error, gport.Busy)
        assert client.status().motion is None


HANGING_CHILD = """
import os, signal, sys
import gport
with gport.Client(sys.argv[1]) as client:
    with client.moving(yaw=10, lease_ms=300):
        os.kill(os.getpid(), signal.SIGSTOP)  # hangs: every thread stops, the socket stays open
"""


def test_a_hung_process_is_stopped_by_the_lease(daemon: Daemon, client: gport.Client) -> None:
    client.subscribe("motion")
    child = subprocess.Popen([sys.executable, "-c", HANGING_CHILD, daemon.socket])
    try:
        reasons: list[str] = []
        while "lease_expired" not in reasons:
            event = client.next_notification("motion", timeout=10)
            assert isinstance(event, gport.MotionEvent), f"no motion event; so far {reasons}"
            if event.change == "ended" and event.reason is not None:
                reasons.append(event.reason)
        assert client.status().motion is None
        assert child.poll() is None, "the child is still there, hung"
    finally:
        child.kill()
        child.wait(timeout=10)
