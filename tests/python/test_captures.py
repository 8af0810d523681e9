"""Captures through gport.Client and gport.AsyncClient: `meta` on photo and
record, the `captures` method, the `capture` notification, the log kept
across a restart (docs/api.md, "Captures")."""

from __future__ import annotations

import asyncio
import os
from pathlib import Path
from typing import Callable

import pytest
from conftest import Daemon, eventually, link_up

import gport


def test_meta_that_is_no_mapping_is_refused_before_anything_is_sent(
    client: gport.Client,
) -> None:
    for bad in ([1, 2], "lat=1", 3):
        with pytest.raises(ValueError, match="meta must be a mapping"):
            client.photo(meta=bad)  # type: ignore[arg-type]
        with pytest.raises(ValueError, match="meta must be a mapping"):
            client.record(meta=bad)  # type: ignore[arg-type]
    assert client.captures().captures == ()


def test_meta_over_1024_bytes_is_invalid_params_and_takes_nothing(client: gport.Client) -> None:
    with pytest.raises(gport.InvalidParams, match="at most 1024"):
        client.photo(meta={"note": "x" * 1100})
    with pytest.raises(gport.InvalidParams, match="at most 1024"):
        client.record(meta={"note": "x" * 1100})
    assert client.captures().captures == ()
    # Exactly at the bound (compact JSON, as gportd counts) is accepted.
    at_bound = {"n": "x" * (1024 - len('{"n":""}'))}
    assert client.photo(meta=at_bound).capture is not None


def test_a_photo_with_meta_is_listed_with_its_attitude_and_client(client: gport.Client) -> None:
    sample = client.attitude()
    result = client.photo(meta={"lat": 47.397742, "lon": 8.545594, "wp": 3})
    assert result.sent and result.capture is not None
    taken = result.capture
    assert taken.index >= 1 and taken.kind == "photo"
    assert taken.utc_us is not None and abs(taken.utc_us / 1e6 - sample.t) < 60
    listed = client.captures()
    assert [c.index for c in listed.captures] == [taken.index]
    assert listed.next == taken.index + 1
    capture = listed.captures[0]
    assert capture.meta == {"lat": 47.397742, "lon": 8.545594, "wp": 3}
    assert capture.utc_us == taken.utc_us and capture.mono_us is not None
    assert capture.attitude is not None and capture.attitude.age_ms >= 0
    assert abs(capture.attitude.hall.pitch - sample.hall.pitch) < 5
    assert capture.client is not None and capture.client.pid == os.getpid()
    assert capture.client.uid == os.getuid()
    assert capture.raw["index"] == taken.index


def test_record_toggles_are_captures_of_their_kind(client: gport.Client) -> None:
    toggled = client.record()
    assert toggled.capture is not None and toggled.capture.kind == "record_toggle"
    started = client.record(on=True, force=True, meta={"leg": 1})
    assert started.capture is not None and started.capture.kind == "record_start"
    unsent = client.record(on=True)  # already on: nothing reaches the wire
    assert not unsent.sent and unsent.capture is None
    stopped = client.record(on=False)
    assert stopped.capture is not None and stopped.capture.kind == "record_stop"
    kinds = [(c.kind, c.meta) for c in client.captures().captures]
    assert kinds == [("record_toggle", None), ("record_start", {"leg": 1}), ("record_stop", None)]


def test_since_and_limit_page_through_the_log(client: gport.Client) -> None:
    indexes = []
    for _ in range(5):
        capture = client.photo().capture
        assert capture is not None
        indexes.append(capture.index)
    seen, since = [], 0
    while True:
        page = client.captures(since=since, limit=2)
        if not page.captures:
            break
        assert len(page.captures) <= 2
        seen += [c.index for c in page.captures]
        since = page.next
    assert seen == indexes
    assert client.captures(since=since).next == indexes[-1] + 1
    with pytest.raises(gport.InvalidParams, match="limit"):
        client.captures(limit=0)


def test_subscribers_get_each_capture_as_a_notification(daemon: Daemon) -> None:
    with daemon.client() as watcher, daemon.client() as taker:
        assert link_up(taker)
        watcher.subscribe(["capture"])
        taken = taker.photo(meta={"wp": 7}).capture
        assert taken is not None
        event = watcher.next_notification("capture", timeout=5)
        assert isinstance(event, gport.Capture)
        assert event.index == taken.index and event.kind == "photo"
        assert event.meta == {"wp": 7}
        assert event.client is not None and event.client.pid == os.getpid()


def test_indexes_continue_after_a_restart(
    make_daemon: Callable[..., Daemon], tmp_path: Path
) -> None:
    daemon = make_daemon({"captures": {"dir": str(tmp_path)}})
    with daemon.client() as client:
        assert link_up(client)
        first = client.photo(meta={"run": 1}).capture
        assert first is not None
    daemon.restart()
    with daemon.client() as client:
        assert link_up(client)
        second = client.photo(meta={"run": 2}).capture
        assert second is not None and second.index == first.index + 1
        metas = [c.meta for c in client.captures().captures]
        assert metas == [{"run": 1}, {"run": 2}]
    # The writer thread appends each line after the reply: wait for it.
    log = tmp_path / "captures.jsonl"
    assert eventually(lambda: log.read_text().count("\n") == 2), log.read_text()


def test_async_photo_record_and_captures(daemon: Daemon) -> None:
    async def main() -> None:
        client = await gport.AsyncClient.open(daemon.socket)
        try:
            for _ in range(500):
                if (await client.status()).link.state == "up":
                    break
                await asyncio.sleep(0.02)
            photo = await client.photo(meta={"wp": 1})
            assert photo.capture is not None and photo.capture.kind == "photo"
            record = await client.record(on=True, force=True, meta={"wp": 2})
            assert record.capture is not None and record.capture.kind == "record_start"
            with pytest.raises(ValueError, match="meta must be a mapping"):
                await client.photo(meta=["wp"])  # type: ignore[arg-type]
            listed = await client.captures(since=photo.capture.index)
            assert [(c.kind, c.meta) for c in listed.captures] == [
                ("photo", {"wp": 1}),
                ("record_start", {"wp": 2}),
            ]
        finally:
            await client.close()

    asyncio.run(main())
