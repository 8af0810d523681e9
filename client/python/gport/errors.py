"""Exceptions raised by the gport clients.

Every error is a :class:`GportError` with ``code`` (the JSON-RPC error code,
or ``None`` for errors of the client side: lost connection, timeout) and
``message`` (the daemon's text, which names what was wrong and what is
allowed).

The codes are gportd's wire contract (contract/include/gport/contract/
errors.hpp in the source tree); tests/contract/check_python.py checks every
class below against it.
"""

from __future__ import annotations

from typing import Any, Mapping


class GportError(Exception):
    """Base class of every error the gport package raises."""

    code: int | None = None

    def __init__(self, message: str, code: int | None = None) -> None:
        super().__init__(message if code is None else f"{message} ({code})")
        self.message = message
        if code is not None:
            self.code = code


class ParseError(GportError):
    """-32700: the daemon could not parse a request line."""

    code = -32700


class InvalidRequest(GportError):
    """-32600: the request was not a valid JSON-RPC request."""

    code = -32600


class MethodNotFound(GportError):
    """-32601: the daemon has no such method."""

    code = -32601


class InvalidParams(GportError):
    """-32602: a parameter was missing, unknown or out of range."""

    code = -32602


class InternalError(GportError):
    """-32603: a bug in the daemon."""

    code = -32603


class LinkDown(GportError):
    """-32000: the serial device is not open (``attitude``: no sample yet)."""

    code = -32000


class PermissionDenied(GportError):
    """-32001: this peer may only read (``access.control_uids/gids``), or may
    not publish the vehicle's state (``access.vehicle_uids``)."""

    code = -32001


class NotAnswering(GportError):
    """-32002: the gimbal did not answer a settings request."""

    code = -32002


class Busy(GportError):
    """-32003: another client holds control (or publishes the vehicle's state)."""

    code = -32003


class NoSlot(GportError):
    """-32004: the daemon refused or closed this connection (a limit)."""

    code = -32004


class TooManyRequests(GportError):
    """-32005: over the request rate or the settings queue; retry later."""

    code = -32005


class ConfigInvalid(GportError):
    """-32006: the daemon started by socket activation found its configuration
    invalid; ``message`` names the file and the key. Fix the file, then
    ``systemctl restart gportd`` (or ``reload``)."""

    code = -32006


class ConnectionLost(GportError):
    """The socket could not be opened, or the daemon closed it."""


class Timeout(GportError):
    """No reply within the client's timeout (the request may still be carried out)."""


_BY_CODE: dict[int, type[GportError]] = {
    cls.code: cls
    for cls in (
        ParseError,
        InvalidRequest,
        MethodNotFound,
        InvalidParams,
        InternalError,
        LinkDown,
        PermissionDenied,
        NotAnswering,
        Busy,
        NoSlot,
        TooManyRequests,
        ConfigInvalid,
    )
    if cls.code is not None
}


def error_from_reply(error: Mapping[str, Any]) -> GportError:
    """The exception for a JSON-RPC ``error`` member: its class follows the code."""
    code = error.get("code")
    message = str(error.get("message", "error without a message"))
    if not isinstance(code, int) or isinstance(code, bool):
        return GportError(message, None)
    return _BY_CODE.get(code, GportError)(message, code)


class BadChannel(GportError):
    """The shared-memory attitude channel's block failed its checks (or its
    reply carried no descriptor): ``message`` names what was wrong."""
