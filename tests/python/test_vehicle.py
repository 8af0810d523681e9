"""publish_vehicle and the vehicle's stamp on captures through gport.Client
and gport.AsyncClient: against gportd --simulate (a position carried to the
capture's instant, untagged and why, refusals naming the field, status's
vehicle), and against a fake daemon that lies about the new members' types
or predates them."""

from __future__ import annotations

import asyncio
import dataclasses
import json
import os
import time
from typing import Any, Callable, Iterator

import pytest
from conftest import Daemon, link_up
from test_hostile import PATIENT, Hostile

import gport

# Metres per degree of latitude near 47 deg (WGS84's meridian, to 0.1 %).
METRES_PER_DEG_LAT = 111_180.0
UTC_US = 1_700_000_000_000_000  # 2023-11-14, within what gportd takes


def position(boot_ms: int, **members: Any) -> gport.VehiclePosition:
    """A vehicle at 47 N 8 E flying north at 10 m/s with a 3D fix."""
    values: dict[str, Any] = {
        "boot_ms": boot_ms,
        "lat": 47.0,
        "lon": 8.0,
        "alt_msl_m": 500.0,
        "velocity_ned": (10.0, 0.0, 0.0),
        "alt_rel_m": 20.0,
        "heading_deg": 0.0,
        "fix": 3,
        "h_acc_m": 1.5,
        "satellites": 12,
    }
    values.update(members)
    return gport.VehiclePosition(**values)


@pytest.fixture
def daemon(make_daemon: Callable[..., Daemon]) -> Daemon:
    """gportd --simulate keeping a position for 10 s (default 1 s): a slow
    test machine leaves no capture untagged."""
    return make_daemon({"camera": {"max_position_age_ms": 10_000}})


def test_without_a_source_captures_have_no_vehicle(client: gport.Client) -> None:
    assert client.status().vehicle is None
    taken = client.photo().capture
    assert taken is not None and taken.vehicle is None
    listed = client.captures().captures[0]
    assert listed.vehicle is None
    assert listed.line_mono_us is not None and listed.mono_us is not None
    assert listed.line_mono_us >= listed.mono_us
    assert listed.shutter_mono_us == listed.line_mono_us  # camera.shutter_delay_ms 0


def test_a_photo_is_tagged_with_the_position_carried_to_its_instant(
    client: gport.Client,
) -> None:
    client.publish_vehicle(
        position=position(10_000), time=gport.VehicleTime(boot_ms=10_000, utc_us=UTC_US)
    )
    time.sleep(0.3)  # the vehicle flies 3 m north meanwhile
    taken = client.photo(meta={"wp": 1}).capture
    assert taken is not None and taken.vehicle is not None
    vehicle = taken.vehicle
    assert vehicle.tagged and vehicle.why == ""
    assert vehicle.age_ms is not None and vehicle.age_ms >= 250
    assert vehicle.lat is not None and vehicle.lat > 47.0
    moved_m = (vehicle.lat - 47.0) * METRES_PER_DEG_LAT
    assert abs(moved_m - 10.0 * vehicle.age_ms / 1000) < 0.05, (moved_m, vehicle.age_ms)
    assert vehicle.lon == pytest.approx(8.0, abs=1e-8)
    assert vehicle.alt_msl_m == pytest.approx(500.0) and vehicle.alt_rel_m == pytest.approx(20.0)
    assert vehicle.velocity_ned == (10.0, 0.0, 0.0)
    assert vehicle.fix == 3 and vehicle.satellites == 12 and vehicle.v_acc_m is None
    assert vehicle.h_acc_m is not None and vehicle.h_acc_m > 1.5  # grown by age x speed
    # The autopilot's UTC at the instant, not the companion's clock.
    assert vehicle.utc_us is not None
    assert abs(vehicle.utc_us - (UTC_US + vehicle.age_ms * 1000)) < 2000
    listed = client.captures(since=taken.index).captures[0]
    assert listed.vehicle == vehicle and listed.meta == {"wp": 1}
    assert listed.line_mono_us is not None and listed.shutter_mono_us is not None
    recorded = client.record(on=True, force=True).capture
    assert recorded is not None and recorded.vehicle is not None and recorded.vehicle.tagged


def test_without_a_3d_fix_the_capture_is_untagged_and_says_why(client: gport.Client) -> None:
    client.publish_vehicle(position=position(5_000, fix=1))
    taken = client.photo().capture
    assert taken is not None and taken.vehicle is not None
    vehicle = taken.vehicle
    assert not vehicle.tagged
    assert "GPS_FIX_TYPE 1" in vehicle.why
    assert vehicle.lat is None and vehicle.velocity_ned is None and vehicle.age_ms is None
    assert vehicle.utc_us is None  # no time published


def test_a_position_older_than_the_configured_age_leaves_the_capture_untagged(
    make_daemon: Callable[..., Daemon],
) -> None:
    daemon = make_daemon({"camera": {"max_position_age_ms": 100}})
    with daemon.client() as client:
        assert link_up(client)
        client.publish_vehicle(position=position(1_000))
        time.sleep(0.3)
        taken = client.photo().capture
        assert taken is not None and taken.vehicle is not None
        assert not taken.vehicle.tagged
        assert "old at the capture (camera.max_position_age_ms is 100)" in taken.vehicle.why


def test_status_shows_the_source_and_the_newest_position(client: gport.Client) -> None:
    published = position(20_000, yaw_rate_dps=5.0)
    client.publish_vehicle(position=published)
    client.publish_vehicle(time=gport.VehicleTime(20_050, UTC_US))
    vehicle = client.status().vehicle
    assert vehicle is not None
    assert vehicle.source is not None and vehicle.source.pid == os.getpid()
    assert vehicle.source.uid == os.getuid()
    assert vehicle.position is not None
    # As published, but for the yaw rate, which status does not show.
    assert vehicle.position == dataclasses.replace(published, yaw_rate_dps=None)
    assert vehicle.position_age_ms is not None and vehicle.position_age_ms >= 0
    assert vehicle.utc_known and vehicle.time_age_ms is not None
    assert (vehicle.published, vehicle.refused, vehicle.resets) == (2, 0, 0)


def test_refused_values_name_the_field(client: gport.Client) -> None:
    with pytest.raises(gport.InvalidParams, match=r"position\.lat must be a number from -90"):
        client.publish_vehicle(position=position(1_000, lat=95.0))
    with pytest.raises(gport.InvalidParams, match=r"time\.utc_us"):
        client.publish_vehicle(time=gport.VehicleTime(1_000, 0))
    client.publish_vehicle(position=position(2_000))
    with pytest.raises(gport.InvalidParams, match="out of order"):
        client.publish_vehicle(position=position(2_000))
    vehicle = client.status().vehicle
    assert vehicle is not None and vehicle.refused == 3 and vehicle.published == 1


def test_wrong_types_are_refused_before_anything_is_sent(client: gport.Client) -> None:
    with pytest.raises(ValueError, match="needs position, time or both"):
        client.publish_vehicle()
    wrong: list[tuple[dict[str, Any], str]] = [
        ({"lat": "47"}, r"position\.lat must be a number, not str"),
        ({"lon": True}, r"position\.lon must be a number, not bool"),
        ({"alt_msl_m": float("nan")}, r"position\.alt_msl_m must be a finite number"),
        ({"satellites": 12.0}, r"position\.satellites must be an integer, not float"),
        ({"velocity_ned": (1.0, 2.0)}, r"position\.velocity_ned must be three numbers"),
        ({"velocity_ned": (1.0, 2.0, None)}, r"position\.velocity_ned\[2\] must be a number"),
        ({"fix": 3.0}, r"position\.fix must be an integer"),
    ]
    for members, message in wrong:
        with pytest.raises(ValueError, match=message):
            client.publish_vehicle(position=position(1_000, **members))
    with pytest.raises(ValueError, match=r"position\.boot_ms must be an integer, not float"):
        client.publish_vehicle(position=position(1.0))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match=r"time\.utc_us must be an integer"):
        client.publish_vehicle(time=gport.VehicleTime(1_000, "now"))  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="position must be a gport.VehiclePosition, not dict"):
        client.publish_vehicle(position={"lat": 47.0})  # type: ignore[arg-type]
    assert client.status().vehicle is None  # gportd saw none of them


def test_the_capture_notification_carries_the_vehicle(daemon: Daemon) -> None:
    with daemon.client() as watcher, daemon.client() as taker:
        assert link_up(taker)
        watcher.subscribe(["capture"])
        taker.publish_vehicle(position=position(1_000))
        taken = taker.photo().capture
        assert taken is not None
        event = watcher.next_notification("capture", timeout=5)
        assert isinstance(event, gport.Capture) and event.index == taken.index
        assert event.vehicle is not None and event.vehicle == taken.vehicle
        assert event.line_mono_us is not None and event.shutter_mono_us is not None


def test_async_publish_and_photo(daemon: Daemon) -> None:
    async def main() -> None:
        async with gport.AsyncClient(daemon.socket) as client:
            for _ in range(500):
                if (await client.status()).link.state == "up":
                    break
                await asyncio.sleep(0.02)
            await client.publish_vehicle(position=position(3_000, fix=1))
            photo = await client.photo()
            assert photo.capture is not None and photo.capture.vehicle is not None
            vehicle = photo.capture.vehicle
            assert not vehicle.tagged and "GPS_FIX_TYPE 1" in vehicle.why
            await client.publish_vehicle(position=position(3_100))
            photo = await client.photo()
            assert photo.capture is not None and photo.capture.vehicle is not None
            assert photo.capture.vehicle.tagged
            with pytest.raises(gport.InvalidParams, match=r"position\.lon"):
                await client.publish_vehicle(position=position(3_200, lon=200.0))
            with pytest.raises(ValueError, match="needs position, time or both"):
                await client.publish_vehicle()
            status = await client.status()
            assert status.vehicle is not None and status.vehicle.published == 2

    asyncio.run(main())


# ---- a fake daemon: older, or lying about the types ----------------------
CAPTURE: dict[str, Any] = {
    "index": 7,
    "kind": "photo",
    "utc_us": 1_795_944_030_191_281,
    "mono_us": 25_361_785_468,
    "line_mono_us": 25_361_786_440,
    "shutter_mono_us": 25_361_786_440,
    "vehicle": {
        "tagged": True,
        "utc_us": UTC_US,
        "lat": 47.00001813,
        "lon": 8.0,
        "alt_msl_m": 500.0,
        "alt_rel_m": None,
        "velocity_ned": [10.0, 0.0, 0.0],
        "heading_deg": None,
        "h_acc_m": None,
        "v_acc_m": None,
        "fix": 3,
        "satellites": None,
        "age_ms": 201,
    },
}
STATUS: dict[str, Any] = {
    "api_version": 1,
    "daemon_version": "0.1.0",
    "link": {"state": "up", "reason": ""},
    "vehicle": {
        "source": {"id": 1, "pid": 42, "uid": 0, "gid": 0},
        "position": {
            "boot_ms": 1000,
            "lat": 47.0,
            "lon": 8.0,
            "alt_msl_m": 500.0,
            "alt_rel_m": None,
            "velocity_ned": [10.0, 0.0, 0.0],
            "heading_deg": None,
            "fix": 3,
            "h_acc_m": None,
            "v_acc_m": None,
            "satellites": None,
        },
        "position_age_ms": 201,
        "utc_known": True,
        "time_age_ms": 201,
        "published": 1,
        "refused": 0,
        "resets": 0,
    },
}


def changed(base: dict[str, Any], path: str, value: Any) -> dict[str, Any]:
    """A deep copy of ``base`` with the member at ``path`` (dotted) set."""
    copy: dict[str, Any] = json.loads(json.dumps(base))
    *parents, last = path.split(".")
    node = copy
    for name in parents:
        node = node[name]
    node[last] = value
    return copy


def answering(results: dict[str, Any], notification: Any = None) -> Callable[[Hostile, Any], None]:
    """A script answering each method with its result (``results``), and
    sending ``notification`` (a capture's params) after a subscribe."""

    def script(peer: Hostile, request: Any) -> None:
        subscribed = {"topics": ["capture"], "max_rate_hz": None}
        peer.reply(request, {"subscribe": subscribed, **results}.get(request["method"], {}))
        if request["method"] == "subscribe" and notification is not None:
            peer.line({"jsonrpc": "2.0", "method": "capture", "params": notification})

    return script


@pytest.fixture
def fake() -> Iterator[Callable[..., Hostile]]:
    servers: list[Hostile] = []

    def start(script: Callable[[Hostile, Any], None]) -> Hostile:
        servers.append(Hostile(script))
        return servers[-1]

    yield start
    for server in servers:
        server.close()


def test_an_older_gportd_without_the_members_still_parses(fake: Callable[..., Hostile]) -> None:
    new = ("line_mono_us", "shutter_mono_us", "vehicle")
    older = {k: v for k, v in CAPTURE.items() if k not in new}
    status = {k: v for k, v in STATUS.items() if k != "vehicle"}
    results = {
        "photo": {"sent": True, "capture": older},
        "captures": {"captures": [older], "next": 8},
        "status": status,
    }
    server = fake(answering(results, older))
    with gport.Client(server.path, timeout=PATIENT) as client:
        capture = client.photo().capture
        assert capture is not None and capture.vehicle is None and capture.line_mono_us is None
        assert client.captures().captures[0].shutter_mono_us is None
        assert client.status().vehicle is None
        client.subscribe("capture")
        event = client.next_notification("capture", timeout=PATIENT)
        assert isinstance(event, gport.Capture) and event.vehicle is None


def test_what_gportd_sends_parses(fake: Callable[..., Hostile]) -> None:
    why = "no position published yet"
    untagged = changed(CAPTURE, "vehicle", {"tagged": False, "utc_us": None, "why": why})
    results = {
        "photo": {"sent": True, "capture": CAPTURE},
        "captures": {"captures": [untagged], "next": 8},
        "status": STATUS,
    }
    server = fake(answering(results))
    with gport.Client(server.path, timeout=PATIENT) as client:
        capture = client.photo().capture
        assert capture is not None and capture.line_mono_us == 25_361_786_440
        assert capture.vehicle == gport.CaptureVehicle(
            tagged=True,
            utc_us=UTC_US,
            lat=47.00001813,
            lon=8.0,
            alt_msl_m=500.0,
            velocity_ned=(10.0, 0.0, 0.0),
            fix=3,
            age_ms=201,
        )
        listed = client.captures().captures[0]
        assert listed.vehicle == gport.CaptureVehicle(False, why=why)
        vehicle = client.status().vehicle
        assert vehicle == gport.VehicleStatus(
            source=gport.Peer(1, 42, 0, 0),
            position=gport.VehiclePosition(1000, 47.0, 8.0, 500.0, (10.0, 0.0, 0.0), fix=3),
            position_age_ms=201,
            utc_known=True,
            time_age_ms=201,
            published=1,
        )


# (where, the lie, the member the error names)
CAPTURE_LIES = [
    ("vehicle", "tagged", "vehicle must be an object, not str"),
    ("vehicle", {"lat": 47.0}, "vehicle.tagged must be true or false, not null"),
    ("vehicle.tagged", 1, "vehicle.tagged must be true or false, not int"),
    ("vehicle.lat", "47.0", "vehicle.lat must be a number, not str"),
    ("vehicle.velocity_ned", [10.0, 0.0], "vehicle.velocity_ned must be three numbers"),
    ("vehicle.velocity_ned", [10.0, 0.0, "x"], "vehicle.velocity_ned[2] must be a number"),
    ("vehicle.age_ms", 2.5, "vehicle.age_ms must be an integer, not float"),
    ("vehicle.why", 3, "vehicle.why must be a string, not int"),
    ("line_mono_us", "soon", "line_mono_us must be an integer, not str"),
    ("shutter_mono_us", [], "shutter_mono_us must be an integer, not list"),
]
STATUS_LIES = [
    ("vehicle", [], "vehicle must be an object, not list"),
    ("vehicle.source", 5, "vehicle.source must be an object, not int"),
    ("vehicle.position.lat", None, "vehicle.position.lat must be a number, not null"),
    ("vehicle.position.velocity_ned", {}, "vehicle.position.velocity_ned must be three numbers"),
    ("vehicle.utc_known", "yes", "vehicle.utc_known must be true or false, not str"),
    ("vehicle.published", 1.0, "vehicle.published must be an integer, not float"),
]


@pytest.mark.parametrize("where,lie,named", CAPTURE_LIES)
def test_a_capture_that_lies_is_a_clear_error(
    fake: Callable[..., Hostile], where: str, lie: Any, named: str
) -> None:
    bad = changed(CAPTURE, where, lie)
    results = {"photo": {"sent": True, "capture": bad}, "captures": {"captures": [bad], "next": 8}}
    server = fake(answering(results, bad))
    with gport.Client(server.path, timeout=PATIENT) as client:
        calls: list[tuple[str, Callable[[], object]]] = [
            ("photo", client.photo),
            ("captures", client.captures),
        ]
        for method, call in calls:
            with pytest.raises(gport.GportError) as raised:
                call()
            message = raised.value.message
            assert f"a {method} result this client cannot read" in message and named in message
            assert raised.value.code is None and client.connected  # the line itself was sound
        client.subscribe("capture")  # a notification has no caller: the connection ends
        with pytest.raises(gport.ConnectionLost) as lost:
            client.next_notification("capture", timeout=PATIENT)
        assert "a capture notification this client cannot read" in lost.value.message
        assert named in lost.value.message
        assert not client.connected


@pytest.mark.parametrize("where,lie,named", STATUS_LIES)
def test_a_status_that_lies_is_a_clear_error(
    fake: Callable[..., Hostile], where: str, lie: Any, named: str
) -> None:
    server = fake(answering({"status": changed(STATUS, where, lie)}))
    with gport.Client(server.path, timeout=PATIENT) as client:
        with pytest.raises(gport.GportError, match="a status result this client cannot") as raised:
            client.status()
        assert named in raised.value.message and client.connected


def test_async_a_capture_that_lies_is_a_clear_error(fake: Callable[..., Hostile]) -> None:
    bad = changed(CAPTURE, "vehicle.lon", "8")
    server = fake(answering({"photo": {"sent": True, "capture": bad}}, bad))

    async def main() -> None:
        async with gport.AsyncClient(server.path, timeout=PATIENT) as client:
            with pytest.raises(gport.GportError, match=r"a photo result .*vehicle\.lon must be"):
                await client.photo()
            assert client.connected
            await client.subscribe("capture")
            with pytest.raises(gport.ConnectionLost, match=r"capture notification .*vehicle\.lon"):
                await client.next_notification("capture", timeout=PATIENT)

    asyncio.run(main())
