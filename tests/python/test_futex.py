"""The futex from Python (gport/_futex.py): the system call is chosen by the
interpreter's own architecture, never the kernel's; a refused call falls
back to polling; a wait sleeps its timeout."""

from __future__ import annotations

import ctypes
import struct
import time
from pathlib import Path

from gport import _futex


def elf_header(bits: int, machine: int, little: bool = True) -> bytes:
    order = "<" if little else ">"
    ident = b"\x7fELF" + bytes([1 if bits == 32 else 2, 1 if little else 2, 1]) + bytes(9)
    return ident + struct.pack(order + "HH", 2, machine)


def test_a_32_bit_arm_interpreter_gets_arm_s_futex_whatever_the_kernel(tmp_path: Path) -> None:
    # Raspberry Pi OS 32-bit on a Pi 4: platform.machine() says "aarch64"
    # (the kernel), but the interpreter is 32-bit ARM, where 98 does not exist.
    exe = tmp_path / "python3"
    exe.write_bytes(elf_header(32, _futex.EM_ARM) + bytes(100))
    architecture = _futex.interpreter_architecture(str(exe), pointer_bits=32)
    assert architecture == (_futex.EM_ARM, 32)
    assert _futex.futex_number(*architecture) == 240
    assert _futex.machine_name(architecture) == "arm (32-bit)"


def test_each_known_interpreter_gets_its_own_call() -> None:
    assert _futex.futex_number(_futex.EM_X86_64, 64) == 202
    assert _futex.futex_number(_futex.EM_AARCH64, 64) == 98
    assert _futex.futex_number(_futex.EM_386, 32) == 240
    assert _futex.futex_number(_futex.EM_ARM, 32) == 240
    # Unknown, or a class that does not fit the machine: poll.
    assert _futex.futex_number(_futex.EM_ARM, 64) is None
    assert _futex.futex_number(21, 64) is None


def test_a_header_of_another_class_than_the_interpreter_is_not_trusted(tmp_path: Path) -> None:
    exe = tmp_path / "python3"
    exe.write_bytes(elf_header(32, _futex.EM_ARM))
    assert _futex.interpreter_architecture(str(exe), pointer_bits=64) is None
    assert _futex.interpreter_architecture(str(tmp_path / "missing")) is None
    exe.write_bytes(b"#!/bin/sh\n" + bytes(20))
    assert _futex.interpreter_architecture(str(exe)) is None
    assert _futex.parse_elf_header(elf_header(64, _futex.EM_AARCH64, little=False)) == (
        _futex.EM_AARCH64,
        64,
    )


def test_the_running_interpreter_is_recognised() -> None:
    assert _futex.ARCHITECTURE is not None
    assert _futex.ARCHITECTURE[1] == struct.calcsize("P") * 8
    assert _futex.FUTEX.available


def test_a_wait_sleeps_its_timeout() -> None:
    word = ctypes.c_uint32(7)
    start = time.monotonic()
    _futex.FUTEX.wait(ctypes.addressof(word), 7, 0.3)
    assert time.monotonic() - start >= 0.25  # never early (may be late)


def test_a_refused_call_falls_back_to_polling_for_good() -> None:
    futex = _futex.Futex(1_000_000)  # no such system call: ENOSYS
    assert futex.available
    word = ctypes.c_uint32(7)
    start = time.monotonic()
    futex.wait(ctypes.addressof(word), 7, 5.0)
    assert not futex.available
    assert time.monotonic() - start < 4.0  # a poll slice, not the timeout
    futex.wake_all(ctypes.addressof(word))  # no call, no error
