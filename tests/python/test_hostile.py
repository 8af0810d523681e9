"""Both clients against a hostile fake daemon (issue 22 item 7): lines that
are too deep, not UTF-8, not JSON, of the wrong shape or without end; a
daemon that never reads; a notification flood. Every decoding error must end
the connection with ConnectionLost naming the reason: the reader stops,
``connected`` turns false, and pending and later calls fail at once."""

from __future__ import annotations

import asyncio
import json
import os
import shutil
import socket
import tempfile
import threading
import time
from typing import Any, Callable, Iterator

import pytest

import gport
from gport import _protocol

MiB = 1024 * 1024
# Well above any wait of these tests: a call that ends by this limit is a failure.
PATIENT = 60.0


class Hostile:
    """A one-connection fake daemon: ``script(peer, request)`` runs for each
    request line (None: the requests are never read)."""

    def __init__(self, script: Callable[[Hostile, Any], None] | None) -> None:
        self.dir = tempfile.mkdtemp(prefix="gport-hostile-", dir="/tmp")
        self.path = os.path.join(self.dir, "gportd.sock")
        self.sent = 0
        self.script = script
        self.conn: socket.socket | None = None
        self.closed_by_client = threading.Event()
        self._stop = threading.Event()
        self._listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self._listener.bind(self.path)
        self._listener.listen(1)
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self) -> None:
        try:
            conn, _ = self._listener.accept()
        except OSError:
            return
        self.conn = conn
        with conn:
            if self.script is None:
                self._stop.wait()
                return
            try:
                with conn.makefile("rb") as lines:
                    for line in lines:
                        self.script(self, json.loads(line))
            except OSError:
                pass
            self.closed_by_client.set()

    def send(self, data: bytes) -> bool:
        """False once the client is gone."""
        assert self.conn is not None
        try:
            self.conn.sendall(data)
        except OSError:
            return False
        self.sent += len(data)
        return True

    def line(self, message: Any) -> bool:
        return self.send((json.dumps(message) + "\n").encode())

    def reply(self, request: Any, result: Any) -> bool:
        return self.line({"jsonrpc": "2.0", "id": request["id"], "result": result})

    def stream(self, total: int) -> None:
        """``total`` bytes without a newline, 1 MiB at a time, until the client leaves."""
        chunk = b"a" * MiB
        while total > 0 and self.send(chunk[: min(total, MiB)]):
            total -= MiB

    def close(self) -> None:
        self._stop.set()
        if self.conn is not None:
            try:
                self.conn.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass
        self._listener.close()
        self._thread.join(timeout=10)
        shutil.rmtree(self.dir, ignore_errors=True)


@pytest.fixture
def hostile() -> Iterator[Callable[..., Hostile]]:
    servers: list[Hostile] = []

    def start(script: Callable[[Hostile, Any], None] | None) -> Hostile:
        servers.append(Hostile(script))
        return servers[-1]

    yield start
    for server in servers:
        server.close()


def answering_with(raw: bytes) -> Callable[[Hostile, Any], None]:
    """A script answering every request with ``raw`` (a whole line)."""

    def script(peer: Hostile, request: Any) -> None:
        peer.send(raw)

    return script


DEEP = b"[" * 1_000_000 + b"]" * 1_000_000 + b"\n"
BAD_LINES = {
    "deep": (DEEP, "nested deeper than 64"),
    "utf8": (b'{"jsonrpc":"2.0","id":1,"result":"caf\xe9"}\n', "UTF-8"),
    "json": (b'{"jsonrpc":"2.0","id":1,"result":}\n', "not JSON"),
    "array": (b"[1,2,3]\n", "not a JSON object"),
    "string id": (b'{"jsonrpc":"2.0","id":"1","result":{}}\n', "id"),
    "no id, no method": (b'{"jsonrpc":"2.0","result":{}}\n', "neither"),
    "bad params": (b'{"jsonrpc":"2.0","method":"link","params":5}\n', "link"),
    "bad attitude": (
        b'{"jsonrpc":"2.0","method":"attitude","params":{"seq":"x","imu":3}}\n',
        "attitude",
    ),
    "bad capture": (
        b'{"jsonrpc":"2.0","method":"capture","params":{"index":"x","kind":1}}\n',
        "capture",
    ),
}


def peak_rss_kib() -> int:
    with open("/proc/self/status", encoding="ascii") as status:
        for line in status:
            if line.startswith("VmHWM:"):
                return int(line.split()[1])
    raise AssertionError("no VmHWM in /proc/self/status")


def reset_peak_rss() -> int:
    """The peak reset to the current RSS where the kernel allows (clear_refs 5)."""
    try:
        with open("/proc/self/clear_refs", "w", encoding="ascii") as refs:
            refs.write("5")
    except OSError:
        pass
    return peak_rss_kib()


# ---- the blocking client --------------------------------------------------
@pytest.mark.parametrize("kind", list(BAD_LINES))
def test_a_bad_line_ends_the_connection(hostile: Callable[..., Hostile], kind: str) -> None:
    raw, reason = BAD_LINES[kind]
    server = hostile(answering_with(raw))
    with gport.Client(server.path, timeout=PATIENT) as client:
        with pytest.raises(gport.ConnectionLost) as raised:
            client.status()
        assert reason in raised.value.message
        assert not client.connected
        with pytest.raises(gport.ConnectionLost) as again:
            client.status()  # at once: no request goes out
        assert reason in again.value.message
        with pytest.raises(gport.ConnectionLost):
            client.next_notification(timeout=PATIENT)
    assert server.closed_by_client.wait(10), "the client closed its end"


def test_recursion_error_ends_the_connection(
    hostile: Callable[..., Hostile], monkeypatch: pytest.MonkeyPatch
) -> None:
    # Without the pre-scan the decoder recurses and raises RecursionError.
    monkeypatch.setattr(_protocol, "NESTING_LIMIT", 10**7)
    server = hostile(answering_with(DEEP))
    with gport.Client(server.path, timeout=PATIENT) as client:
        with pytest.raises(gport.ConnectionLost) as raised:
            client.status()
        assert "recursion" in raised.value.message.lower()
        assert not client.connected


def test_a_pending_call_and_a_waiting_reader_fail_at_once(
    hostile: Callable[..., Hostile],
) -> None:
    def script(peer: Hostile, request: Any) -> None:
        time.sleep(0.3)  # both waits have begun
        peer.send(b"not json at all\n")

    server = hostile(script)
    with gport.Client(server.path, timeout=PATIENT) as client:
        failures: list[BaseException] = []

        def wait_for_notification() -> None:
            try:
                client.next_notification(timeout=PATIENT)
            except BaseException as error:
                failures.append(error)

        waiter = threading.Thread(target=wait_for_notification)
        waiter.start()
        with pytest.raises(gport.ConnectionLost) as raised:
            client.status()
        waiter.join(PATIENT)
        assert "not JSON" in raised.value.message
        assert len(failures) == 1 and isinstance(failures[0], gport.ConnectionLost)


def test_a_line_without_end_stops_at_the_limit(hostile: Callable[..., Hostile]) -> None:
    server = hostile(lambda peer, request: peer.stream(400 * MiB))
    with gport.Client(server.path, timeout=PATIENT) as client:
        before = reset_peak_rss()
        with pytest.raises(gport.ConnectionLost) as raised:
            client.status()
        growth = peak_rss_kib() - before
        print(f"400 MB line: peak RSS grew {growth} KiB; the server sent {server.sent} bytes")
        assert str(gport.LINE_LIMIT) in raised.value.message
        assert not client.connected
    assert growth < 64 * 1024
    assert server.sent < 64 * MiB, "the client stopped reading at the limit"


def test_a_line_at_the_limit_is_accepted(hostile: Callable[..., Hostile]) -> None:
    def script(peer: Hostile, request: Any) -> None:
        head = json.dumps({"jsonrpc": "2.0", "id": request["id"], "result": {"pad": ""}})
        pad = "x" * (gport.LINE_LIMIT - len(head))
        line = json.dumps({"jsonrpc": "2.0", "id": request["id"], "result": {"pad": pad}})
        assert len(line) == gport.LINE_LIMIT
        peer.send(line.encode() + b"\n")

    server = hostile(script)
    with gport.Client(server.path, timeout=PATIENT) as client:
        assert len(client.call("status")["pad"]) > 16_000_000
        assert client.connected


def test_one_byte_over_the_limit_ends_the_connection(hostile: Callable[..., Hostile]) -> None:
    server = hostile(answering_with(b" " * (gport.LINE_LIMIT + 1) + b"\n"))
    with gport.Client(server.path, timeout=PATIENT) as client:
        with pytest.raises(gport.ConnectionLost) as raised:
            client.status()
        assert str(gport.LINE_LIMIT) in raised.value.message


def test_a_daemon_that_never_reads_cannot_block_a_call(hostile: Callable[..., Hostile]) -> None:
    server = hostile(None)
    with gport.Client(server.path, timeout=0.3) as client:
        with pytest.raises(gport.ConnectionLost) as raised:
            client.call("status", {"pad": "x" * (16 * MiB)})
        assert "did not read" in raised.value.message
        assert not client.connected


def test_a_thread_waiting_to_write_behind_a_stuck_one_keeps_its_own_timeout(
    hostile: Callable[..., Hostile],
) -> None:
    """Before: a call waited for the write lock without a deadline, for as
    long as the thread holding it was allowed (here PATIENT)."""
    server = hostile(None)
    with gport.Client(server.path, timeout=PATIENT) as client:
        stuck = threading.Thread(
            target=lambda: pytest.raises(
                gport.ConnectionLost, client.call, "status", {"pad": "x" * (16 * MiB)}
            )
        )
        stuck.start()
        deadline = time.monotonic() + PATIENT
        while not client._write_lock.locked():  # until the stuck thread writes
            assert time.monotonic() < deadline and stuck.is_alive()
            time.sleep(0.01)
        started = time.monotonic()
        with pytest.raises(gport.ConnectionLost) as raised:
            client.call("status", timeout=0.3)
        assert "did not read" in raised.value.message
        assert time.monotonic() - started < PATIENT / 2
        stuck.join(PATIENT)
        assert not stuck.is_alive(), "the connection the late writer closed ends the other"


def test_a_silent_daemon_gives_a_timeout_and_the_connection_stays(
    hostile: Callable[..., Hostile],
) -> None:
    def script(peer: Hostile, request: Any) -> None:
        if request["method"] == "photo":
            peer.reply(request, {"sent": True})

    server = hostile(script)
    with gport.Client(server.path, timeout=0.2) as client:
        with pytest.raises(gport.Timeout):
            client.status()
        assert client.connected
        assert client.call("photo") == {"sent": True}


def test_a_result_that_does_not_decode_is_an_error_and_the_connection_stays(
    hostile: Callable[..., Hostile],
) -> None:
    def script(peer: Hostile, request: Any) -> None:
        results = {"status": {"daemon_version": 1}, "limits": {"roll": 5}, "photo": {"sent": True}}
        peer.reply(request, results[request["method"]])

    server = hostile(script)
    with gport.Client(server.path, timeout=PATIENT) as client:
        with pytest.raises(gport.GportError) as raised:
            client.status()
        assert raised.value.code is None
        assert raised.value.message == (
            "the daemon sent a status result this client cannot read (KeyError('api_version'))"
        )
        with pytest.raises(gport.GportError, match="a limits result this client cannot read"):
            client.limits()
        assert client.connected and client.photo().sent


def test_async_a_result_that_does_not_decode_is_an_error_and_the_connection_stays(
    hostile: Callable[..., Hostile],
) -> None:
    def script(peer: Hostile, request: Any) -> None:
        results = {"settings": {"dead_zone": "wide"}, "photo": {"sent": True}}
        peer.reply(request, results.get(request["method"], results["settings"]))

    server = hostile(script)

    async def main() -> None:
        async with gport.AsyncClient(server.path, timeout=PATIENT) as client:
            with pytest.raises(gport.GportError, match="a get_settings result this client cannot"):
                await client.settings()
            assert client.connected and (await client.photo()).sent

    asyncio.run(main())


def attitude(seq: int) -> dict[str, Any]:
    """An attitude notification as gportd sends it."""
    axes = {"roll": 0.5, "pitch": -2.25, "yaw": 44.75}
    params = {"seq": seq, "t": 1.7e9, "imu": axes, "hall": axes}
    return {"jsonrpc": "2.0", "method": "attitude", "params": params}


def test_a_flood_nobody_takes_is_bounded_and_counted(hostile: Callable[..., Hostile]) -> None:
    flood = 20_000

    def script(peer: Hostile, request: Any) -> None:
        peer.line({"jsonrpc": "2.0", "method": "link", "params": {"state": "up", "reason": ""}})
        lines = [json.dumps(attitude(seq)) + "\n" for seq in range(1, flood + 1)]
        peer.send("".join(lines).encode())
        peer.reply(request, {"sent": True})

    server = hostile(script)
    with gport.Client(server.path, timeout=PATIENT) as client:
        client.call("photo")
        assert client.dropped_notifications == flood - gport.INBOX_LIMIT
        link = client.next_notification(timeout=0)
        assert isinstance(link, gport.Link), "a flood of one topic keeps the others"
        seqs = []
        while (item := client.next_notification(timeout=0)) is not None:
            assert isinstance(item, gport.Attitude)
            seqs.append(item.seq)
        assert seqs == list(range(flood - gport.INBOX_LIMIT + 1, flood + 1)), "the newest"


def long_link_events(count: int) -> Callable[[Hostile, Any], None]:
    """A script: ``count`` link events whose reason is a 1 MiB string, then the reply."""
    line = json.dumps(
        {"jsonrpc": "2.0", "method": "link", "params": {"state": "down", "reason": "r" * MiB}}
    )

    def script(peer: Hostile, request: Any) -> None:
        for _ in range(count):
            peer.send((line + "\n").encode())
        peer.reply(request, {"sent": True})

    return script


def test_long_notifications_are_bounded_in_bytes_too(hostile: Callable[..., Hostile]) -> None:
    """Review finding 7. Before: all 32 were kept (1024 per topic), and a
    few lines of [{},{},...] could take gigabytes."""
    events = 32
    server = hostile(long_link_events(events))
    with gport.Client(server.path, timeout=PATIENT) as client:
        client.call("photo")
        kept = 0
        while (item := client.next_notification(timeout=0)) is not None:
            assert isinstance(item, gport.Link)
            kept += 1
        assert kept <= gport.INBOX_BYTES // MiB
        assert client.dropped_notifications == events - kept


# ---- the asyncio client ---------------------------------------------------
@pytest.mark.parametrize("kind", list(BAD_LINES))
def test_async_a_bad_line_ends_the_connection(
    hostile: Callable[..., Hostile], kind: str
) -> None:
    raw, reason = BAD_LINES[kind]
    server = hostile(answering_with(raw))

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=PATIENT)
        with pytest.raises(gport.ConnectionLost) as raised:
            await client.status()
        assert reason in raised.value.message
        assert not client.connected
        with pytest.raises(gport.ConnectionLost) as again:
            await client.status()
        assert reason in again.value.message
        with pytest.raises(gport.ConnectionLost):
            await client.next_notification(timeout=PATIENT)
        await client.close()

    asyncio.run(main())
    assert server.closed_by_client.wait(10), "the client closed its end"


def test_async_recursion_error_ends_the_connection(
    hostile: Callable[..., Hostile], monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(_protocol, "NESTING_LIMIT", 10**7)
    server = hostile(answering_with(DEEP))

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=PATIENT)
        with pytest.raises(gport.ConnectionLost) as raised:
            await client.status()
        assert "recursion" in raised.value.message.lower()
        assert not client.connected

    asyncio.run(main())


def test_async_a_pending_call_and_a_waiting_task_fail_at_once(
    hostile: Callable[..., Hostile],
) -> None:
    def script(peer: Hostile, request: Any) -> None:
        time.sleep(0.3)  # both waits have begun
        peer.send(b"not json at all\n")

    server = hostile(script)

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=PATIENT)
        waiter = asyncio.create_task(client.next_notification(timeout=PATIENT))
        with pytest.raises(gport.ConnectionLost) as raised:
            await client.status()
        assert "not JSON" in raised.value.message
        with pytest.raises(gport.ConnectionLost):
            await waiter
        await client.close()

    asyncio.run(main())


def test_async_a_silent_daemon_gives_a_timeout_and_the_connection_stays(
    hostile: Callable[..., Hostile],
) -> None:
    def script(peer: Hostile, request: Any) -> None:
        if request["method"] == "photo":
            peer.reply(request, {"sent": True})

    server = hostile(script)

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=0.2)
        with pytest.raises(gport.Timeout):
            await client.status()
        assert client.connected
        assert await client.call("photo") == {"sent": True}
        await client.close()

    asyncio.run(main())


def test_async_a_line_without_end_stops_at_the_limit(hostile: Callable[..., Hostile]) -> None:
    server = hostile(lambda peer, request: peer.stream(400 * MiB))

    async def main() -> int:
        client = await gport.AsyncClient.open(server.path, timeout=PATIENT)
        before = reset_peak_rss()
        with pytest.raises(gport.ConnectionLost) as raised:
            await client.status()
        assert str(gport.LINE_LIMIT) in raised.value.message
        assert not client.connected
        return peak_rss_kib() - before

    growth = asyncio.run(main())
    print(f"async, 400 MB line: peak RSS grew {growth} KiB; the server sent {server.sent} bytes")
    assert growth < 64 * 1024
    assert server.sent < 64 * MiB


def test_async_a_daemon_that_never_reads_cannot_block_a_call(
    hostile: Callable[..., Hostile],
) -> None:
    server = hostile(None)

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=0.3)
        with pytest.raises(gport.ConnectionLost) as raised:
            await client.call("status", {"pad": "x" * (16 * MiB)})
        assert "did not read" in raised.value.message
        assert not client.connected

    asyncio.run(main())


def test_async_a_flood_nobody_takes_is_counted(hostile: Callable[..., Hostile]) -> None:
    flood = 5_000

    def script(peer: Hostile, request: Any) -> None:
        for seq in range(1, flood + 1):
            peer.line(attitude(seq))
        peer.reply(request, {"sent": True})

    server = hostile(script)

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=PATIENT)
        await client.call("photo")
        assert client.dropped_notifications == flood - gport.INBOX_LIMIT
        first = await client.next_notification(timeout=0)
        assert isinstance(first, gport.Attitude)
        assert first.seq == flood - gport.INBOX_LIMIT + 1
        await client.close()

    asyncio.run(main())


def test_async_long_notifications_are_bounded_in_bytes_too(
    hostile: Callable[..., Hostile],
) -> None:
    events = 32
    server = hostile(long_link_events(events))

    async def main() -> None:
        client = await gport.AsyncClient.open(server.path, timeout=PATIENT)
        await client.call("photo")
        kept = 0
        while (item := await client.next_notification(timeout=0)) is not None:
            assert isinstance(item, gport.Link)
            kept += 1
        assert kept <= gport.INBOX_BYTES // MiB
        assert client.dropped_notifications == events - kept
        await client.close()

    asyncio.run(main())
