"""The client against a scripted fake daemon: error classes, interleaving,
timeouts, and the reason given with a closed connection."""

from __future__ import annotations

import json
import os
import socket
import tempfile
import threading
import time
from typing import Any, Callable, Iterator

import pytest

import gport

Script = Callable[[socket.socket, Any], None]  # (connection, decoded request)


@pytest.fixture
def fake() -> Iterator[Callable[[Script], str]]:
    """A one-connection server running `script` for each request line."""
    directory = tempfile.mkdtemp(prefix="gport-fake-", dir="/tmp")
    servers: list[socket.socket] = []

    def start(script: Script) -> str:
        path = os.path.join(directory, f"fake{len(servers)}.sock")
        server = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        server.bind(path)
        server.listen(1)
        servers.append(server)

        def serve() -> None:
            connection, _ = server.accept()
            with connection, connection.makefile("rb") as lines:
                for line in lines:
                    script(connection, json.loads(line))

        threading.Thread(target=serve, daemon=True).start()
        return path

    yield start
    for server in servers:
        server.close()


def send(connection: socket.socket, message: dict[str, Any]) -> None:
    connection.sendall((json.dumps(message) + "\n").encode())


CODES = {
    -32700: gport.ParseError,
    -32600: gport.InvalidRequest,
    -32601: gport.MethodNotFound,
    -32602: gport.InvalidParams,
    -32603: gport.InternalError,
    -32000: gport.LinkDown,
    -32001: gport.PermissionDenied,
    -32002: gport.NotAnswering,
    -32003: gport.Busy,
    -32004: gport.NoSlot,
    -32005: gport.TooManyRequests,
    -32099: gport.GportError,
}


def test_each_error_code_has_its_class(fake: Callable[[Script], str]) -> None:
    def script(connection: socket.socket, request: Any) -> None:
        code = int(request["params"]["code"])
        send(connection, {"jsonrpc": "2.0", "id": request["id"],
                          "error": {"code": code, "message": f"refused {code}"}})

    with gport.Client(fake(script)) as client:
        for code, cls in CODES.items():
            with pytest.raises(cls) as raised:
                client.call("x", {"code": code})
            assert type(raised.value) is cls
            assert raised.value.code == code and raised.value.message == f"refused {code}"


def test_notifications_before_the_reply_are_queued(fake: Callable[[Script], str]) -> None:
    sample = {"seq": 7, "t": 1.5, "imu": {"roll": 1, "pitch": 2, "yaw": 3},
              "hall": {"roll": 4, "pitch": 5, "yaw": 6},
              "rates": {"hall": {"roll": 0.5, "pitch": 0, "yaw": 0},
                        "imu": {"x": 1, "y": 2, "z": 3}}}

    def script(connection: socket.socket, request: Any) -> None:
        send(connection, {"jsonrpc": "2.0", "method": "attitude", "params": sample})
        send(connection, {"jsonrpc": "2.0", "method": "link",
                          "params": {"state": "stale", "reason": "no attitude for 500 ms"}})
        send(connection, {"jsonrpc": "2.0", "method": "future_topic", "params": {}})
        send(connection, {"jsonrpc": "2.0", "id": request["id"], "result": {"sent": True}})

    with gport.Client(fake(script)) as client:
        assert client.call("photo") == {"sent": True}
        attitude = client.next_notification(timeout=1)
        assert isinstance(attitude, gport.Attitude) and attitude.seq == 7
        assert attitude.rates == gport.Rates(gport.Axes(0.5, 0, 0), gport.ImuRates(1, 2, 3))
        assert client.next_notification(timeout=1) == gport.Link("stale", "no attitude for 500 ms")
        assert client.next_notification(timeout=0.05) is None


def test_timeout_without_a_reply(fake: Callable[[Script], str]) -> None:
    with gport.Client(fake(lambda connection, request: None), timeout=0.2) as client:
        with pytest.raises(gport.Timeout) as raised:
            client.status()
        assert raised.value.code is None and "status" in raised.value.message


def test_refusal_with_null_id_names_the_reason(fake: Callable[[Script], str]) -> None:
    def script(connection: socket.socket, request: Any) -> None:
        send(connection, {"jsonrpc": "2.0", "id": None,
                          "error": {"code": -32004, "message": "idle for 100 ms"}})
        connection.shutdown(socket.SHUT_RDWR)

    with gport.Client(fake(script)) as client:
        with pytest.raises(gport.ConnectionLost) as raised:
            client.status()
        assert "idle for 100 ms" in raised.value.message and "-32004" in raised.value.message
        assert not client.connected


def test_wait_sends_the_flag_and_parses_ended(fake: Callable[[Script], str]) -> None:
    # The shape of CONTRACT's tracked motions, answered late: a waited call
    # is not limited by the client's reply timeout.
    sample = {"seq": 3, "t": 2.0, "imu": {"roll": 0, "pitch": 0, "yaw": 10},
              "hall": {"roll": 0, "pitch": 0, "yaw": 9.8}, "age_ms": 4}
    seen: list[Any] = []

    def script(connection: socket.socket, request: Any) -> None:
        seen.append(request)
        time.sleep(0.3)
        ended: dict[str, Any] = {"reason": "reached", "attitude": sample, "elapsed_ms": 812}
        result: dict[str, Any] = {"sent": True, "ended": ended}
        if request["method"] == "angle":
            result.update(angle={"roll": 0, "pitch": 0, "yaw": 10}, clamped=[])
        else:  # a centre stopped short by something in the way
            ended.update(reason="stalled", detail="stalled at roll 40.00 (target 0.00, 40.00° short)")
        send(connection, {"jsonrpc": "2.0", "id": request["id"], "result": result})

    with gport.Client(fake(script), timeout=0.1) as client:
        result = client.angle(yaw=10, wait=True)
        assert result.ended is not None and result.ended.reason == "reached"
        assert result.ended.elapsed_ms == 812
        assert result.ended.detail == "", "no detail unless stalled"
        assert result.ended.attitude is not None and result.ended.attitude.hall.yaw == 9.8
        centered = client.center(wait=True)
        assert centered.ended is not None and centered.ended.reason == "stalled"
        assert centered.ended.detail.startswith("stalled at roll 40.00")
    assert seen[0]["params"] == {"roll": 0.0, "pitch": 0.0, "yaw": 10, "wait": True}
    assert seen[1]["params"] == {"wait": True}
