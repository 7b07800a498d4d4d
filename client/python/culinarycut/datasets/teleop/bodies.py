"""The JSON bodies of the teleoperation API, checked before anything reaches the session: a malformed one
is refused (BadBody, answered 400) with a message naming the field, never a 500 and never a step."""
from __future__ import annotations

import json
import math

from culinarycut.datasets.teleop.session import RATINGS

ACTION_SIZE = 6  # pd_ee_delta_pose: position delta, then axis-angle
JSON_TYPE = "application/json"


class BadBody(ValueError):
    """A body this API does not accept."""


class NotJson(ValueError):
    """A POST whose Content-Type is not application/json (a form or text/plain body: answered 415)."""


def check_content_type(content_type: str | None) -> None:
    """JSON only: the request shapes a cross-site form can send (text/plain, form encodings) are refused,
    and a page of another origin cannot send JSON here without a preflight this app never grants."""
    media = (content_type or "").split(";")[0].strip().lower()
    if media != JSON_TYPE:
        raise NotJson(f"the body must be {JSON_TYPE}, not {media or 'untyped'}")


def _refuse_constant(name: str):
    raise BadBody(f"the body holds {name}, which is not a JSON number")


def parse(raw: bytes, allowed: tuple[str, ...]) -> dict:
    """The body as a JSON object with no other field than `allowed` (an empty body is {})."""
    try:
        body = json.loads(raw or b"{}", parse_constant=_refuse_constant)
    except BadBody:
        raise
    except ValueError as err:  # UnicodeDecodeError too
        raise BadBody(f"the body is not JSON: {err}") from None
    if not isinstance(body, dict):
        raise BadBody(f"the body must be a JSON object, not {type(body).__name__}")
    unknown = sorted(set(body) - set(allowed))
    if unknown:
        raise BadBody(f"unknown field(s) {', '.join(map(repr, unknown))}; this call takes "
                      f"{', '.join(map(repr, allowed)) or 'none'}")
    return body


def _required(body: dict, field: str):
    if field not in body:
        raise BadBody(f"missing field {field!r}")
    return body[field]


def action(raw: bytes) -> list[float]:
    """{"action": [6 finite numbers]}; values beyond [-1, 1] are clipped by the session."""
    values = _required(parse(raw, ("action",)), "action")
    if not isinstance(values, list):
        raise BadBody(f"'action' must be a list of {ACTION_SIZE} numbers, not {type(values).__name__}")
    if len(values) != ACTION_SIZE:
        raise BadBody(f"'action' has {len(values)} value(s); a pd_ee_delta_pose action has {ACTION_SIZE}")
    for i, value in enumerate(values):
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            raise BadBody(f"'action'[{i}] is {value!r}: every value must be a finite number")
    return [float(v) for v in values]


def recording(raw: bytes) -> bool:
    """{"on": true|false}."""
    on = _required(parse(raw, ("on",)), "on")
    if not isinstance(on, bool):
        raise BadBody(f"'on' must be true or false, not {on!r}")
    return on


def rating(raw: bytes) -> str:
    """{"rating": "good"|"bad"}."""
    value = _required(parse(raw, ("rating",)), "rating")
    if value not in RATINGS:
        raise BadBody(f"'rating' must be one of {', '.join(map(repr, RATINGS))}, not {value!r}")
    return value


def empty(raw: bytes) -> None:
    """{} (or no body)."""
    parse(raw, ())
