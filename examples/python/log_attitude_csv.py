#!/usr/bin/env python3
"""Log the gimbal's attitude to CSV, one row per sample, with timestamps.

`time` is the sample's receive time in UTC (ISO 8601), `t` the same in
seconds since the epoch; then the IMU and hall angles (degrees) and, when the
gimbal sends them, the hall rates (degrees per second).

    python3 log_attitude_csv.py --rate 10 --seconds 60 --output attitude.csv
"""

from __future__ import annotations

import argparse
import csv
import sys
import time
from datetime import datetime, timezone
from typing import TextIO

import gport

COLUMNS = ["time", "t", "seq", "imu_roll", "imu_pitch", "imu_yaw",
           "hall_roll", "hall_pitch", "hall_yaw", "rate_roll", "rate_pitch", "rate_yaw"]


def row(sample: gport.Attitude) -> list[str]:
    stamp = datetime.fromtimestamp(sample.t, timezone.utc).isoformat(timespec="microseconds")
    rates = sample.rates.hall if sample.rates else None
    values = [sample.imu.roll, sample.imu.pitch, sample.imu.yaw,
              sample.hall.roll, sample.hall.pitch, sample.hall.yaw]
    cells = [stamp, f"{sample.t:.6f}", str(sample.seq)] + [f"{v:.2f}" for v in values]
    cells += [f"{v:.2f}" for v in (rates.roll, rates.pitch, rates.yaw)] if rates else ["", "", ""]
    return cells


def log(gimbal: gport.Client, output: TextIO, rate: float, seconds: float) -> int:
    writer = csv.writer(output)
    writer.writerow(COLUMNS)
    deadline = time.monotonic() + seconds
    rows = 0
    for sample in gimbal.attitude_stream(rate=rate, timeout=5.0):
        writer.writerow(row(sample))
        rows += 1
        if time.monotonic() >= deadline:
            break
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--socket", help="default: $GPORT_SOCKET, else /run/gportd.sock")
    parser.add_argument("--rate", type=float, default=10.0, help="samples per second (at most)")
    parser.add_argument("--seconds", type=float, default=10.0, help="how long to log")
    parser.add_argument("--output", help="CSV file (default: standard output)")
    args = parser.parse_args()

    try:
        with gport.Client(args.socket) as gimbal:
            if args.output:
                with open(args.output, "w", newline="", encoding="utf-8") as output:
                    rows = log(gimbal, output, args.rate, args.seconds)
            else:
                rows = log(gimbal, sys.stdout, args.rate, args.seconds)
    except gport.GportError as error:
        print(f"log_attitude_csv: {error}", file=sys.stderr)
        return 1
    print(f"{rows} samples logged", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
