#!/usr/bin/env python3
"""The descriptor attack of issue 22 (problem 3), measured: a read-only peer
sends batches of 32 attitude_channel requests (160 a second, under the
default rate limit of 200) and never reads; after SECONDS another client
asks for the channel. Before: every reply line carried 32 descriptors, they
piled up in flight, and once they passed gportd's RLIMIT_NOFILE everyone got
-32603 "Too many references" (ETOOMANYREFS). Now a connection has its two
in flight once.

The kernel waives that limit for CAP_SYS_RESOURCE, so gportd runs as uid
65534 without capabilities (setpriv), with the usual soft limit of 1024
open files, as on a real system; so this needs root.

    bench/e2e/descriptor_attack.py GPORTD [SECONDS (10)] [ATTACKERS (1)]

Prints the other client's reply, the descriptors it carried, gportd's log
lines about the channel and (version 2 daemons) status's
attitude_channel_failures. Exits 0 when the other client got the channel.
"""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import tempfile
import time


def batch() -> bytes:
    requests = [{"jsonrpc": "2.0", "id": i, "method": "attitude_channel"} for i in range(1, 33)]
    return (json.dumps(requests) + "\n").encode()


def call(path: str, method: str) -> tuple[dict[str, object], int]:
    """One request on a fresh connection: the reply and the descriptors it carried."""
    with socket.socket(socket.AF_UNIX, socket.SOCK_STREAM) as sock:
        sock.connect(path)
        sock.settimeout(10)
        sock.sendall((json.dumps({"jsonrpc": "2.0", "id": 1, "method": method}) + "\n").encode())
        data, fds = b"", []
        while b"\n" not in data:
            chunk, received, _flags, _addr = socket.recv_fds(sock, 65536, 8)
            if not chunk:
                break
            data += chunk
            fds += received
        for fd in fds:
            os.close(fd)
        return json.loads(data.split(b"\n")[0]), len(fds)


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__)
        return 64
    gportd = os.path.abspath(sys.argv[1])
    seconds = float(sys.argv[2]) if len(sys.argv) > 2 else 10.0
    attackers = int(sys.argv[3]) if len(sys.argv) > 3 else 1
    work = tempfile.mkdtemp(prefix="gport-fdattack-", dir="/tmp")
    os.chmod(work, 0o777)
    path = os.path.join(work, "gportd.sock")
    config = os.path.join(work, "gportd.json")
    with open(config, "w", encoding="utf-8") as out:
        json.dump({"socket": {"mode": "0666"}, "log": {"level": "info"}}, out)
    log = open(os.path.join(work, "gportd.log"), "w+", encoding="utf-8")
    daemon = subprocess.Popen(
        ["prlimit", "--nofile=1024:4096", "setpriv", "--reuid=65534", "--regid=65534",
         "--clear-groups", "--inh-caps=-all", "--bounding-set=-all",
         gportd, "--config", config, "--socket", path, "--simulate"],
        stdout=log, stderr=subprocess.STDOUT)
    try:
        for _ in range(200):
            if os.path.exists(path):
                break
            time.sleep(0.05)
        time.sleep(0.5)
        conns = []
        for _ in range(attackers):
            sock = socket.socket(socket.AF_UNIX, socket.SOCK_STREAM)
            sock.connect(path)
            sock.setblocking(False)
            conns.append(sock)
        line, sent, refused = batch(), 0, 0
        start = time.monotonic()
        while time.monotonic() - start < seconds:
            for sock in conns:
                try:
                    sock.send(line)  # never read
                    sent += 1
                except BlockingIOError:
                    refused += 1  # gportd stopped reading us: back-pressure
            time.sleep(0.2)
        reply, fds = call(path, "attitude_channel")
        status, _ = call(path, "status")
        result = status.get("result", {})
        failures = result.get("attitude_channel_failures") if isinstance(result, dict) else None
        daemon.terminate()
        daemon.wait(timeout=10)
        log.seek(0)
        lines = [l.rstrip() for l in log if "attitude channel" in l]
        print(f"gportd: {gportd}")
        print(f"attack: {attackers} peer(s), {sent} batches of 32 written over {seconds:g} s, "
              f"{refused} not taken (socket full)")
        print(f"another client's attitude_channel after {seconds:g} s: {json.dumps(reply)}")
        print(f"  descriptors with it: {fds}")
        print(f"status attitude_channel_failures: {failures}")
        print(f"gportd log lines about the channel: {len(lines)}")
        for l in lines[:3]:
            print(f"  {l}")
        return 0 if "result" in reply else 1
    finally:
        if daemon.poll() is None:
            daemon.kill()
            daemon.wait()


if __name__ == "__main__":
    sys.exit(main())
