"""Refusals and transport errors: read-only peer, busy, link down, limits, restarts."""

from __future__ import annotations

import os
import time
from typing import Callable

import pytest
from conftest import Daemon, eventually, link_up

import gport

NOBODY = 65534


def run_as_nobody(socket_path: str, method: str) -> int:
    """Calls `method` as uid/gid 65534 in a forked child; its exit status:
    0 a result, 1 PermissionDenied (-32001), 2 anything else."""
    child = os.fork()
    if child == 0:
        code = 2
        try:
            os.setgroups([])
            os.setgid(NOBODY)
            os.setuid(NOBODY)
            with gport.Client(socket_path) as client:
                client.call(method)
            code = 0
        except gport.PermissionDenied as error:
            code = 1 if error.code == -32001 else 2
        except BaseException:
            code = 2
        finally:
            os._exit(code)
    _, status = os.waitpid(child, 0)
    return os.waitstatus_to_exitcode(status)


@pytest.mark.skipif(os.geteuid() != 0, reason="needs root to connect as another uid")
def test_read_only_peer_gets_permission_denied(make_daemon: Callable[..., Daemon]) -> None:
    daemon = make_daemon({"socket": {"mode": "0666"}, "access": {"control_uids": [4242]}})
    with daemon.client() as watcher:
        assert link_up(watcher)
    assert run_as_nobody(daemon.socket, "center") == 1
    assert run_as_nobody(daemon.socket, "status") == 0, "reading is open to everyone"


def test_link_down_without_a_device(make_daemon: Callable[..., Daemon]) -> None:
    daemon = make_daemon(simulate=False)
    with daemon.client() as client:
        status = client.status()
        assert status.link.state == "down" and not status.device_open
        assert status.attitude_age_ms is None
        with pytest.raises(gport.LinkDown) as raised:
            client.attitude()
        assert raised.value.code == -32000
        with pytest.raises(gport.LinkDown):
            client.photo()


def test_reconnect_after_a_daemon_restart(daemon: Daemon) -> None:
    client = daemon.client()
    assert link_up(client)
    client.subscribe("attitude", max_rate_hz=20)
    daemon.restart()
    with pytest.raises(gport.ConnectionLost):
        for _ in range(100):  # replies may still be in flight before the EOF
            client.status()
            time.sleep(0.05)
    assert not client.connected
    client.reconnect(retry_for=10)
    assert link_up(client)
    sample = client.next_notification("attitude", timeout=10)
    assert isinstance(sample, gport.Attitude), "the attitude subscription is restored"
    client.close()


def test_connect_to_a_missing_socket(daemon: Daemon) -> None:
    with pytest.raises(gport.ConnectionLost) as raised:
        gport.Client(daemon.socket + ".missing")
    assert raised.value.code is None and ".missing" in raised.value.message


def only_client(daemon: Daemon) -> gport.Client:
    """A client in the one slot, once the fixture's readiness probe has left it."""
    for _ in range(100):
        client = daemon.client()
        try:
            client.status()
            return client
        except gport.ConnectionLost:
            client.close()
            time.sleep(0.05)
    raise AssertionError("the only slot stayed taken")


def test_no_slot_closes_with_the_reason(make_daemon: Callable[..., Daemon]) -> None:
    daemon = make_daemon({"socket": {"max_clients": 1, "reserved_command_slots": 0}})
    with only_client(daemon) as first:
        assert first.status().clients == 1
        second = daemon.client()
        with pytest.raises(gport.ConnectionLost) as raised:
            assert eventually(lambda: not second.connected)
            second.status()
        assert "too many clients" in raised.value.message
        second.close()


def test_busy_controller_names_the_holder(daemon: Daemon, client: gport.Client) -> None:
    with daemon.client() as other:
        holder = other.acquire()
        assert holder.controller is not None
        with pytest.raises(gport.Busy) as raised:
            client.angle(yaw=10)
        assert str(holder.controller.pid) in raised.value.message
        with pytest.raises(gport.Busy):
            client.acquire()
