"""The examples in examples/python, run against gportd --simulate."""

from __future__ import annotations

import csv
import io
import os
import subprocess
import sys

import pytest
from conftest import Daemon, link_up

import gport

EXAMPLES = os.environ.get(
    "GPORT_EXAMPLES",
    os.path.join(os.path.dirname(__file__), "..", "..", "examples", "python"),
)


def run(daemon: Daemon, script: str, *args: str) -> subprocess.CompletedProcess[str]:
    with daemon.client() as client:  # wait for the link, as a user would
        assert link_up(client)
    return subprocess.run(
        [sys.executable, os.path.join(EXAMPLES, script), *args],
        env={**os.environ, "GPORT_SOCKET": daemon.socket},
        capture_output=True,
        text=True,
        timeout=120,
    )


def test_sweep_and_photo(daemon: Daemon) -> None:
    done = run(daemon, "sweep_and_photo.py", "--pitch", "-10", "--yaw", "-20", "0", "20")
    if done.returncode != 0 and "-32602" in done.stderr and '"wait"' in done.stderr:
        # `wait` comes with the tracked motions (helper "track"), merged separately.
        pytest.skip("this gportd has no `wait` on angle/center yet (tracked motions)")
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert len(lines) == 3 and all("photo taken" in line for line in lines)


def test_tracker(daemon: Daemon) -> None:
    done = run(daemon, "tracker.py", "--seconds", "1.5")
    assert done.returncode == 0, done.stderr
    ticks = int(done.stdout.split()[0])
    assert ticks > 5, done.stdout  # 20 Hz nominal; a loaded machine does fewer
    with gport.Client(daemon.socket) as client:
        status = client.status()
        assert status.motion is None, "the tracker stops the gimbal when it ends"
        assert status.counters.motion_updates > 0, "the stream updated one motion"


def test_log_attitude_csv(daemon: Daemon) -> None:
    output = os.path.join(daemon.dir, "attitude.csv")
    done = run(daemon, "log_attitude_csv.py", "--rate", "20", "--seconds", "1", "--output", output)
    assert done.returncode == 0, done.stderr
    with open(output, encoding="utf-8") as file:
        rows = list(csv.DictReader(io.StringIO(file.read())))
    assert len(rows) >= 3
    assert rows[0]["time"].endswith("+00:00")
    seqs = [int(r["seq"]) for r in rows]
    assert seqs == sorted(seqs)
    assert float(rows[-1]["t"]) >= float(rows[0]["t"])
