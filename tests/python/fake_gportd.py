"""A stand-in for gportd in the shared-memory channel tests: a Unix socket
whose thread answers ``attitude_channel`` with a memfd (sent with
SCM_RIGHTS on the reply line, as gportd does) and echoes ``subscribe`` /
``unsubscribe``; RingBlock formats the memfd as base::RingWriter does (the
layout of base/include/gport/base/attitude_ring.hpp, version 1)."""

from __future__ import annotations

import ctypes
import json
import mmap
import os
import shutil
import socket
import struct
import tempfile
import threading
from typing import Any

from gport import channel as ch

_SLOT_WORDS = struct.Struct("=Qd3d3dQ3d3d")


class RingBlock:
    """A memfd holding a ring, mapped read-write to publish into."""

    def __init__(self, slots: int = 64) -> None:
        self.size = ch.HEADER_SIZE + slots * ch.SLOT_SIZE
        self.slots = slots
        self.fd = os.memfd_create("fake-gportd-attitude", os.MFD_CLOEXEC)
        os.ftruncate(self.fd, self.size)
        self.map = mmap.mmap(self.fd, self.size)
        self._word = ctypes.c_char.from_buffer(self.map)
        self.address = ctypes.addressof(self._word)
        struct.pack_into("=IIIII", self.map, 0, ch.MAGIC, 1, ch.HEADER_SIZE, ch.SLOT_SIZE, slots)
        self.published = 0

    def publish(self, seq: int, rates: bool = False) -> None:
        n = self.published + 1
        slot = ch.HEADER_SIZE + ((n - 1) % self.slots) * ch.SLOT_SIZE
        struct.pack_into("=Q", self.map, slot, 2 * n - 1)
        words: tuple[float, ...] = (seq, 1.7e9 + seq / 100, seq / 10, -2.5, 45.0, 0.5, -2.25)
        words += (44.75, 1 if rates else 0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0)
        _SLOT_WORDS.pack_into(self.map, slot + 8, *words)
        struct.pack_into("=Q", self.map, slot, 2 * n)
        struct.pack_into("=Q", self.map, 32, n)
        self.published = n
        self._bump()

    def close(self) -> None:
        flags = struct.unpack_from("=I", self.map, 20)[0]
        struct.pack_into("=I", self.map, 20, flags | ch.FLAG_CLOSED)
        self._bump()

    def set_header(self, offset: int, value: int) -> None:
        struct.pack_into("=I", self.map, offset, value)

    def _bump(self) -> None:
        wake = struct.unpack_from("=I", self.map, 24)[0]
        struct.pack_into("=I", self.map, 24, (wake + 1) & 0xFFFFFFFF)
        if ch._SYS_FUTEX is not None:
            ch._libc.syscall(
                ctypes.c_long(ch._SYS_FUTEX),
                ctypes.c_void_p(self.address + 24),
                ctypes.c_int(1),
                ctypes.c_int(2**31 - 1),
                None,
                None,
                ctypes.c_int(0),
            )

    def release(self) -> None:
        del self._word
        self.map.close()
        os.close(self.fd)


class FakeServer:
    """Answers one connection at a time; ``offers`` are the blocks (or None:
    no descriptor) that successive attitude_channel replies carry."""

    def __init__(self) -> None:
        self.dir = tempfile.mkdtemp(prefix="gport-shm-", dir="/tmp")
        self.path = os.path.join(self.dir, "gportd.sock")
        self.offers: list[RingBlock | None] = []
        self.subscribed: list[Any] | None = None
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

    def _answer(self, request: dict[str, Any]) -> None:
        method = request["method"]
        reply: dict[str, Any] = {"jsonrpc": "2.0", "id": request["id"]}
        fd = None
        params = request.get("params", {})
        if method == "attitude_channel":
            block = self.offers.pop(0) if self.offers else None
            size = 0 if block is None else block.size
            reply["result"] = {"version": 1, "slots": 64, "size": size, "published": 0}
            fd = None if block is None else block.fd
        elif method in ("subscribe", "unsubscribe"):
            if method == "subscribe":
                self.subscribed = params.get("topics")
            reply["result"] = {"topics": params.get("topics", [])}
        else:
            reply["error"] = {"code": -32601, "message": f"unknown method {method}"}
        self.push(reply, fd)

    def push(self, message: dict[str, Any], fd: int | None = None) -> None:
        """Sends a line to the connected client, with ``fd`` attached."""
        data = (json.dumps(message) + "\n").encode()
        with self._lock:
            assert self._conn is not None, "no client connected"
            if fd is None:
                self._conn.sendall(data)
            else:
                socket.send_fds(self._conn, [data], [fd])

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


def open_descriptors() -> int:
    return len(os.listdir("/proc/self/fd"))
