"""Typed exceptions for the gRPC status codes the CulinaryCut server returns."""
from __future__ import annotations

import grpc


class CulinaryCutError(Exception):
    """A failed RPC: `.code` is the grpc.StatusCode, `.details` the server's message and, for bad input,
    `.field` the path of the field at fault (e.g. "scene.objects[0].scale"; "" when none is named)."""

    code: grpc.StatusCode = grpc.StatusCode.UNKNOWN

    def __init__(self, details: str = "", code: grpc.StatusCode | None = None, field: str = ""):
        if code is not None:
            self.code = code
        self.details = details
        self.field = field
        super().__init__(f"{self.code.name}: {details}")


class InvalidArgument(CulinaryCutError):
    code = grpc.StatusCode.INVALID_ARGUMENT


class NotFound(CulinaryCutError):
    code = grpc.StatusCode.NOT_FOUND


class FailedPrecondition(CulinaryCutError):
    code = grpc.StatusCode.FAILED_PRECONDITION


class ResourceExhausted(CulinaryCutError):
    code = grpc.StatusCode.RESOURCE_EXHAUSTED


class Unimplemented(CulinaryCutError):
    code = grpc.StatusCode.UNIMPLEMENTED


class Unavailable(CulinaryCutError):
    """The server could not be reached (not running, wrong address, or shutting down)."""

    code = grpc.StatusCode.UNAVAILABLE


class Unauthenticated(CulinaryCutError):
    """The server wants a bearer token (or another one): pass Client(token=...) or set CULINARYCUT_TOKEN."""

    code = grpc.StatusCode.UNAUTHENTICATED


class DeadlineExceeded(CulinaryCutError):
    code = grpc.StatusCode.DEADLINE_EXCEEDED


class Internal(CulinaryCutError):
    """The engine failed inside a call (e.g. a runaway MPM state); the message says how to recover."""

    code = grpc.StatusCode.INTERNAL


_BY_CODE = {
    cls.code: cls
    for cls in (InvalidArgument, NotFound, FailedPrecondition, ResourceExhausted, Unimplemented,
                Unavailable, Unauthenticated, DeadlineExceeded, Internal)
}


# The trailing metadata in which the server names the field of an INVALID_ARGUMENT (a structured detail).
FIELD_METADATA_KEY = "culinarycut-field"

# gRPC answers a request it cannot decode itself, before the server's code sees it, with INTERNAL and no
# message: said here, so that a client's bug does not read as an engine failure.
UNDECODABLE_REQUEST = ("the server could not decode the request (gRPC answered INTERNAL with no message): it is "
                       "not a valid culinarycut.v1 message, e.g. a string field that is not UTF-8; the request was "
                       "not applied, and this is a fault in what the client sent, not in the engine")

# A TCP connection the server closed as soon as it was made: it was at its connection caps, or stopping.
CLOSED_CONNECTION_HINT = ("; the server closed the connection: it may be at its connection caps "
                          "(--max-connections, --max-connections-per-address; docs/protocol.md) or shutting down")


def from_rpc_error(err: grpc.RpcError) -> CulinaryCutError:
    """Map a grpc.RpcError (a grpc.Call) to the matching CulinaryCutError subclass."""
    code = err.code() if hasattr(err, "code") else grpc.StatusCode.UNKNOWN
    details = err.details() if hasattr(err, "details") else None
    if code == grpc.StatusCode.INTERNAL and not details:
        details = UNDECODABLE_REQUEST
    details = details or str(err)
    if code == grpc.StatusCode.UNAVAILABLE and ("Socket closed" in details or "Connection reset" in details):
        details += CLOSED_CONNECTION_HINT
    trailers = err.trailing_metadata() if hasattr(err, "trailing_metadata") else None
    field = next((value for key, value in (trailers or ()) if key == FIELD_METADATA_KEY), "")
    cls = _BY_CODE.get(code)
    if cls is None:
        return CulinaryCutError(details, code=code, field=field)
    return cls(details, field=field)


__all__ = [
    "CulinaryCutError", "InvalidArgument", "NotFound", "FailedPrecondition", "ResourceExhausted",
    "Unimplemented", "Unavailable", "Unauthenticated", "DeadlineExceeded", "Internal", "from_rpc_error",
]
