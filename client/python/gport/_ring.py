"""One connection's shared-memory attitude channel, mapped: the ring and the
connection's wake block (docs/api.md, "Shared-memory attitude channel"),
checked before they are mapped and never trusted afterwards.

The ring (layout version 2 of base/include/gport/base/attitude_ring.hpp), in
native (little-endian) byte order, is a 64-byte header and then
``slot_count`` 128-byte slots::

    header  0 u32 magic 0x52415047 ("GPAR")   4 u32 version (2)
            8 u32 header_size (64)            12 u32 slot_size (128)
           16 u32 slot_count (a power of two) 20 u32 flags (1: closed)
           24 u32 reserved (0; version 1's futex word)
           28 u32 reserved                    32 u64 published (n of the newest)
    slot    0 u64 seq: 2n - 1 while sample n is written, 2n once complete
            8 u64 sample seq   16 f64 t   24 f64 imu roll, pitch, yaw
           48 f64 hall roll, pitch, yaw   72 u64 has_rates (0 or 1)
           80 f64 hall_rates roll, pitch, yaw   104 f64 imu_rates x, y, z

The wake block (base/include/gport/base/wake_block.hpp), 64 bytes: u32 magic
0x57415047 ("GPAW") at 0, u32 version 1 at 4, u32 size 64 at 8, the u32
futex word at 16. gportd bumps it and wakes ONE waiter per sample; the first
thread of this process to see a new value wakes the others (relay()).

Checks: each descriptor must be a memfd sealed with F_SEAL_SHRINK and
F_SEAL_WRITE or F_SEAL_FUTURE_WRITE (looked at first), then of exactly the
size announced (the ring's ``size``; 64), so it can never shrink under this
process (SIGBUS);
the slot count used is the one checked here, never re-read.

Reads: a slot is a seqlock (its seq, the words, its seq again). On a weakly
ordered CPU (arm64) the loads need fences that ctypes cannot make, so the
read is libgport-client's ``gport_ring_read`` (loaded from
$GPORT_CLIENT_LIBRARY, else ``libgport-client.so.1``; "none" loads nothing)
when it is there.
Without it plain loads are used by an x86_64 interpreter only (loads are
not reordered with loads there, and aligned 8-byte loads are atomic); on any
other CPU mapping the channel raises BadChannel. The futex: _futex.py (the
system call of the interpreter's own architecture; elsewhere, or where it is
refused, waits poll every millisecond).
"""

from __future__ import annotations

import ctypes
import fcntl
import mmap
import os
import stat
import struct
import threading
from typing import Any, Callable, NamedTuple

from ._futex import FUTEX, IS_X86_64, NAME
from .errors import BadChannel

MAGIC = 0x52415047
VERSION = 2
HEADER_SIZE = 64
SLOT_SIZE = 128
MAX_SLOTS = 1 << 16
FLAG_CLOSED = 1
WAKE_MAGIC = 0x57415047
WAKE_VERSION = 1
WAKE_SIZE = 64
OFF_SLOT_COUNT = 16
OFF_FLAGS = 20
OFF_PUBLISHED = 32
OFF_WAKE = 16  # in the wake block
_HEADER = struct.Struct("=IIIII")  # magic, version, header_size, slot_size, slot_count
_WAKE_HEADER = struct.Struct("=III")  # magic, version, size
WORDS = struct.Struct("=Qd3d3dQ3d3d")  # the 15 words after a slot's seq

# fcntl's seals (Linux), defined here: Python's fcntl module lacks FUTURE_WRITE.
F_GET_SEALS = 1034
F_SEAL_SHRINK = 0x0002
F_SEAL_WRITE = 0x0008
F_SEAL_FUTURE_WRITE = 0x0010

LIBRARY_ENV = "GPORT_CLIENT_LIBRARY"

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
_MAP_FAILED = ctypes.c_void_p(-1).value
_Words = ctypes.c_uint64 * 15


def load_fenced_reader() -> Callable[..., int] | None:
    """libgport-client's gport_ring_read, or None when it cannot be loaded
    (or $GPORT_CLIENT_LIBRARY is "none": use plain loads where they are safe)."""
    path = os.environ.get(LIBRARY_ENV) or "libgport-client.so.1"
    if path == "none":
        return None
    try:
        library = ctypes.CDLL(path)
        read: Callable[..., int] = library.gport_ring_read
    except (OSError, AttributeError):
        return None
    read.restype = ctypes.c_int  # type: ignore[attr-defined]
    read.argtypes = [  # type: ignore[attr-defined]
        ctypes.c_void_p,
        ctypes.c_uint32,
        ctypes.c_uint64,
        ctypes.POINTER(ctypes.c_uint64),
    ]
    return read


class Loads(NamedTuple):
    """libgport-client's acquire loads (since 1.3): the order of the wake
    word, ``published`` and the flags is kept on weakly ordered CPUs."""

    published: Callable[[int], int]
    flags: Callable[[int], int]
    wake_word: Callable[[int], int]


def load_fenced_loads() -> Loads | None:
    """The acquire loads of libgport-client 1.3 or later, else None."""
    path = os.environ.get(LIBRARY_ENV) or "libgport-client.so.1"
    if path == "none":
        return None
    try:
        library = ctypes.CDLL(path)
        minor = library.gport_client_abi_minor
        minor.restype = ctypes.c_uint32
        if minor() < 3:
            return None
        loads = []
        for name, result in (
            ("gport_ring_published", ctypes.c_uint64),
            ("gport_ring_flags", ctypes.c_uint32),
            ("gport_wake_word", ctypes.c_uint32),
        ):
            load = getattr(library, name)
            load.restype, load.argtypes = result, [ctypes.c_void_p]
            loads.append(load)
    except (OSError, AttributeError):
        return None
    return Loads(*loads)


_fenced: list[tuple[Callable[..., int] | None, Loads | None]] = []  # loaded once, on first use


def fenced_reader() -> Callable[..., int] | None:
    return _library()[0]


def fenced_loads() -> Loads | None:
    return _library()[1]


def _library() -> tuple[Callable[..., int] | None, Loads | None]:
    if not _fenced:
        read = load_fenced_reader()
        _fenced.append((read, None if read is None else load_fenced_loads()))
    return _fenced[0]


def futex_available() -> bool:
    """True when waits sleep on the futex, False when they poll (_futex.py)."""
    return FUTEX.available


def _fail(what: str) -> BadChannel:
    return BadChannel(f"attitude channel: {what}")


def reply_fields(result: Any) -> tuple[int, int, int]:
    """(slots, size, descriptors) of an attitude_channel result, checked."""
    if not isinstance(result, dict):
        raise _fail("the reply's result is not an object")

    def unsigned(name: str) -> int:
        value = result.get(name)
        if not isinstance(value, int) or isinstance(value, bool) or value < 0:
            raise _fail(f'the reply\'s "{name}" is missing or not a non-negative integer')
        return value

    version = unsigned("version")
    if version != VERSION:
        newer = "gportd" if version < VERSION else "the gport package"
        raise _fail(
            f"gportd's channel is version {version}; this client reads version {VERSION}"
            f" (update {newer})"
        )
    slots = unsigned("slots")
    if slots == 0 or slots & (slots - 1) or slots > MAX_SLOTS:
        raise _fail(f"slots = {slots} is not a power of two from 1 to {MAX_SLOTS}")
    size = unsigned("size")
    if size != HEADER_SIZE + slots * SLOT_SIZE:
        raise _fail(
            f"size = {size} does not fit {slots} slots ({HEADER_SIZE + slots * SLOT_SIZE} bytes)"
        )
    descriptors = unsigned("descriptors")
    if descriptors not in (0, 2):
        raise _fail(f"descriptors = {descriptors}; gportd sends 2 or 0")
    return slots, size, descriptors


def check_descriptor(fd: int, size: int, what: str) -> None:
    """A memfd that can neither shrink nor be written, of exactly ``size``
    bytes. The seals are read first: once F_SEAL_SHRINK is there nobody can
    remove it, so the size seen next stays (size first, a server holding
    another descriptor could shrink the file between the two looks and seal
    it then: the client would map the old size and die of SIGBUS)."""
    try:
        seals = fcntl.fcntl(fd, F_GET_SEALS)
    except OSError as error:
        raise _fail(f"the {what} is not a sealed memfd (F_GET_SEALS: {error.strerror})") from None
    if not seals & F_SEAL_SHRINK or not seals & (F_SEAL_WRITE | F_SEAL_FUTURE_WRITE):
        raise _fail(
            f"the {what} is not sealed against shrinking and writing (seals {seals:#x}; "
            "F_SEAL_SHRINK and F_SEAL_WRITE or F_SEAL_FUTURE_WRITE are required): refused"
        )
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode) or info.st_size != size:
        raise _fail(f"the {what} is {info.st_size} bytes, not the {size} expected")


def ring_problem(header: bytes, size: int) -> str | None:
    """What is wrong with a ring (its first bytes, the mapping's size), or None:
    the checks of base::RingReader::check, with the same messages."""
    if size < HEADER_SIZE or len(header) < _HEADER.size:
        return "the block is smaller than a ring header"
    magic, version, header_size, slot_size, slot_count = _HEADER.unpack_from(header)
    if magic != MAGIC:
        return "not an attitude ring (bad magic)"
    if version != VERSION:
        return f"attitude ring version {version} is not supported ({VERSION} is)"
    if header_size != HEADER_SIZE or slot_size != SLOT_SIZE:
        return f"attitude ring header or slot size does not match version {VERSION}"
    if slot_count == 0 or slot_count & (slot_count - 1) or slot_count > MAX_SLOTS:
        return f"attitude ring slot count {slot_count} is not a power of two from 1 to {MAX_SLOTS}"
    if size < HEADER_SIZE + slot_count * SLOT_SIZE:
        return "the block is smaller than its ring"
    if size != HEADER_SIZE + slot_count * SLOT_SIZE:
        return "the block is larger than its ring"
    return None


def wake_problem(header: bytes) -> str | None:
    magic, version, size = _WAKE_HEADER.unpack_from(header)
    if magic != WAKE_MAGIC:
        return "not an attitude channel wake block (bad magic)"
    if version != WAKE_VERSION:
        return f"wake block version {version} is not supported ({WAKE_VERSION} is)"
    if size != WAKE_SIZE:
        return f"the wake block's header gives size {size}, not {WAKE_SIZE}"
    return None


def _map(fd: int, size: int, what: str) -> int:
    address = _libc.mmap(None, size, mmap.PROT_READ, mmap.MAP_SHARED, fd, 0)
    if address is None or address == _MAP_FAILED:
        raise _fail(f"cannot map the {what}: {os.strerror(ctypes.get_errno())}")
    return int(address)


class Mapping:
    """One connection's ring and wake block, mapped read-only and checked,
    with the relay state every reader of the connection in this process
    shares. Unmapped when the last reference goes (each AttitudeChannel and
    the client that cached it hold one; the mapping refers to none of them
    nor to itself, so no cycle waits for the collector). The descriptors
    stay the caller's."""

    def __init__(self, ring_fd: int, wake_fd: int, slots: int, size: int) -> None:
        self._ring = self._wake = 0
        self._read, self._loads = _reader()  # module functions: no reference to self
        check_descriptor(ring_fd, size, "ring")
        check_descriptor(wake_fd, WAKE_SIZE, "wake block")
        self.size = size
        self.slots = slots  # the count checked: never re-read from the block
        try:
            self._ring = _map(ring_fd, size, "ring")
            self._wake = _map(wake_fd, WAKE_SIZE, "wake block")
            self._check_headers()
        except BaseException:
            self._unmap()
            raise
        self._lock = threading.Lock()
        self._relayed = self.wake_word()

    def _check_headers(self) -> None:
        problem = ring_problem(ctypes.string_at(self._ring, HEADER_SIZE), self.size)
        if problem is None and (self.size - HEADER_SIZE) // SLOT_SIZE != self.slots:
            problem = "the ring does not hold the slots the reply announced"
        problem = problem or wake_problem(ctypes.string_at(self._wake, WAKE_SIZE))
        if problem is not None:
            raise _fail(problem)

    # ---- loads ----------------------------------------------------------------
    def u32(self, offset: int) -> int:
        return ctypes.c_uint32.from_address(self._ring + offset).value

    def u64(self, offset: int) -> int:
        return ctypes.c_uint64.from_address(self._ring + offset).value

    def published(self) -> int:
        if self._loads is not None:
            return self._loads.published(self._ring)
        return self.u64(OFF_PUBLISHED)

    def closed(self) -> bool:
        flags = self._loads.flags(self._ring) if self._loads else self.u32(OFF_FLAGS)
        return bool(flags & FLAG_CLOSED)

    def wake_word(self) -> int:
        if self._loads is not None:
            return self._loads.wake_word(self._wake)
        return ctypes.c_uint32.from_address(self._wake + OFF_WAKE).value

    def read_words(self, n: int) -> tuple[Any, ...] | None:
        """The words of sample ``n`` when slot n still holds it, else None."""
        if n == 0:
            return None
        if self._read is None:
            return self._read_plain(n)
        # A buffer per read: the library fills it with the GIL released, so
        # a buffer shared by the threads could be rewritten by another read
        # between this one's return and the copy below.
        words = _Words()
        if not self._read(self._ring, self.slots, n, words):
            return None
        return WORDS.unpack(bytes(words))

    def _read_plain(self, n: int) -> tuple[Any, ...] | None:
        """x86_64 only: loads are not reordered with loads."""
        slot = HEADER_SIZE + ((n - 1) % self.slots) * SLOT_SIZE
        before = self.u64(slot)
        if before != 2 * n:
            return None
        words = ctypes.string_at(self._ring + slot + 8, WORDS.size)
        if self.u64(slot) != before:
            return None
        return WORDS.unpack(words)

    @property
    def fenced(self) -> bool:
        """True when reads go through libgport-client's gport_ring_read."""
        return self._read is not None

    # ---- waiting ----------------------------------------------------------------
    def relay(self, seen: int) -> bool:
        """Passes a wake on: the first thread of this process to see a value
        of the word newer than every one relayed yet wakes the others
        (gportd wakes only one); True for that thread. Only forward: a
        thread that loaded an older value and was preempted neither moves
        the relay back nor wakes everyone again (modulo 2**32: it wraps)."""
        with self._lock:
            if not 0 < (seen - self._relayed) % 2**32 < 2**31:
                return False
            self._relayed = seen
        self.wake_all()
        return True

    def wait(self, seen: int, timeout: float) -> None:
        """Sleeps while the word still holds ``seen``, at most ``timeout`` s."""
        FUTEX.wait(self._wake + OFF_WAKE, seen, timeout)

    def wake_all(self) -> None:
        """Wakes every waiter on the word (a read-only mapping is enough)."""
        FUTEX.wake_all(self._wake + OFF_WAKE)

    def _unmap(self) -> None:
        if self._ring:
            _libc.munmap(ctypes.c_void_p(self._ring), self.size)
            self._ring = 0
        if self._wake:
            _libc.munmap(ctypes.c_void_p(self._wake), WAKE_SIZE)
            self._wake = 0

    def __del__(self) -> None:
        try:
            self._unmap()
        except Exception:  # interpreter shutdown: ctypes may be gone already
            pass


def _reader() -> tuple[Callable[..., int] | None, Loads | None]:
    """libgport-client's fenced read and loads, or (None, None) for plain
    loads where they are safe (x86_64); BadChannel on any other CPU."""
    read = fenced_reader()
    if read is not None:
        return read, fenced_loads()
    if IS_X86_64:
        return None, None
    raise _fail(
        f"the shared-memory channel needs libgport-client on this CPU ({NAME}): its "
        "ring cannot be read safely without fences; install libgport-client.so.1 (gportd's "
        f"package ships it) or set {LIBRARY_ENV} to its path (the socket keeps working)"
    )
