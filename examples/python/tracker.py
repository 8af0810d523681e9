#!/usr/bin/env python3
"""A tracker loop: steer the gimbal with speed commands at 20 Hz.

A real tracker takes the target's position from a camera or a detector; here
the target is a point moving to and fro in yaw. Each tick compares it with
the gimbal's latest attitude (from the attitude notifications, drained
without blocking) and sends a proportional speed with a short lease: if this
program hangs, gportd stops the gimbal within `--lease-ms`.

    python3 tracker.py --seconds 10
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import gport

RATE_HZ = 20.0
GAIN = 1.5  # degrees per second per degree of error
MAX_SPEED = 40.0


def target_yaw(elapsed: float) -> float:
    """Where the simulated target is: 30 degrees either side, every 8 seconds."""
    return 30.0 * math.sin(2 * math.pi * elapsed / 8.0)


def latest_sample(gimbal: gport.Client, last: gport.Attitude | None) -> gport.Attitude | None:
    """The newest attitude notification waiting, or `last` when none arrived."""
    while (item := gimbal.next_notification("attitude", timeout=0)) is not None:
        if isinstance(item, gport.Attitude):
            last = item
    return last


def track(gimbal: gport.Client, seconds: float, lease_ms: int) -> int:
    gimbal.subscribe("attitude", max_rate_hz=RATE_HZ)
    start = time.monotonic()
    sample: gport.Attitude | None = None
    ticks = 0
    while (elapsed := time.monotonic() - start) < seconds:
        sample = latest_sample(gimbal, sample)
        if sample is not None:
            error = target_yaw(elapsed) - sample.hall.yaw
            yaw = max(-MAX_SPEED, min(MAX_SPEED, GAIN * error))
            gimbal.speed(yaw=yaw, lease_ms=lease_ms, duration_ms=5000, clamp=True)
            ticks += 1
        next_tick = start + (ticks + 1) / RATE_HZ
        time.sleep(max(0.0, next_tick - time.monotonic()))
    return ticks


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--socket", help="default: $GPORT_SOCKET, else /run/gportd.sock")
    parser.add_argument("--seconds", type=float, default=10.0, help="how long to track")
    parser.add_argument("--lease-ms", type=int, default=300, help="the deadman lease of each speed")
    args = parser.parse_args()

    try:
        with gport.Client(args.socket) as gimbal:
            try:
                ticks = track(gimbal, args.seconds, args.lease_ms)
            finally:
                gimbal.stop()
            final = gimbal.attitude()
    except gport.GportError as error:
        print(f"tracker: {error}", file=sys.stderr)
        return 1
    print(f"{ticks} speed commands in {args.seconds} s; final yaw {final.hall.yaw:.2f}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
