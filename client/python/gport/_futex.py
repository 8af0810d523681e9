"""The futex, from Python, for the shared-memory attitude channel's wake word.

The system call number depends on the INTERPRETER's architecture, not the
kernel's: Raspberry Pi OS 32-bit on a Pi 4/5 runs a 32-bit (armhf) Python on
a 64-bit kernel, where ``platform.machine()`` says ``aarch64`` but 98 (arm64's
futex) does not exist for the process ("Function not implemented"). The
interpreter's architecture is read from its own ELF header (/proc/self/exe):
its class (32/64-bit) and machine.

The timeout is passed in the layout the chosen call takes: ``SYS_futex`` reads
a timespec of two C longs (32-bit on 32-bit targets, whatever the C library's
_TIME_BITS), which is what ctypes' c_long gives. Should the call still be
refused (ENOSYS: a seccomp filter, an emulator), waits fall back to polling
every millisecond, for good.
"""

from __future__ import annotations

import ctypes
import errno
import struct
import threading
from typing import Any

# ELF e_machine values and Linux's futex system call on each (the "old" one,
# whose timespec is made of longs: right on every one of them).
EM_386 = 3
EM_ARM = 40
EM_X86_64 = 62
EM_AARCH64 = 183
EM_RISCV = 243
_FUTEX_BY_MACHINE = {
    (EM_X86_64, 64): 202,
    (EM_AARCH64, 64): 98,
    (EM_RISCV, 64): 98,
    (EM_ARM, 32): 240,
    (EM_386, 32): 240,
}
_NAMES = {
    EM_386: "i386",
    EM_ARM: "arm",
    EM_X86_64: "x86_64",
    EM_AARCH64: "aarch64",
    EM_RISCV: "riscv",
}
FUTEX_WAIT = 0
FUTEX_WAKE = 1
POLL_SLICE = 0.001  # seconds, without a futex


def futex_number(machine: int, bits: int) -> int | None:
    """The futex system call of an interpreter of this ELF machine and class
    (32 or 64 bits), or None where we do not know it (waits then poll)."""
    return _FUTEX_BY_MACHINE.get((machine, bits))


def parse_elf_header(head: bytes) -> tuple[int, int] | None:
    """(e_machine, bits) of an ELF header's first 20 bytes, or None."""
    if len(head) < 20 or head[:4] != b"\x7fELF" or head[4] not in (1, 2):
        return None
    bits = 32 if head[4] == 1 else 64
    order = "<" if head[5] == 1 else ">"
    (machine,) = struct.unpack_from(order + "H", head, 18)
    return machine, bits


def interpreter_architecture(
    path: str = "/proc/self/exe", pointer_bits: int = struct.calcsize("P") * 8
) -> tuple[int, int] | None:
    """The running interpreter's (e_machine, bits), from its own ELF header;
    None when it cannot be read or its class is not the interpreter's pointer
    size."""
    try:
        with open(path, "rb") as exe:
            found = parse_elf_header(exe.read(20))
    except OSError:
        return None
    if found is None or found[1] != pointer_bits:
        return None
    return found


def machine_name(architecture: tuple[int, int] | None) -> str:
    """A readable name: "x86_64", "arm (32-bit)", "machine 21 (64-bit)"."""
    if architecture is None:
        return "an unknown architecture"
    machine, bits = architecture
    name = _NAMES.get(machine, f"machine {machine}")
    return f"{name} ({bits}-bit)"


ARCHITECTURE = interpreter_architecture()
NAME = machine_name(ARCHITECTURE)
IS_X86_64 = ARCHITECTURE == (EM_X86_64, 64)


class _Timespec(ctypes.Structure):
    _fields_ = [("tv_sec", ctypes.c_long), ("tv_nsec", ctypes.c_long)]


class Futex:
    """Waits and wakes on 32-bit words; polls where the futex is unknown or
    refused."""

    def __init__(self, number: int | None) -> None:
        self._number = number
        self._libc = ctypes.CDLL(None, use_errno=True)
        self._libc.syscall.restype = ctypes.c_long

    @property
    def available(self) -> bool:
        return self._number is not None

    def _call(self, *args: Any) -> None:
        number = self._number
        if number is None:
            return
        ctypes.set_errno(0)
        if self._libc.syscall(ctypes.c_long(number), *args) == -1:
            if ctypes.get_errno() == errno.ENOSYS:
                self._number = None  # poll from now on

    def wait(self, address: int, seen: int, timeout: float) -> None:
        """Sleeps while the word at ``address`` holds ``seen``, at most
        ``timeout`` seconds (interrupted early by a signal: callers loop)."""
        if self._number is None:
            threading.Event().wait(min(max(timeout, 0.0), POLL_SLICE))
            return
        timeout = max(timeout, 0.0)
        whole = int(timeout)
        span = _Timespec(whole, int((timeout - whole) * 1e9))
        self._call(
            ctypes.c_void_p(address),
            ctypes.c_int(FUTEX_WAIT),
            ctypes.c_uint32(seen),
            ctypes.byref(span),
            None,
            ctypes.c_int(0),
        )
        if self._number is None:  # refused just now: wait the polling way
            threading.Event().wait(min(timeout, POLL_SLICE))

    def wake(self, address: int, count: int) -> None:
        """Wakes at most ``count`` waiters on the word at ``address``."""
        self._call(
            ctypes.c_void_p(address),
            ctypes.c_int(FUTEX_WAKE),
            ctypes.c_int(count),
            None,
            None,
            ctypes.c_int(0),
        )

    def wake_all(self, address: int) -> None:
        """Wakes every waiter on the word at ``address``."""
        self.wake(address, 2**31 - 1)


FUTEX = Futex(futex_number(*ARCHITECTURE) if ARCHITECTURE else None)
