"""The sans-I/O core of gport.Client and gport.AsyncClient: what each method
sends and how its result is read (a Call), what a client subscribed to
(Subscriptions), and next_notification() but for its wait. None of it
touches a socket or a loop: the clients carry a Call out, the sync one
blocking, the async one awaiting, so every method of both is one line over
the same Call."""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Any, Callable, Generic, Iterable, Mapping, TypeVar

from . import _checks as check
from . import _protocol as p
from . import results as r
from .errors import ConnectionLost, GportError, Timeout

T = TypeVar("T")


def _nothing(result: Any) -> None:
    """For methods whose result says nothing (stop, lock)."""


@dataclass(frozen=True)
class Call(Generic[T]):
    """One request: the method, its params (None: none sent), how its
    result is read, and whether its reply waits for the motion's end."""

    method: str
    params: Mapping[str, Any] | None
    parse: Callable[[Any], T]
    wait: bool = False

    def limit(self, timeout: float | None) -> float | None:
        """Seconds to wait for the reply: the client's ``timeout``, plus
        WAIT_ALLOWANCE with wait=True; None: no limit."""
        return p.reply_limit(timeout, self.wait)

    def read(self, result: Any) -> T:
        """The result, parsed. One this client cannot read (a member missing
        or of the wrong type) raises GportError naming the method and why;
        the connection stays (the line itself was sound)."""
        try:
            return self.parse(result)
        except (KeyError, TypeError, ValueError, AttributeError, OverflowError) as error:
            raise GportError(
                f"the daemon sent a {self.method} result this client cannot read "
                f"({p.short(repr(error))})"
            ) from None


# The methods without params.
STATUS: Call[r.Status] = Call("status", None, r.parse_status)
ATTITUDE: Call[r.Attitude] = Call("attitude", None, r.parse_attitude)
STOP: Call[None] = Call("stop", None, _nothing)
LOCK: Call[None] = Call("lock", None, _nothing)
ACQUIRE: Call[r.Control] = Call("acquire", None, r.parse_control)
RELEASE: Call[r.Control] = Call("release", None, r.parse_control)
LIMITS: Call[r.Limits] = Call("limits", None, r.parse_limits)
SETTINGS: Call[r.Settings] = Call("get_settings", None, r.parse_settings)


def speed(
    roll: float,
    pitch: float,
    yaw: float,
    duration_ms: int | None,
    lease_ms: int | None,
    clamp: bool,
) -> Call[r.SpeedResult]:
    """Also what a moving() block re-sends (Movement)."""
    params = p.drop_none(
        roll=roll,
        pitch=pitch,
        yaw=yaw,
        duration_ms=duration_ms,
        lease_ms=lease_ms,
        clamp=True if clamp else None,
    )
    return Call("speed", params, r.parse_speed)


def angle(roll: float, pitch: float, yaw: float, clamp: bool, wait: bool) -> Call[r.AngleResult]:
    # `wait` is sent only when true, so that daemons without it still answer.
    params = p.drop_none(
        roll=roll, pitch=pitch, yaw=yaw, clamp=True if clamp else None, wait=True if wait else None
    )
    return Call("angle", params, r.parse_angle, wait)


def center(wait: bool) -> Call[r.CenterResult]:
    return Call("center", {"wait": True} if wait else None, r.parse_center, wait)


def photo(meta: Mapping[str, Any] | None) -> Call[r.PhotoResult]:
    return Call("photo", _with_meta({}, meta) or None, r.parse_photo)


def record(on: bool | None, force: bool, meta: Mapping[str, Any] | None) -> Call[r.RecordResult]:
    if force and on is None:
        raise ValueError("record(force=True) needs on=True or on=False")
    params = p.drop_none(on=on, force=True if force else None)
    return Call("record", _with_meta(params, meta), r.parse_record)


def _with_meta(params: dict[str, Any], meta: Mapping[str, Any] | None) -> dict[str, Any]:
    """``params`` with ``meta`` for photo and record (docs/api.md, "Captures"):
    a mapping, sent as a JSON object; gportd refuses one over 1024 bytes as
    compact JSON with InvalidParams. Anything else raises ValueError here."""
    if meta is None:
        return params
    if not isinstance(meta, Mapping):
        raise ValueError(f"meta must be a mapping (a JSON object), not {type(meta).__name__}")
    return {**params, "meta": dict(meta)}


def captures(since: int | None, limit: int | None) -> Call[r.Captures]:
    return Call("captures", p.drop_none(since=since, limit=limit), r.parse_captures)


def publish_vehicle(position: r.VehiclePosition | None, when: r.VehicleTime | None) -> Call[None]:
    """The vehicle's state for gportd to stamp captures with (``when``: the
    ``time`` part). The types are checked here (ValueError naming the member
    before anything is sent), the ranges by gportd (InvalidParams)."""
    if position is None and when is None:
        raise ValueError("publish_vehicle needs position, time or both")
    params: dict[str, Any] = {}
    if position is not None:
        params["position"] = _position_json(position)
    if when is not None:
        if not isinstance(when, r.VehicleTime):
            raise ValueError(f"time must be a gport.VehicleTime, not {type(when).__name__}")
        params["time"] = {
            "boot_ms": check.integer(when.boot_ms, "time.boot_ms"),
            "utc_us": check.integer(when.utc_us, "time.utc_us"),
        }
    return Call("publish_vehicle", params, _nothing)


def _position_json(position: r.VehiclePosition) -> dict[str, Any]:
    if not isinstance(position, r.VehiclePosition):
        raise ValueError(f"position must be a gport.VehiclePosition, not {type(position).__name__}")

    def optional(name: str) -> float | None:
        return check.optional_number(getattr(position, name), f"position.{name}")

    return p.drop_none(
        boot_ms=check.integer(position.boot_ms, "position.boot_ms"),
        lat=check.number(position.lat, "position.lat"),
        lon=check.number(position.lon, "position.lon"),
        alt_msl_m=check.number(position.alt_msl_m, "position.alt_msl_m"),
        alt_rel_m=optional("alt_rel_m"),
        velocity_ned=list(check.triple(position.velocity_ned, "position.velocity_ned")),
        heading_deg=optional("heading_deg"),
        yaw_rate_dps=optional("yaw_rate_dps"),
        fix=check.optional_integer(position.fix, "position.fix"),
        h_acc_m=optional("h_acc_m"),
        v_acc_m=optional("v_acc_m"),
        satellites=check.optional_integer(position.satellites, "position.satellites"),
    )


def set_settings(
    dead_zone: int | None, follow_speed: int | None, inverted: bool | None
) -> Call[r.Settings]:
    params = p.drop_none(dead_zone=dead_zone, follow_speed=follow_speed, inverted=inverted)
    if not params:
        raise ValueError("set_settings needs at least one of dead_zone, follow_speed, inverted")
    return Call("set_settings", params, r.parse_settings)


def subscribe(topics: Iterable[str], max_rate_hz: float | None) -> Call[r.Subscription]:
    params = p.drop_none(topics=p.topic_list(topics), max_rate_hz=max_rate_hz)
    return Call("subscribe", params, r.parse_subscription)


def unsubscribe(topics: str | Iterable[str] | None) -> Call[r.Subscription]:
    params = None if topics is None else {"topics": p.topic_list(topics)}
    return Call("unsubscribe", params, r.parse_subscription)


class Subscriptions:
    """What a client subscribed to, so that reconnect() can subscribe again:
    each topic on the socket (attitude with its max_rate_hz), and whether
    attitude comes from the shared-memory channel instead."""

    def __init__(self) -> None:
        self.topics: dict[str, float | None] = {}
        self.shared_attitude = False

    @staticmethod
    def through_channel(wanted: list[str], shared_memory: bool) -> list[str] | None:
        """With attitude asked for over shared memory: the topics left for
        the socket (maybe none); else None (all go to the socket)."""
        if shared_memory and "attitude" in wanted:
            return [t for t in wanted if t != "attitude"]
        return None

    @staticmethod
    def with_channel(result: r.Subscription) -> r.Subscription:
        """The socket's subscription plus attitude from the channel."""
        return r.Subscription((*result.topics, "attitude"), None)

    def subscribed(
        self, wanted: list[str], max_rate_hz: float | None, result: r.Subscription
    ) -> None:
        for topic in result.topics:
            self.topics.setdefault(topic, None)
        if "attitude" in wanted:
            self.topics["attitude"] = max_rate_hz

    @staticmethod
    def ends_channel(topics: str | Iterable[str] | None) -> bool:
        """Whether unsubscribe(topics) ends the shared-memory attitude too."""
        return topics is None or "attitude" in p.topic_list(topics)

    def unsubscribed(
        self, topics: str | Iterable[str] | None, result: r.Subscription, inbox: p.Inbox
    ) -> None:
        """After unsubscribe(topics): what is left, and none of theirs waits."""
        self.topics = {t: self.topics.get(t) for t in result.topics}
        inbox.clear(None if topics is None else p.topic_list(topics))

    def again(self) -> list[tuple[list[str], float | None]]:
        """The subscribe calls (topics, max_rate_hz) that restore the socket's
        topics on a new connection: attitude with its rate first."""
        topics = dict(self.topics)
        calls: list[tuple[list[str], float | None]] = []
        if "attitude" in topics:
            calls.append((["attitude"], topics.pop("attitude")))
        if topics:
            calls.append((list(topics), None))
        return calls


class NextNotification:
    """next_notification() but for its wait: the topics wanted (None: all)
    and until when (None: no limit)."""

    def __init__(self, topics: Iterable[str] | None, timeout: float | None) -> None:
        self.wanted = None if topics is None else frozenset(p.topic_list(topics))
        self.deadline = None if timeout is None else time.monotonic() + timeout

    def take(
        self, inbox: p.Inbox, alive: bool, closed: Callable[[], str]
    ) -> r.Notification | None:
        """The oldest waiting notification wanted; ConnectionLost (closed()
        says why) once the connection is gone and none waits."""
        item = inbox.take(self.wanted)
        if item is None and not alive:
            raise ConnectionLost(closed())
        return item

    def left(self) -> float | None:
        """Seconds still to wait: None for no limit, 0 when the time is up."""
        return None if self.deadline is None else max(0.0, self.deadline - time.monotonic())


def streamed(item: r.Notification | None, timeout: float | None) -> r.Attitude:
    """attitude_stream()'s next sample: Timeout when none came in ``timeout``."""
    if item is None:
        raise Timeout(f"no attitude sample within {timeout} s")
    assert isinstance(item, r.Attitude)
    return item
