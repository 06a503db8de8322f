"""What every web page of the suite (the DSR viewer, the clinician's dashboard) does before and
after its own handlers, against other web pages the same browser opens:

- every request needs an allowed ``Host`` (loopback names, plus the ones configured): a page of
  another site that rebinds its DNS name to 127.0.0.1 gets nothing (403);
- a state-changing request (POST, PUT, PATCH, DELETE) needs a JSON body (``Content-Type:
  application/json``, which a cross-site form or a "simple" fetch cannot send without a
  preflight) and, when the browser says where it comes from, this very origin (``Origin``) and
  ``Sec-Fetch-Site: same-origin``;
- every response says: the page's own files only (a CSP of ``default-src 'self'``), never in a
  frame (``frame-ancestors 'none'``), no content sniffing, no referrer; API answers are not
  cached.

``access_token``: the viewer's notebook-style token (printed at start), for a page that has no
accounts: ``?token=`` once (it becomes an HttpOnly, SameSite=Strict cookie), or an
``Authorization: Bearer`` header.
"""

from __future__ import annotations

import hmac
import secrets
from collections.abc import Iterable

from aiohttp import web

LOOPBACK = frozenset({"127.0.0.1", "localhost", "::1"})
UNSAFE = frozenset({"POST", "PUT", "PATCH", "DELETE"})
CSP = (
    "default-src 'self'; frame-ancestors 'none'; base-uri 'none'; form-action 'self'; "
    "object-src 'none'"
)
HEADERS = {
    "Content-Security-Policy": CSP,
    "X-Content-Type-Options": "nosniff",
    "Referrer-Policy": "no-referrer",
    "X-Frame-Options": "DENY",
    "Cross-Origin-Opener-Policy": "same-origin",
    "Cross-Origin-Resource-Policy": "same-origin",
}
TOKEN_COOKIE = "dsr_viewer_token"


def host_name(host: str) -> str:
    """The name in a Host header, without its port (``[::1]:8080`` -> ``::1``)."""
    host = host.strip().lower()
    if host.startswith("["):
        return host[1 : host.find("]")] if "]" in host else host
    return host.rsplit(":", 1)[0] if host.count(":") == 1 else host


def allowed_hosts(extra: Iterable[str] = ()) -> frozenset[str]:
    return LOOPBACK | {host_name(h) for h in extra if h.strip()}


def protect(app: web.Application, hosts: frozenset[str], token: str | None = None) -> None:
    """Add the checks and the headers to ``app`` (before it starts)."""

    @web.middleware
    async def guard(request: web.Request, handler):
        if host_name(request.host or "") not in hosts:
            raise web.HTTPForbidden(text="this Host is not served here")
        if request.method in UNSAFE:
            _same_origin(request)
        if token is not None:
            answer = _token(request, token)
            if answer is not None:
                return answer
        return await handler(request)

    async def headers(request: web.Request, response: web.StreamResponse) -> None:
        response.headers.update(HEADERS)
        if request.path.startswith("/api/"):
            response.headers["Cache-Control"] = "no-store"

    app.middlewares.append(guard)
    app.on_response_prepare.append(headers)


def _same_origin(request: web.Request) -> None:
    if request.content_type != "application/json":
        raise web.HTTPUnsupportedMediaType(text="send JSON (Content-Type: application/json)")
    origin = request.headers.get("Origin")
    if origin is not None and origin != f"{request.scheme}://{request.host}":
        raise web.HTTPForbidden(text=f"a request from another origin ({origin}) is refused")
    site = request.headers.get("Sec-Fetch-Site")
    if site is not None and site not in ("same-origin", "none"):
        raise web.HTTPForbidden(text=f"a request from another site ({site}) is refused")


def new_token() -> str:
    return secrets.token_urlsafe(24)


def _token(request: web.Request, token: str) -> web.StreamResponse | None:
    """None when the request carries the token; else the answer to give instead."""
    given = request.query.get("token")
    if given is not None and hmac.compare_digest(given, token):
        if request.method != "GET" or request.path.startswith("/api/"):
            return None
        # the token becomes a cookie, and leaves the address (history, screenshots)
        query = {k: v for k, v in request.query.items() if k != "token"}
        answer = web.HTTPFound(request.rel_url.with_query(query))
        answer.set_cookie(TOKEN_COOKIE, token, httponly=True, samesite="Strict", path="/")
        return answer
    cookie = request.cookies.get(TOKEN_COOKIE, "")
    bearer = request.headers.get("Authorization", "")
    if hmac.compare_digest(cookie, token) or hmac.compare_digest(bearer, f"Bearer {token}"):
        return None
    raise web.HTTPUnauthorized(
        text="this page needs its access token: open the address it printed when it started "
        "(…/?token=…)"
    )
