"""Typed results and notifications: frozen dataclasses built from the daemon's JSON.

Each ``parse_*`` function takes the decoded ``result`` (or notification
``params``) and returns the dataclass; members a newer daemon adds are kept
in ``raw`` where a type has it, so nothing is lost. Also here: what
``publish_vehicle`` takes (VehiclePosition, VehicleTime), the position being
what ``status`` shows of the newest one too.
"""

from __future__ import annotations

from dataclasses import dataclass, field, fields
from typing import Any, Mapping, Union

from . import _checks as check

Json = Mapping[str, Any]


@dataclass(frozen=True)
class Axes:
    """Roll, pitch and yaw: degrees (angles) or degrees per second (speeds)."""

    roll: float = 0.0
    pitch: float = 0.0
    yaw: float = 0.0


@dataclass(frozen=True)
class ImuRates:
    """The IMU's angular rates, x/y/z, in degrees per second."""

    x: float = 0.0
    y: float = 0.0
    z: float = 0.0


@dataclass(frozen=True)
class Rates:
    """Angular rates of a 24-byte attitude frame."""

    hall: Axes
    imu: ImuRates


@dataclass(frozen=True)
class Attitude:
    """One attitude sample (method ``attitude`` or notification ``attitude``)."""

    seq: int
    t: float  # receive time, seconds since the epoch
    imu: Axes
    hall: Axes
    rates: Rates | None = None
    age_ms: int | None = None  # only in the ``attitude`` method's result
    dropped: int | None = None  # notifications lost so far, when some were


@dataclass(frozen=True)
class Peer:
    """A connected client as the daemon identifies it (SO_PEERCRED)."""

    id: int
    pid: int
    uid: int
    gid: int


@dataclass(frozen=True)
class Me(Peer):
    """The calling client in ``status``, with its own notification drop count
    and whether it opened the shared-memory attitude channel."""

    dropped: int = 0
    attitude_channel: bool = False


@dataclass(frozen=True)
class Link:
    """The gimbal link: ``state`` is ``up``, ``stale`` or ``down``."""

    state: str
    reason: str


@dataclass(frozen=True)
class Counters:
    """The daemon's counters (``status.counters``); missing ones read 0."""

    frames_in: int = 0
    bytes_in: int = 0
    frames_out: int = 0
    bytes_out: int = 0
    attitude_frames: int = 0
    crc_errors: int = 0
    header_errors: int = 0
    garbage_bytes: int = 0
    resyncs: int = 0
    bad_messages: int = 0
    device_opens: int = 0
    device_failures: int = 0
    keepalive_frames: int = 0
    motion_updates: int = 0
    stops_sent: int = 0
    frames_replaced: int = 0
    frames_refused: int = 0
    settings_timeouts: int = 0
    dropped_notifications: int = 0


@dataclass(frozen=True)
class Motion:
    """The running motion (``status.motion``): speed, angle or centre."""

    mode: str
    owner: Peer | None
    speed: Axes | None = None  # speed motions
    time_left_ms: int | None = None  # speed motions
    target: Axes | None = None  # tracked angle and centre motions
    elapsed_ms: int | None = None


@dataclass(frozen=True)
class Status:
    """The ``status`` result."""

    api_version: int
    daemon_version: str
    link: Link
    device: str
    device_open: bool
    uptime_ms: int
    attitude_age_ms: int | None
    counters: Counters
    clients: int
    dropped_notifications: int
    motion: Motion | None
    controller: Peer | None
    recording: str  # assumed: on, off or unknown
    client: Me | None
    raw: Json = field(default_factory=dict, compare=False, repr=False)
    device_error: str | None = None  # closed: why the last open failed
    attitude_channel_clients: int = 0  # connected clients that opened the channel
    vehicle: VehicleStatus | None = None  # None: nothing published (or an older gportd)


@dataclass(frozen=True)
class SpeedResult:
    """The ``speed`` result: what was sent and until when."""

    duration_ms: int
    ends_at: float  # seconds since the epoch
    speed: Axes
    clamped: tuple[str, ...]


@dataclass(frozen=True)
class Ended:
    """How a waited-for angle or centre motion ended."""

    reason: str  # reached, stalled, timeout, replaced, stop, owner_gone, ...
    attitude: Attitude | None
    elapsed_ms: int
    detail: str = ""  # stalled: where the gimbal stopped ("stalled at pitch -90.00 ..."), else ""


@dataclass(frozen=True)
class AngleResult:
    """The ``angle`` result; ``ended`` is set when called with ``wait=True``."""

    sent: bool
    angle: Axes
    clamped: tuple[str, ...]
    ended: Ended | None = None


@dataclass(frozen=True)
class CenterResult:
    """The ``center`` result; ``ended`` is set when called with ``wait=True``.
    ``target`` is the centre aimed at: 0/0/0, or clamped into the soft limits
    where they exclude 0 (``clamped`` names those axes)."""

    sent: bool
    ended: Ended | None = None
    target: Axes = Axes(0.0, 0.0, 0.0)
    clamped: tuple[str, ...] = ()


@dataclass(frozen=True)
class CaptureAttitude:
    """The newest attitude when a capture was taken, and its age."""

    imu: Axes
    hall: Axes
    age_ms: int


@dataclass(frozen=True)
class CaptureClient:
    """Who asked for a capture: pid, uid and the process's name when known."""

    pid: int
    uid: int
    name: str | None = None


@dataclass(frozen=True)
class VehiclePosition:
    """A position of the vehicle at the autopilot's boot time ``boot_ms``
    (MAVLink time_boot_ms): what ``publish_vehicle`` sends, and the newest
    one taken in ``status().vehicle``. Degrees (WGS84), metres, m/s;
    ``heading_deg`` 0 to 360, ``yaw_rate_dps`` clockwise seen from above
    (``status`` does not show it), ``fix`` MAVLink's GPS_FIX_TYPE,
    ``h_acc_m``/``v_acc_m`` 1-sigma. None: not known (not sent)."""

    boot_ms: int
    lat: float
    lon: float
    alt_msl_m: float
    velocity_ned: tuple[float, float, float]  # north, east, down
    alt_rel_m: float | None = None
    heading_deg: float | None = None
    yaw_rate_dps: float | None = None
    fix: int | None = None
    h_acc_m: float | None = None
    v_acc_m: float | None = None
    satellites: int | None = None


@dataclass(frozen=True)
class VehicleTime:
    """The autopilot's UTC (MAVLink SYSTEM_TIME) at its boot time ``boot_ms``:
    ``utc_us`` is time_unix_usec (gportd refuses 0, sent before GPS time)."""

    boot_ms: int
    utc_us: int


@dataclass(frozen=True)
class CaptureVehicle:
    """The vehicle at a capture's instant, as gportd stamped it: ``tagged``
    with the newest position carried to the instant by its velocity
    (``age_ms`` old there; the accuracies grown by that age), or untagged
    and ``why``. ``utc_us``: the autopilot's UTC at the instant (None: no
    time published). The position's members are None when untagged."""

    tagged: bool
    why: str = ""  # untagged: why ("no 3D GPS fix (GPS_FIX_TYPE 1)", ...)
    utc_us: int | None = None
    lat: float | None = None
    lon: float | None = None
    alt_msl_m: float | None = None
    alt_rel_m: float | None = None
    velocity_ned: tuple[float, float, float] | None = None
    heading_deg: float | None = None
    h_acc_m: float | None = None
    v_acc_m: float | None = None
    fix: int | None = None
    satellites: int | None = None
    age_ms: int | None = None


@dataclass(frozen=True)
class VehicleStatus:
    """``status().vehicle``: who publishes the vehicle's state (None: no
    source now), the newest position taken and its age, whether the
    autopilot's UTC is known and how old its newest time is, and the
    reports published, refused and the autopilot's reboots seen."""

    source: Peer | None = None
    position: VehiclePosition | None = None
    position_age_ms: int | None = None
    utc_known: bool = False
    time_age_ms: int | None = None
    published: int = 0
    refused: int = 0
    resets: int = 0


@dataclass(frozen=True)
class Capture:
    """A photo or record toggle that reached the wire, as gportd's capture log
    keeps it (docs/api.md, "Captures"). The ``photo`` and ``record`` replies
    carry ``index``, ``kind``, ``utc_us``, ``attitude`` and ``vehicle`` only;
    ``captures()`` and the ``capture`` notification carry everything."""

    index: int
    kind: str  # photo, record_start, record_stop or record_toggle
    utc_us: int | None = None  # wall clock, microseconds since the epoch
    mono_us: int | None = None  # CLOCK_MONOTONIC, microseconds
    attitude: CaptureAttitude | None = None  # None before the first sample
    client: CaptureClient | None = None
    meta: Json | None = None  # the ``meta`` object sent with the command
    raw: Json = field(default_factory=dict, compare=False, repr=False)
    # When the frame's last byte was due on the line, and that plus
    # camera.shutter_delay_ms: the instant stamped (clock of mono_us).
    line_mono_us: int | None = None
    shutter_mono_us: int | None = None
    vehicle: CaptureVehicle | None = None  # None: nothing ever published the vehicle


@dataclass(frozen=True)
class Captures:
    """The ``captures`` result: the kept captures asked for, oldest first,
    ``next``, the ``since`` that asks for the following ones, and ``more``:
    whether captures at or after ``next`` are kept (a page is bounded by
    ``limit`` and by 64 KiB; ask again from ``next`` while ``more``)."""

    captures: tuple[Capture, ...]
    next: int
    more: bool = False


@dataclass(frozen=True)
class PhotoResult:
    """The ``photo`` result; ``capture`` is None from a gportd without the log."""

    sent: bool
    capture: Capture | None = None


@dataclass(frozen=True)
class RecordResult:
    """The ``record`` result: whether a toggle was sent, the assumed state
    after, and the capture it made (when sent; not compared)."""

    sent: bool
    recording: str
    capture: Capture | None = field(default=None, compare=False)


@dataclass(frozen=True)
class Control:
    """The ``acquire`` / ``release`` result."""

    controller: Peer | None
    you_hold_control: bool


@dataclass(frozen=True)
class Settings:
    """The gimbal's settings (``get_settings`` / ``set_settings``)."""

    dead_zone: int
    follow_speed: int
    inverted: bool


@dataclass(frozen=True)
class AxisRange:
    """One axis's soft limit in degrees (``limits``)."""

    min: float
    max: float


@dataclass(frozen=True)
class Limits:
    """gportd's configured soft limits (the ``limits`` method)."""

    roll: AxisRange
    pitch: AxisRange
    yaw: AxisRange
    max_speed: float
    braking_margin_deg: float


@dataclass(frozen=True)
class Subscription:
    """The topics now subscribed and the attitude rate cap."""

    topics: tuple[str, ...]
    max_rate_hz: float | None


@dataclass(frozen=True)
class MotionEvent:
    """A ``motion`` notification: started, replaced, updated or ended."""

    change: str
    mode: str
    owner: Peer | None
    speed: Axes | None = None
    duration_ms: int | None = None
    angle: Axes | None = None
    target: Axes | None = None
    reason: str | None = None  # for ``ended`` (and ``updated`` when braked)
    braked: tuple[str, ...] = ()
    raw: Json = field(default_factory=dict, compare=False, repr=False)


Notification = Union[Attitude, Link, MotionEvent, Capture]


def _axes(raw: Json | None) -> Axes | None:
    if raw is None:
        return None
    return Axes(float(raw.get("roll", 0)), float(raw.get("pitch", 0)), float(raw.get("yaw", 0)))


def _axes_required(raw: Json) -> Axes:
    return Axes(float(raw.get("roll", 0)), float(raw.get("pitch", 0)), float(raw.get("yaw", 0)))


def _peer(raw: Json | None) -> Peer | None:
    if raw is None:
        return None
    return Peer(int(raw["id"]), int(raw["pid"]), int(raw["uid"]), int(raw["gid"]))


def _optional_int(value: Any) -> int | None:
    return None if value is None else int(value)


def _optional_str(value: Any) -> str | None:
    return None if value is None else str(value)


def parse_attitude(raw: Json) -> Attitude:
    rates = raw.get("rates")
    parsed_rates = None
    if rates is not None:
        imu = rates.get("imu", {})
        parsed_rates = Rates(
            _axes_required(rates.get("hall", {})),
            ImuRates(float(imu.get("x", 0)), float(imu.get("y", 0)), float(imu.get("z", 0))),
        )
    return Attitude(
        seq=int(raw["seq"]),
        t=float(raw["t"]),
        imu=_axes_required(raw["imu"]),
        hall=_axes_required(raw["hall"]),
        rates=parsed_rates,
        age_ms=_optional_int(raw.get("age_ms")),
        dropped=_optional_int(raw.get("dropped")),
    )


def parse_link(raw: Json) -> Link:
    return Link(str(raw["state"]), str(raw.get("reason", "")))


def _motion(raw: Json | None) -> Motion | None:
    if raw is None:
        return None
    return Motion(
        mode=str(raw["mode"]),
        owner=_peer(raw.get("owner")),
        speed=_axes(raw.get("speed")),
        time_left_ms=_optional_int(raw.get("time_left_ms")),
        target=_axes(raw.get("target")),
        elapsed_ms=_optional_int(raw.get("elapsed_ms")),
    )


def _counters(raw: Json) -> Counters:
    values = {f.name: int(raw.get(f.name, 0)) for f in fields(Counters)}
    return Counters(**values)


def _me(raw: Json | None) -> Me | None:
    if raw is None:
        return None
    peer = _peer(raw)
    assert peer is not None
    return Me(
        peer.id,
        peer.pid,
        peer.uid,
        peer.gid,
        int(raw.get("dropped", 0)),
        bool(raw.get("attitude_channel", False)),
    )


def parse_status(raw: Json) -> Status:
    return Status(
        api_version=int(raw["api_version"]),
        daemon_version=str(raw["daemon_version"]),
        link=parse_link(raw["link"]),
        device=str(raw.get("device", "")),
        device_open=bool(raw.get("device_open", False)),
        uptime_ms=int(raw.get("uptime_ms", 0)),
        attitude_age_ms=_optional_int(raw.get("attitude_age_ms")),
        counters=_counters(raw.get("counters", {})),
        clients=int(raw.get("clients", 0)),
        dropped_notifications=int(raw.get("dropped_notifications", 0)),
        motion=_motion(raw.get("motion")),
        controller=_peer(raw.get("controller")),
        recording=str(raw.get("recording", "unknown")),
        client=_me(raw.get("client")),
        raw=raw,
        device_error=_optional_str(raw.get("device_error")),
        attitude_channel_clients=int(raw.get("attitude_channel_clients", 0)),
        vehicle=_vehicle_status(raw.get("vehicle")),
    )


def _vehicle_position(raw: Any, where: str) -> VehiclePosition | None:
    if raw is None:
        return None
    position = check.mapping(raw, where)

    def number(name: str) -> float:
        return check.number(position.get(name), f"{where}.{name}")

    def optional(name: str) -> float | None:
        return check.optional_number(position.get(name), f"{where}.{name}")

    return VehiclePosition(
        boot_ms=check.integer(position.get("boot_ms"), f"{where}.boot_ms"),
        lat=number("lat"),
        lon=number("lon"),
        alt_msl_m=number("alt_msl_m"),
        velocity_ned=check.triple(position.get("velocity_ned"), f"{where}.velocity_ned"),
        alt_rel_m=optional("alt_rel_m"),
        heading_deg=optional("heading_deg"),
        yaw_rate_dps=optional("yaw_rate_dps"),
        fix=check.optional_integer(position.get("fix"), f"{where}.fix"),
        h_acc_m=optional("h_acc_m"),
        v_acc_m=optional("v_acc_m"),
        satellites=check.optional_integer(position.get("satellites"), f"{where}.satellites"),
    )


def _vehicle_status(raw: Any) -> VehicleStatus | None:
    if raw is None:
        return None
    vehicle = check.mapping(raw, "vehicle")
    source = vehicle.get("source")

    def count(name: str) -> int:
        return check.integer(vehicle.get(name, 0), f"vehicle.{name}")

    def age(name: str) -> int | None:
        return check.optional_integer(vehicle.get(name), f"vehicle.{name}")

    return VehicleStatus(
        source=None if source is None else _peer(check.mapping(source, "vehicle.source")),
        position=_vehicle_position(vehicle.get("position"), "vehicle.position"),
        position_age_ms=age("position_age_ms"),
        utc_known=check.flag(vehicle.get("utc_known", False), "vehicle.utc_known"),
        time_age_ms=age("time_age_ms"),
        published=count("published"),
        refused=count("refused"),
        resets=count("resets"),
    )


def parse_speed(raw: Json) -> SpeedResult:
    return SpeedResult(
        duration_ms=int(raw["duration_ms"]),
        ends_at=float(raw["ends_at"]),
        speed=_axes_required(raw["speed"]),
        clamped=tuple(str(a) for a in raw.get("clamped", [])),
    )


def _ended(raw: Json | None) -> Ended | None:
    if raw is None:
        return None
    sample = raw.get("attitude")
    return Ended(
        reason=str(raw["reason"]),
        attitude=None if sample is None else parse_attitude(sample),
        elapsed_ms=int(raw.get("elapsed_ms", 0)),
        detail=str(raw.get("detail", "")),
    )


def parse_angle(raw: Json) -> AngleResult:
    return AngleResult(
        sent=bool(raw.get("sent", True)),
        angle=_axes_required(raw["angle"]),
        clamped=tuple(str(a) for a in raw.get("clamped", [])),
        ended=_ended(raw.get("ended")),
    )


def parse_center(raw: Json) -> CenterResult:
    target = raw.get("target")
    return CenterResult(
        sent=bool(raw.get("sent", True)),
        ended=_ended(raw.get("ended")),
        target=_axes_required(target) if target is not None else Axes(0.0, 0.0, 0.0),
        clamped=tuple(str(a) for a in raw.get("clamped", [])),
    )


def parse_record(raw: Json) -> RecordResult:
    return RecordResult(
        sent=bool(raw["sent"]),
        recording=str(raw["recording"]),
        capture=_capture(raw.get("capture")),
    )


def parse_photo(raw: Json | None) -> PhotoResult:
    # A gportd without the capture log answers an empty result.
    if not isinstance(raw, Mapping):
        return PhotoResult(sent=True)
    return PhotoResult(sent=bool(raw.get("sent", True)), capture=_capture(raw.get("capture")))


def parse_capture(raw: Json) -> Capture:
    attitude, client, meta = raw.get("attitude"), raw.get("client"), raw.get("meta")
    return Capture(
        index=int(raw["index"]),
        kind=str(raw["kind"]),
        utc_us=_optional_int(raw.get("utc_us")),
        mono_us=_optional_int(raw.get("mono_us")),
        attitude=None
        if attitude is None
        else CaptureAttitude(
            _axes_required(attitude["imu"]),
            _axes_required(attitude["hall"]),
            int(attitude.get("age_ms", 0)),
        ),
        client=None
        if client is None
        else CaptureClient(int(client["pid"]), int(client["uid"]), _optional_str(client.get("name"))),
        meta=None if meta is None else dict(meta),
        raw=raw,
        line_mono_us=check.optional_integer(raw.get("line_mono_us"), "line_mono_us"),
        shutter_mono_us=check.optional_integer(raw.get("shutter_mono_us"), "shutter_mono_us"),
        vehicle=_capture_vehicle(raw.get("vehicle")),
    )


def _capture_vehicle(raw: Any) -> CaptureVehicle | None:
    """A capture's ``vehicle``: null, or an object with ``tagged``; every
    other member may be missing (None)."""
    if raw is None:
        return None
    vehicle = check.mapping(raw, "vehicle")

    def optional(name: str) -> float | None:
        return check.optional_number(vehicle.get(name), f"vehicle.{name}")

    def optional_integer(name: str) -> int | None:
        return check.optional_integer(vehicle.get(name), f"vehicle.{name}")

    why, velocity = vehicle.get("why"), vehicle.get("velocity_ned")
    return CaptureVehicle(
        tagged=check.flag(vehicle.get("tagged"), "vehicle.tagged"),
        why="" if why is None else check.text(why, "vehicle.why"),
        utc_us=optional_integer("utc_us"),
        lat=optional("lat"),
        lon=optional("lon"),
        alt_msl_m=optional("alt_msl_m"),
        alt_rel_m=optional("alt_rel_m"),
        velocity_ned=None if velocity is None else check.triple(velocity, "vehicle.velocity_ned"),
        heading_deg=optional("heading_deg"),
        h_acc_m=optional("h_acc_m"),
        v_acc_m=optional("v_acc_m"),
        fix=optional_integer("fix"),
        satellites=optional_integer("satellites"),
        age_ms=optional_integer("age_ms"),
    )


def _capture(raw: Json | None) -> Capture | None:
    return None if raw is None else parse_capture(raw)


def parse_captures(raw: Json) -> Captures:
    return Captures(
        tuple(parse_capture(c) for c in raw["captures"]), int(raw["next"]), bool(raw.get("more", False))
    )


def parse_control(raw: Json) -> Control:
    return Control(_peer(raw.get("controller")), bool(raw["you_hold_control"]))


def parse_settings(raw: Json) -> Settings:
    return Settings(int(raw["dead_zone"]), int(raw["follow_speed"]), bool(raw["inverted"]))


def parse_limits(raw: Json) -> Limits:
    def axis(name: str) -> AxisRange:
        return AxisRange(float(raw[name]["min"]), float(raw[name]["max"]))

    return Limits(
        axis("roll"),
        axis("pitch"),
        axis("yaw"),
        float(raw["max_speed"]),
        float(raw["braking_margin_deg"]),
    )


def parse_subscription(raw: Json) -> Subscription:
    rate = raw.get("max_rate_hz")
    return Subscription(tuple(str(t) for t in raw["topics"]), None if rate is None else float(rate))


def parse_motion_event(raw: Json) -> MotionEvent:
    return MotionEvent(
        change=str(raw["change"]),
        mode=str(raw["mode"]),
        owner=_peer(raw.get("owner")),
        speed=_axes(raw.get("speed")),
        duration_ms=_optional_int(raw.get("duration_ms")),
        angle=_axes(raw.get("angle")),
        target=_axes(raw.get("target")),
        reason=None if raw.get("reason") is None else str(raw["reason"]),
        braked=tuple(str(a) for a in raw.get("braked", [])),
        raw=raw,
    )


def parse_notification(method: str, params: Json) -> Notification | None:
    """The typed notification, or None for a topic this version does not know."""
    if method == "attitude":
        return parse_attitude(params)
    if method == "link":
        return parse_link(params)
    if method == "motion":
        return parse_motion_event(params)
    if method == "capture":
        return parse_capture(params)
    return None
