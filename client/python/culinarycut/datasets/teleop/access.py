"""Who may use the teleoperation app: a request must name this server in Host (no DNS rebinding), come
from one of its own origins when it says where it comes from (Origin), and carry the launch's secret token.

The token is made per launch (secrets.token_urlsafe) and printed in the page's URL (?token=...). Opening
that URL sets it as an HttpOnly, SameSite=Strict cookie named after the port and redirects to the bare
path, so the token leaves the address bar; pages, JSON views and camera images then authenticate by the
cookie. A POST must also carry the token in the X-CulinaryCut-Token header, which the page reads from
its own HTML: another site can neither read that page nor set the header without a CORS preflight, which
this app never grants, so a cookie sent along by the browser alone never drives the robot.
"""
from __future__ import annotations

import hmac
import ipaddress
import secrets
import socket
from urllib.parse import urlsplit

TOKEN_HEADER = "X-CulinaryCut-Token"
TOKEN_QUERY = "token"
LOOPBACK_NAMES = ("127.0.0.1", "localhost", "::1")
WILDCARD_BINDS = ("", "0.0.0.0", "::")
DEFAULT_HTTP_PORT = 80


class Refused(Exception):
    """A request this app does not serve; `status` is the HTTP status to answer with."""

    def __init__(self, status: int, message: str):
        super().__init__(message)
        self.status = status


def new_token() -> str:
    return secrets.token_urlsafe(32)


def is_loopback(host: str) -> bool:
    if host.lower() == "localhost":
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def url_host(name: str) -> str:
    """The name as a URL writes it: IPv6 addresses in brackets."""
    return f"[{name}]" if ":" in name else name


def served_names(bind: str, extra: tuple[str, ...] = ()) -> set[str]:
    """The host names a browser may use to reach a server bound to `bind`: the loopback names for a
    loopback bind, the address itself for one interface, and this machine's names for all of them."""
    names = {bind} if bind not in WILDCARD_BINDS else set()
    if bind in WILDCARD_BINDS or is_loopback(bind):
        names.update(LOOPBACK_NAMES)
    if bind in WILDCARD_BINDS:
        names.update({socket.gethostname(), socket.getfqdn()})
    names.update(extra)
    return {name.lower().strip("[]") for name in names if name}


def _host_and_port(netloc: str) -> tuple[str, int] | None:
    """('name', port) of a Host header or an origin's netloc, or None when it does not parse."""
    try:
        parts = urlsplit("//" + netloc)
        return (parts.hostname or "", parts.port or DEFAULT_HTTP_PORT)
    except ValueError:
        return None


class AccessPolicy:
    """The checks every request goes through (`check`), for a server bound to `bind`:`port`."""

    def __init__(self, bind: str, port: int, token: str, extra_hosts: tuple[str, ...] = ()):
        self.port, self.token = int(port), token
        self.names = served_names(bind, extra_hosts)
        self.cookie = f"culinarycut_teleop_{self.port}"  # cookies are shared across ports: one name per app

    def hosts(self) -> list[str]:
        return [f"{url_host(name)}:{self.port}" for name in sorted(self.names)]

    def _ours(self, netloc: str) -> bool:
        parsed = _host_and_port(netloc)
        return parsed is not None and parsed[0] in self.names and parsed[1] == self.port

    def check_host(self, host: str) -> None:
        if not self._ours(host):
            raise Refused(403, f"Host {host!r} is not this server (it serves {', '.join(self.hosts())}): "
                               "a page on another name reached it, as DNS rebinding does")

    def check_origin(self, origin: str | None) -> None:
        if origin is None:
            return  # not from a browser page (curl, scripts): the token decides
        parts = urlsplit(origin)
        if parts.scheme != "http" or not self._ours(parts.netloc):
            raise Refused(403, f"requests from origin {origin!r} are refused: only pages of this server "
                               f"({', '.join('http://' + h for h in self.hosts())}) may call it")

    def token_matches(self, candidate: str | None) -> bool:
        return bool(candidate) and hmac.compare_digest(candidate.encode(), self.token.encode())

    def check_token(self, header: str | None, cookie: str | None, state_changing: bool) -> None:
        """A POST needs the header (a browser adds a cookie to any request, but a header only for this
        app's own page); reads take either."""
        if state_changing:
            if not self.token_matches(header):
                raise Refused(403, f"a POST needs this launch's token in the {TOKEN_HEADER} header "
                                   f"({'wrong token' if header else 'none given'})")
        elif not (self.token_matches(header) or self.token_matches(cookie)):
            raise Refused(403, "no valid token: open the URL `culinarycut data teleop` printed (it carries "
                               f"?{TOKEN_QUERY}=...), or send the token in the {TOKEN_HEADER} header")
