#!/usr/bin/env python3
"""Sweep the camera across a few yaw positions and take a photo at each.

Each `angle(..., wait=True)` returns when the gimbal has reached the target
(or the motion ended otherwise: the reason says why). Control is held for the
whole sweep so that no other client moves the camera in between.

    python3 sweep_and_photo.py --pitch -20 --yaw -60 -30 0 30 60
"""

from __future__ import annotations

import argparse
import sys

import gport


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--socket", help="default: $GPORT_SOCKET, else /run/gportd.sock")
    parser.add_argument("--pitch", type=float, default=-20.0, help="pitch for every shot, degrees")
    parser.add_argument("--yaw", type=float, nargs="+", default=[-30.0, 0.0, 30.0],
                        help="yaw positions, degrees")
    args = parser.parse_args()

    try:
        with gport.Client(args.socket) as gimbal, gimbal.control():
            for yaw in args.yaw:
                result = gimbal.angle(pitch=args.pitch, yaw=yaw, clamp=True, wait=True)
                reason = result.ended.reason if result.ended else "sent"
                gimbal.photo()
                target = result.angle
                print(f"yaw {target.yaw:7.2f} pitch {target.pitch:7.2f}: {reason}, photo taken")
            gimbal.center(wait=True)
    except gport.GportError as error:
        print(f"sweep_and_photo: {error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
