"""A stand-in for gportd in the shared-memory channel tests: a Unix socket
whose thread answers ``attitude_channel`` as gportd does (the ring and a
wake block of the connection's own, sent with SCM_RIGHTS on the first
reply, ``"descriptors":0`` afterwards) and echoes ``subscribe`` /
``unsubscribe``. RingBlock and WakeBlock format sealed memfds with the
layouts of base/include/gport/base/attitude_ring.hpp (version 2) and
wake_block.hpp; the test keeps a writable mapping of each, so it can also
play a hostile server that rewrites or truncates them."""

from __future__ import annotations

import ctypes
import fcntl
import json
import mmap
import os
import shutil
import socket
import struct
import tempfile
import threading
from dataclasses import dataclass, field
from typing import Any

from gport import _ring as ring
from gport._futex import FUTEX

_SLOT_WORDS = struct.Struct("=Qd3d3dQ3d3d")
SEALS = ring.F_SEAL_SHRINK | 0x0004 | ring.F_SEAL_FUTURE_WRITE  # shrink, grow, future write
F_ADD_SEALS = 1033


def _memfd(name: str, size: int, seals: int | None) -> tuple[int, mmap.mmap]:
    fd = os.memfd_create(name, os.MFD_CLOEXEC | os.MFD_ALLOW_SEALING)
    os.ftruncate(fd, size)
    mapping = mmap.mmap(fd, size)
    if seals:
        fcntl.fcntl(fd, F_ADD_SEALS, seals)
    return fd, mapping


class WakeBlock:
    """A connection's wake block; bump() wakes ``wakes`` waiters: all by
    default, 1 as gportd does."""

    def __init__(self, seals: int | None = SEALS) -> None:
        self.fd, self.map = _memfd("fake-gportd-wake", ring.WAKE_SIZE, None)
        struct.pack_into("=III", self.map, 0, ring.WAKE_MAGIC, ring.WAKE_VERSION, ring.WAKE_SIZE)
        if seals:
            fcntl.fcntl(self.fd, F_ADD_SEALS, seals)
        self._word = ctypes.c_char.from_buffer(self.map)
        self.address = ctypes.addressof(self._word)
        self.wakes = 2**31 - 1

    def bump(self) -> None:
        word = struct.unpack_from("=I", self.map, ring.OFF_WAKE)[0]
        struct.pack_into("=I", self.map, ring.OFF_WAKE, (word + 1) & 0xFFFFFFFF)
        FUTEX.wake(self.address + ring.OFF_WAKE, self.wakes)

    def release(self) -> None:
        del self._word
        self.map.close()
        os.close(self.fd)


class RingBlock:
    """A memfd holding a ring, mapped read-write to publish into; its wake
    block is bumped on every publish and close."""

    def __init__(self, slots: int = 64, seals: int | None = SEALS) -> None:
        self.size = ring.HEADER_SIZE + slots * ring.SLOT_SIZE
        self.slots = slots
        self.fd, self.map = _memfd("fake-gportd-attitude", self.size, None)
        struct.pack_into(
            "=IIIII", self.map, 0, ring.MAGIC, 2, ring.HEADER_SIZE, ring.SLOT_SIZE, slots
        )
        if seals:
            fcntl.fcntl(self.fd, F_ADD_SEALS, seals)
        self.published = 0
        self.wake = WakeBlock(seals)

    def publish(self, seq: int, rates: bool = False) -> None:
        n = self.published + 1
        slot = ring.HEADER_SIZE + ((n - 1) % self.slots) * ring.SLOT_SIZE
        struct.pack_into("=Q", self.map, slot, 2 * n - 1)
        words: tuple[float, ...] = (seq, 1.7e9 + seq / 100, seq / 10, -2.5, 45.0, 0.5, -2.25)
        words += (44.75, 1 if rates else 0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
        _SLOT_WORDS.pack_into(self.map, slot + 8, *words)
        struct.pack_into("=Q", self.map, slot, 2 * n)
        struct.pack_into("=Q", self.map, 32, n)
        self.published = n
        self.wake.bump()

    def close(self) -> None:
        flags = struct.unpack_from("=I", self.map, 20)[0]
        struct.pack_into("=I", self.map, 20, flags | ring.FLAG_CLOSED)
        self.wake.bump()

    def set_header(self, offset: int, value: int) -> None:
        struct.pack_into("=I", self.map, offset, value)

    def release(self) -> None:
        self.map.close()
        os.close(self.fd)
        self.wake.release()


@dataclass
class Offer:
    """What one attitude_channel request is answered with: ``block`` sent
    as gportd would (None: none), or a hostile variant: ``fds`` to attach
    instead, ``result`` members to change; ``late``: held back until
    release_held() or the next attitude_channel request, answered first."""

    block: RingBlock | None
    fds: list[int] | None = None
    result: dict[str, Any] = field(default_factory=dict)
    late: bool = False


class FakeServer:
    """Answers one connection at a time. Each attitude_channel request takes
    the next of ``offers`` (a RingBlock, None or an Offer); with none left
    it answers ``"descriptors":0``, as gportd does on a connection that has
    its channel."""

    def __init__(self) -> None:
        self.dir = tempfile.mkdtemp(prefix="gport-shm-", dir="/tmp")
        self.path = os.path.join(self.dir, "gportd.sock")
        self.offers: list[RingBlock | Offer | None] = []
        self.subscribed: list[Any] | None = None
        self._held: list[tuple[Any, Offer]] = []
        self._lock = threading.Lock()
        self._conn: socket.socket | None = None
        self._listener = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
        self._listener.bind(self.path)
        self._listener.listen(4)
        self._thread = threading.Thread(target=self._serve, daemon=True)
        self._thread.start()

    def _serve(self) -> None:
        while True:
            try:
                conn, _ = self._listener.accept()
            except OSError:
                return
            with self._lock:
                self._conn = conn
            try:
                with conn.makefile("rb") as lines:
                    for line in lines:
                        self._answer(json.loads(line))
            except OSError:
                pass
            with self._lock:  # forgotten before it is closed: drop() never sees it closed
                self._conn = None
            conn.close()

    def _channel_reply(self, request_id: Any) -> tuple[dict[str, Any], list[int]] | None:
        """The next offer's result and descriptors; None when it is held back."""
        if not self.offers:
            return _offer_result(Offer(None)), []
        offer = self.offers.pop(0)
        if not isinstance(offer, Offer):
            offer = Offer(offer)
        if offer.late:
            self._held.append((request_id, offer))
            return None
        self.release_held()
        return _offer_result(offer), _offer_fds(offer)

    def release_held(self) -> None:
        """Sends the replies held back (Offer.late), in order."""
        held, self._held = self._held, []
        for request_id, offer in held:
            reply = {"jsonrpc": "2.0", "id": request_id, "result": _offer_result(offer)}
            self.push(reply, _offer_fds(offer))

    def _answer(self, request: dict[str, Any]) -> None:
        method = request["method"]
        reply: dict[str, Any] = {"jsonrpc": "2.0", "id": request["id"]}
        fds: list[int] = []
        params = request.get("params", {})
        if method == "attitude_channel":
            answer = self._channel_reply(request["id"])
            if answer is None:
                return
            reply["result"], fds = answer
        elif method in ("subscribe", "unsubscribe"):
            if method == "subscribe":
                self.subscribed = params.get("topics")
            reply["result"] = {"topics": params.get("topics", [])}
        else:
            reply["error"] = {"code": -32601, "message": f"unknown method {method}"}
        self.push(reply, fds)

    def push(self, message: dict[str, Any], fds: int | list[int] | None = None) -> None:
        """Sends a line to the connected client, with ``fds`` attached."""
        data = (json.dumps(message) + "\n").encode()
        attached = [fds] if isinstance(fds, int) else list(fds or [])
        with self._lock:
            assert self._conn is not None, "no client connected"
            if not attached:
                self._conn.sendall(data)
            else:
                socket.send_fds(self._conn, [data], attached)

    def drop(self) -> None:
        with self._lock:
            if self._conn is not None:
                self._conn.shutdown(socket.SHUT_RDWR)

    def close(self) -> None:
        self.drop()
        try:
            self._listener.shutdown(socket.SHUT_RDWR)  # wakes accept()
        except OSError:
            pass
        self._listener.close()
        self._thread.join(timeout=10)
        shutil.rmtree(self.dir, ignore_errors=True)


def _offer_result(offer: Offer) -> dict[str, Any]:
    result = {"version": 2, "slots": 64, "size": ring.HEADER_SIZE + 64 * ring.SLOT_SIZE}
    result |= {"published": 0, "descriptors": 0}
    if offer.block is not None:
        result |= {"slots": offer.block.slots, "size": offer.block.size, "descriptors": 2}
    return result | offer.result


def _offer_fds(offer: Offer) -> list[int]:
    if offer.fds is not None:
        return offer.fds
    return [] if offer.block is None else [offer.block.fd, offer.block.wake.fd]


def open_descriptors() -> int:
    return len(os.listdir("/proc/self/fd"))
