"""True time without an RTC or a network (issue 43): gportd under
libfaketime (Debian's faketime) with the companion's clock hours off and
stepped mid-run, both ways, while an autopilot publishes its UTC and boot
time. Every capture's vehicle.utc_us is the autopilot's UTC at the capture's
instant (shutter_mono_us, on CLOCK_MONOTONIC, which the fake leaves alone),
within 10 ms p95, and never goes backwards; the capture's own utc_us is the
companion's wrong clock, kept beside it."""

from __future__ import annotations

import glob
import os
import statistics
import time
from pathlib import Path
from typing import Callable

import pytest
from conftest import Daemon, link_up
from test_vehicle import position

import gport

# The companion's clock, as libfaketime reads it from a file at every call:
# five hours slow, then three days fast, then a day slow (a step back).
STEPS = ("-5h", "+3d", "-1d")
STEP_S = {"-5h": -5 * 3600, "+3d": 3 * 86400, "-1d": -86400}
PHOTOS_PER_STEP = 8


def faketime_library() -> str | None:
    found = sorted(glob.glob("/usr/lib/*/faketime/libfaketime.so.1"))
    return found[0] if found else None


def real_utc_us() -> int:
    return time.time_ns() // 1000


class Autopilot:
    """Boot time from this process's CLOCK_MONOTONIC, UTC from its real
    clock (libfaketime is in gportd only): SYSTEM_TIME and a position with
    each, as gport-mavlink publishes them."""

    def __init__(self, client: gport.Client) -> None:
        self.client = client
        self.booted = time.monotonic()

    def boot_ms(self) -> int:
        return 5_000 + int((time.monotonic() - self.booted) * 1000)

    def publish(self) -> None:
        boot_ms = self.boot_ms()
        standing = position(boot_ms, velocity_ned=(0.0, 0.0, 0.0))
        self.client.publish_vehicle(
            position=standing, time=gport.VehicleTime(boot_ms=boot_ms, utc_us=real_utc_us())
        )


def test_captures_carry_the_autopilots_utc_whatever_the_companions_clock(
    make_daemon: Callable[..., Daemon], tmp_path: Path
) -> None:
    library = faketime_library()
    if library is None:
        pytest.skip("libfaketime not installed (Debian package faketime)")
    clock = tmp_path / "companion-clock"
    clock.write_text(STEPS[0] + "\n", encoding="utf-8")
    env = dict(os.environ)
    env.update(
        {
            "LD_PRELOAD": library,
            "FAKETIME_TIMESTAMP_FILE": str(clock),
            "FAKETIME_NO_CACHE": "1",
            "FAKETIME_DONT_FAKE_MONOTONIC": "1",
        }
    )
    daemon = make_daemon({"camera": {"max_position_age_ms": 10_000}}, env=env)
    client = daemon.client()
    assert link_up(client)
    autopilot = Autopilot(client)
    for _ in range(5):  # SYSTEM_TIME's samples; the longest round trips dropped
        autopilot.publish()
        time.sleep(0.05)

    errors_ms: list[float] = []
    previous_utc = 0
    for step in STEPS:
        clock.write_text(step + "\n", encoding="utf-8")
        for _ in range(PHOTOS_PER_STEP):
            autopilot.publish()
            taken = client.photo().capture
            assert taken is not None
            # As the log lists it: with its instants on CLOCK_MONOTONIC.
            capture = client.captures(since=taken.index).captures[0]
            assert capture.vehicle is not None
            vehicle = capture.vehicle
            assert vehicle.tagged, vehicle.why
            assert vehicle.utc_us is not None and capture.shutter_mono_us is not None
            assert capture.utc_us is not None
            # The real UTC at the shutter: its CLOCK_MONOTONIC instant moved
            # onto the real clock.
            real_minus_mono_us = real_utc_us() - time.monotonic_ns() // 1000
            truth_us = capture.shutter_mono_us + real_minus_mono_us
            errors_ms.append((vehicle.utc_us - truth_us) / 1000)
            assert vehicle.utc_us > previous_utc, "the capture's true time went back"
            previous_utc = vehicle.utc_us
            # The companion's own clock is kept beside it, as wrong as it is.
            companion_off_s = (capture.utc_us - truth_us) / 1e6
            assert abs(companion_off_s - STEP_S[step]) < 5, (step, companion_off_s)
            time.sleep(0.03)

    magnitudes = sorted(abs(e) for e in errors_ms)
    p95 = magnitudes[int(0.95 * (len(magnitudes) - 1))]
    print(
        f"\ntrue time under a wrong companion clock ({', '.join(STEPS)}): "
        f"{len(errors_ms)} captures, |vehicle.utc_us - autopilot UTC at the shutter| "
        f"median {statistics.median(magnitudes):.2f} ms, p95 {p95:.2f} ms, "
        f"max {magnitudes[-1]:.2f} ms"
    )
    assert p95 <= 10.0, errors_ms
    assert magnitudes[-1] <= 50.0, errors_ms
