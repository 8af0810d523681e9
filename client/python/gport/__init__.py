"""gport: the Python client of gportd, the G-Port gimbal daemon.

Standard library only. ``gport.Client`` blocks; ``gport.AsyncClient`` is for
asyncio. Both speak gportd's JSON-RPC over its Unix socket (default
/run/gportd.sock, or $GPORT_SOCKET). See docs/client-python.md.

    import gport
    with gport.Client() as gimbal:
        gimbal.angle(pitch=-30, yaw=45, wait=True)
        gimbal.photo()
"""

from ._protocol import INBOX_BYTES, INBOX_LIMIT, LINE_LIMIT, NESTING_LIMIT, WAIT_ALLOWANCE
from .aio import AsyncClient
from .channel import AttitudeChannel
from .client import Client
from .errors import (
    BadChannel,
    Busy,
    ConnectionLost,
    GportError,
    InternalError,
    InvalidParams,
    InvalidRequest,
    LinkDown,
    MethodNotFound,
    NoSlot,
    NotAnswering,
    ParseError,
    PermissionDenied,
    Timeout,
    TooManyRequests,
    ConfigInvalid,
)
from .moving import AsyncMovement, Movement
from .results import (
    AngleResult,
    Attitude,
    Axes,
    Capture,
    CaptureAttitude,
    CaptureClient,
    Captures,
    CaptureVehicle,
    CenterResult,
    Control,
    Counters,
    Ended,
    ImuRates,
    Link,
    Me,
    Motion,
    MotionEvent,
    Notification,
    Peer,
    PhotoResult,
    Rates,
    RecordResult,
    Settings,
    SpeedResult,
    Status,
    Subscription,
    AxisRange,
    Limits,
    VehiclePosition,
    VehicleStatus,
    VehicleTime,
)

# The project's version (CMakeLists.txt project()); tests/python checks they agree.
__version__ = "0.1.0"

__all__ = [
    "INBOX_BYTES",
    "INBOX_LIMIT",
    "LINE_LIMIT",
    "NESTING_LIMIT",
    "WAIT_ALLOWANCE",
    "AngleResult",
    "AsyncClient",
    "AsyncMovement",
    "Attitude",
    "AttitudeChannel",
    "Axes",
    "BadChannel",
    "Busy",
    "Capture",
    "CaptureAttitude",
    "CaptureClient",
    "Captures",
    "CaptureVehicle",
    "CenterResult",
    "Client",
    "ConnectionLost",
    "Control",
    "Counters",
    "Ended",
    "GportError",
    "ImuRates",
    "InternalError",
    "InvalidParams",
    "InvalidRequest",
    "Link",
    "LinkDown",
    "Me",
    "MethodNotFound",
    "Motion",
    "MotionEvent",
    "Movement",
    "NoSlot",
    "NotAnswering",
    "Notification",
    "ParseError",
    "Peer",
    "PermissionDenied",
    "PhotoResult",
    "Rates",
    "RecordResult",
    "Settings",
    "AxisRange",
    "Limits",
    "SpeedResult",
    "Status",
    "Subscription",
    "Timeout",
    "TooManyRequests",
    "ConfigInvalid",
    "VehiclePosition",
    "VehicleStatus",
    "VehicleTime",
]
