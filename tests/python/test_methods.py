"""Every method of gport.Client against gportd --simulate."""

from __future__ import annotations

import os
from typing import Callable

import pytest
from conftest import Daemon, eventually, skip_without_wait

import gport


def test_status_is_typed(client: gport.Client) -> None:
    status = client.status()
    assert status.api_version == 1
    assert status.link == gport.Link("up", status.link.reason)
    assert status.device_open
    assert status.counters.attitude_frames > 0
    assert status.motion is None and status.controller is None
    assert status.recording == "unknown"
    assert isinstance(status.client, gport.Me) and status.client.pid > 0
    assert status.raw["api_version"] == 1


def test_attitude_sample(client: gport.Client) -> None:
    sample = client.attitude()
    assert sample.seq > 0 and sample.t > 1e9
    assert isinstance(sample.imu, gport.Axes) and isinstance(sample.hall, gport.Axes)
    assert sample.age_ms is not None and sample.age_ms >= 0


def test_speed_then_stop(client: gport.Client) -> None:
    stops = client.status().counters.stops_sent
    result = client.speed(yaw=10, duration_ms=5000, lease_ms=5000)
    assert result.speed == gport.Axes(0, 0, 10)
    assert result.duration_ms == 5000 and result.clamped == ()
    motion = client.status().motion
    assert motion is not None and motion.mode == "speed" and motion.speed == gport.Axes(0, 0, 10)
    client.stop()
    assert client.status().motion is None
    # stops_sent counts zero speeds written to the device: gportd paces its
    # writes at the line rate, so the count follows the reply shortly.
    assert eventually(lambda: client.status().counters.stops_sent > stops)


def test_speed_out_of_range_is_invalid_params(client: gport.Client) -> None:
    with pytest.raises(gport.InvalidParams) as raised:
        client.speed(yaw=400)
    assert raised.value.code == -32602
    assert "yaw" in raised.value.message


def test_speed_clamped_to_soft_limit(make_daemon: Callable[..., Daemon]) -> None:
    daemon = make_daemon({"limits": {"max_speed": 50}})
    with daemon.client() as client:
        result = client.speed(yaw=80, duration_ms=500, clamp=True)
        assert result.speed.yaw == 50 and result.clamped == ("yaw",)
        client.stop()


def test_center_clamped_into_the_soft_limits(make_daemon: Callable[..., Daemon]) -> None:
    daemon = make_daemon({"limits": {"pitch": {"min": -60, "max": -10}}})
    with daemon.client() as client:
        result = client.center()
        assert result.target == gport.Axes(0, -10, 0)
        assert result.clamped == ("pitch",)
        assert client.center().clamped == ("pitch",)


def test_angle_center_lock_photo(client: gport.Client) -> None:
    result = client.angle(pitch=-20, yaw=30)
    assert result.sent and result.angle == gport.Axes(0, -20, 30) and result.ended is None
    assert client.center().sent
    client.lock()
    client.photo()


def test_angle_wait_ends_when_reached(client: gport.Client) -> None:
    try:
        result = client.angle(yaw=15, wait=True)
    except gport.InvalidParams as error:
        skip_without_wait(error)
        raise
    assert result.ended is not None
    assert result.ended.reason == "reached"
    assert result.ended.attitude is not None


def test_center_wait_ends(client: gport.Client) -> None:
    try:
        result = client.center(wait=True)
    except gport.InvalidParams as error:
        skip_without_wait(error)
        raise
    assert result.ended is not None and result.ended.reason in ("reached", "timeout")


def test_record_toggle_and_state(client: gport.Client) -> None:
    assert client.record() == gport.RecordResult(True, "unknown")
    with pytest.raises(gport.InvalidParams):
        client.record(on=True)  # the assumed state is unknown
    assert client.record(on=True, force=True) == gport.RecordResult(True, "on")
    assert client.record(on=True) == gport.RecordResult(False, "on")
    assert client.record(on=False) == gport.RecordResult(True, "off")
    with pytest.raises(ValueError):
        client.record(force=True)


def test_limits_are_the_configured_ones(client: gport.Client) -> None:
    limits = client.limits()
    assert limits.pitch == gport.AxisRange(-327.67, 327.67)
    assert limits.max_speed == 327.67
    assert limits.braking_margin_deg == 1.0


def test_settings_read_modify_write(client: gport.Client) -> None:
    before = client.settings()
    after = client.set_settings(dead_zone=(before.dead_zone + 1) % 256)
    assert after.dead_zone == (before.dead_zone + 1) % 256
    assert after.follow_speed == before.follow_speed and after.inverted == before.inverted
    assert client.settings() == after
    with pytest.raises(ValueError):
        client.set_settings()


def test_acquire_release_and_control_block(daemon: Daemon, client: gport.Client) -> None:
    held = client.acquire()
    assert held.you_hold_control and held.controller is not None
    assert client.release() == gport.Control(None, False)
    with daemon.client() as other:
        with client.control() as control:
            assert control.you_hold_control
            with pytest.raises(gport.Busy) as raised:
                other.speed(yaw=5)
            assert raised.value.code == -32003 and "pid" in raised.value.message
            other.stop()  # stop is never restricted by control
        assert client.status().controller is None
        other.center()  # free again


def test_control_released_when_the_block_raises(client: gport.Client) -> None:
    with pytest.raises(KeyError):
        with client.control():
            raise KeyError("boom")
    assert client.status().controller is None


def test_unknown_method_by_name(client: gport.Client) -> None:
    with pytest.raises(gport.MethodNotFound) as raised:
        client.call("fly")
    assert raised.value.code == -32601
    assert client.call("status")["api_version"] == 1


def test_socket_path_from_environment(daemon: Daemon, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("GPORT_SOCKET", daemon.socket)
    with gport.Client() as client:
        assert client.path == daemon.socket
        assert eventually(lambda: client.status().api_version == 1)


def test_module_version_is_the_projects(client: gport.Client) -> None:
    # The module and the daemon ship together, in one version.
    expected = os.environ.get("GPORT_PROJECT_VERSION") or client.status().daemon_version
    assert gport.__version__ == expected
