"""The shared-memory attitude channel (docs/api.md, "Shared-memory attitude
channel"): gportd hands a read-only memory block holding a ring of the latest
attitude samples and wakes its readers once per sample.

This is a reimplementation, with ctypes, of the reader of
base/include/gport/base/attitude_ring.hpp (version 1). The block, in native
(little-endian) byte order, is a 64-byte header and then ``slot_count``
128-byte slots::

    header  0 u32 magic 0x52415047 ("GPAR")   4 u32 version (1)
            8 u32 header_size (64)            12 u32 slot_size (128)
           16 u32 slot_count (a power of two) 20 u32 flags (1: closed)
           24 u32 wake (the futex word)       28 u32 reserved
           32 u64 published (n of the newest) 40..63 reserved
    slot    0 u64 seq: 2n - 1 while sample n is written, 2n once complete
            8 u64 sample seq   16 f64 t   24 f64 imu roll, pitch, yaw
           48 f64 hall roll, pitch, yaw   72 u64 has_rates (0 or 1)
           80 f64 hall_rates roll, pitch, yaw   104 f64 imu_rates x, y, z

Sample n (1, 2, ...) is in slot (n - 1) % slot_count. A slot is read as a
seqlock: its seq, then the words, then its seq again; the read counts only
when both are 2n. The block is mapped with libc's mmap through ctypes
(PROT_READ, MAP_SHARED) rather than Python's mmap module, because the futex
needs the mapping's address, which a read-only ``mmap.mmap`` does not give;
aligned 8-byte words are read with single loads (``ctypes.c_uint64``). The
futex is ``syscall(SYS_futex, ...)`` (202 on x86_64, 98 on aarch64); on
other machines the reader polls every millisecond instead.
"""

from __future__ import annotations

import ctypes
import mmap
import os
import platform
import struct
import threading
import time
from typing import Callable

from .errors import BadChannel
from .results import Attitude, Axes, ImuRates, Rates

MAGIC = 0x52415047
VERSION = 1
HEADER_SIZE = 64
SLOT_SIZE = 128
FLAG_CLOSED = 1
_OFF_SLOT_COUNT = 16
_OFF_FLAGS = 20
_OFF_WAKE = 24
_OFF_PUBLISHED = 32
_HEADER = struct.Struct("=IIIII")  # magic, version, header_size, slot_size, slot_count
_WORDS = struct.Struct("=Qd3d3dQ3d3d")  # the 15 words after a slot's seq

_SYS_FUTEX = {"x86_64": 202, "aarch64": 98}.get(platform.machine())
_FUTEX_WAIT = 0
_FUTEX_WAKE = 1
_POLL_SLICE = 0.001  # seconds, without a futex
_PUMP_SLICE = 0.5  # RingPump looks at its stop flag at least this often

_libc = ctypes.CDLL(None, use_errno=True)
_libc.mmap.restype = ctypes.c_void_p
_libc.mmap.argtypes = [
    ctypes.c_void_p,
    ctypes.c_size_t,
    ctypes.c_int,
    ctypes.c_int,
    ctypes.c_int,
    ctypes.c_long,
]
_libc.munmap.restype = ctypes.c_int
_libc.munmap.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
_libc.syscall.restype = ctypes.c_long
_MAP_FAILED = ctypes.c_void_p(-1).value


class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


def futex_available() -> bool:
    """True when waits sleep on the futex (x86_64, aarch64), False when they poll."""
    return _SYS_FUTEX is not None


def check(header: bytes, size: int) -> str | None:
    """What is wrong with a block (its first bytes and its size), or None:
    the checks of base::RingReader::check, with the same messages."""
    if size < HEADER_SIZE or len(header) < _HEADER.size:
        return "the block is smaller than a ring header"
    magic, version, header_size, slot_size, slot_count = _HEADER.unpack_from(header)
    if magic != MAGIC:
        return "not an attitude ring (bad magic)"
    if version != VERSION:
        return f"attitude ring version {version} is not supported ({VERSION} is)"
    if header_size != HEADER_SIZE or slot_size != SLOT_SIZE:
        return "attitude ring header or slot size does not match version 1"
    if slot_count == 0 or slot_count & (slot_count - 1):
        return "attitude ring slot count is not a power of two"
    if size < HEADER_SIZE + slot_count * SLOT_SIZE:
        return "the block is smaller than its ring"
    return None


class AttitudeChannel:
    """A reader of gportd's attitude ring (``Client.attitude_channel()``).

    ``next(timeout)`` gives the sample after the last one taken (the first
    call: the newest), waiting for it; ``latest()`` the newest; ``missed``
    counts samples skipped because this reader fell more than a ring behind;
    ``closed`` turns true when gportd stops. The mapping is this process's:
    it outlives the connection; ``close()`` (or ``with``) unmaps it. One
    thread should call next() at a time."""

    def __init__(self, fd: int) -> None:
        """Maps ``fd`` read-only and checks it (BadChannel naming the
        problem); the caller still owns ``fd``."""
        self._address = 0
        self._size = os.fstat(fd).st_size
        if self._size <= 0:
            raise BadChannel("attitude channel: the block is empty")
        address = _libc.mmap(None, self._size, mmap.PROT_READ, mmap.MAP_SHARED, fd, 0)
        if address is None or address == _MAP_FAILED:
            error = ctypes.get_errno()
            raise BadChannel(f"attitude channel: cannot map the block: {os.strerror(error)}")
        self._address = int(address)
        problem = check(ctypes.string_at(self._address, min(self._size, HEADER_SIZE)), self._size)
        if problem is not None:
            self.close()
            raise BadChannel(f"attitude channel: {problem}")
        self._slots = self._u32(_OFF_SLOT_COUNT)
        self._cursor = 0
        self._from_first = False
        self.missed = 0

    # ---- raw access ---------------------------------------------------------
    def _u32(self, offset: int) -> int:
        return ctypes.c_uint32.from_address(self._address + offset).value

    def _u64(self, offset: int) -> int:
        return ctypes.c_uint64.from_address(self._address + offset).value

    def _published(self) -> int:
        return self._u64(_OFF_PUBLISHED)

    def _wake_word(self) -> int:
        return self._u32(_OFF_WAKE)

    def _read(self, n: int) -> tuple[float, ...] | None:
        """The words of sample n, if it is still in the ring and complete."""
        if n == 0 or self._address == 0:
            return None
        slot = HEADER_SIZE + ((n - 1) % self._slots) * SLOT_SIZE
        before = self._u64(slot)
        if before != 2 * n:
            return None
        words = ctypes.string_at(self._address + slot + 8, _WORDS.size)
        if self._u64(slot) != before:
            return None
        return _WORDS.unpack(words)

    def _attitude(self, w: tuple[float, ...]) -> Attitude:
        rates = None
        if w[8]:
            rates = Rates(Axes(w[9], w[10], w[11]), ImuRates(w[12], w[13], w[14]))
        return Attitude(
            seq=int(w[0]),
            t=w[1],
            imu=Axes(w[2], w[3], w[4]),
            hall=Axes(w[5], w[6], w[7]),
            rates=rates,
            dropped=self.missed or None,
        )

    # ---- the reader ---------------------------------------------------------
    def take(self) -> Attitude | None:
        """The next sample without waiting (as base::RingReader::next)."""
        if self._address == 0:
            return None
        if self._from_first and self._published() > 0:
            self._from_first = False
            first = self._read(1)
            if first is not None:
                self._cursor = 1
                return self._attitude(first)
        lapped = False
        for _ in range(4):  # bounded: a writer stopped inside a slot never hangs us
            newest = self._published()
            if newest <= self._cursor:
                return None
            want = self._cursor + 1
            if self._cursor == 0:
                want = newest
            elif lapped or newest - self._cursor > self._slots:
                want = max(self._cursor + 1, newest - self._slots // 2)
            words = self._read(want)
            if words is not None:
                self.missed += 0 if self._cursor == 0 else want - self._cursor - 1
                self._cursor = want
                return self._attitude(words)
            # Overwritten between the two looks, or being overwritten: the
            # writer lapped this reader.
            lapped = True
        return None

    def skip_to_newest(self) -> None:
        """From now on, take() gives only samples published after this call."""
        self._cursor = self._published()
        self._from_first = self._cursor == 0

    def next(self, timeout: float | None = None) -> Attitude | None:
        """The next sample, waiting up to ``timeout`` seconds (None: until
        one comes or the channel closes); None on timeout or once closed."""
        deadline = None if timeout is None else time.monotonic() + timeout
        while True:
            seen = self._wake_word() if self._address else 0
            sample = self.take()
            if sample is not None:
                return sample
            left = None if deadline is None else deadline - time.monotonic()
            if self.closed or (left is not None and left <= 0):
                return None
            self.wait(seen, 1.0 if left is None else min(left, 1.0))

    def wait(self, seen: int, timeout: float) -> None:
        """Sleeps while the futex word still holds ``seen``, at most ``timeout`` s."""
        if _SYS_FUTEX is None:
            time.sleep(min(timeout, _POLL_SLICE))
            return
        whole = int(timeout)
        span = _Timespec(whole, int((timeout - whole) * 1e9))
        _libc.syscall(
            ctypes.c_long(_SYS_FUTEX),
            ctypes.c_void_p(self._address + _OFF_WAKE),
            ctypes.c_int(_FUTEX_WAIT),
            ctypes.c_uint32(seen),
            ctypes.byref(span),
            None,
            ctypes.c_int(0),
        )

    def wake(self) -> None:
        """Wakes every waiter on the word (a read-only mapping is enough):
        used to stop a thread blocked in next()."""
        if _SYS_FUTEX is not None and self._address:
            _libc.syscall(
                ctypes.c_long(_SYS_FUTEX),
                ctypes.c_void_p(self._address + _OFF_WAKE),
                ctypes.c_int(_FUTEX_WAKE),
                ctypes.c_int(2**31 - 1),
                None,
                None,
                ctypes.c_int(0),
            )

    def latest(self) -> Attitude | None:
        """The newest sample (next()'s cursor does not move); None before the first."""
        for _ in range(4):
            words = self._read(self._published()) if self._address else None
            if words is not None:
                return self._attitude(words)
        return None

    @property
    def closed(self) -> bool:
        """gportd stopped publishing (or close() was called)."""
        return self._address == 0 or bool(self._u32(_OFF_FLAGS) & FLAG_CLOSED)

    def close(self) -> None:
        """Unmaps the block."""
        if self._address:
            _libc.munmap(ctypes.c_void_p(self._address), self._size)
            self._address = 0

    def __enter__(self) -> AttitudeChannel:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __del__(self) -> None:
        self.close()


class RingPump:
    """A thread that hands each new sample of a channel to ``deliver`` (the
    transparent ``subscribe(..., shared_memory=True)`` of both clients): it
    sleeps on the futex and wakes once per sample. stop() wakes it, joins it
    and unmaps the channel. The cost is this thread, in the client."""

    def __init__(self, channel: AttitudeChannel, deliver: Callable[[Attitude], None]) -> None:
        self.channel = channel
        self._deliver = deliver
        self._stopping = threading.Event()
        channel.skip_to_newest()
        self._thread = threading.Thread(target=self._run, name="gport-attitude", daemon=True)
        self._thread.start()

    def _run(self) -> None:
        try:
            self._pump()
        finally:
            if self._stopping.is_set():
                self.channel.close()  # also when stop() came from deliver (no join)

    def _pump(self) -> None:
        channel = self.channel
        while not self._stopping.is_set():
            seen = channel._wake_word()
            sample = channel.take()
            if sample is not None:
                try:
                    self._deliver(sample)
                except RuntimeError:  # the event loop is closed
                    return
                continue
            if channel.closed:
                return
            channel.wait(seen, _PUMP_SLICE)

    def stop(self) -> None:
        self._stopping.set()
        self.channel.wake()
        if self._thread is not threading.current_thread():
            self._thread.join()
            self.channel.close()
