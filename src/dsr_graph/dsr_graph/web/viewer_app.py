"""The DSR viewer's web application (aiohttp; no ROS): the page, and a read-only JSON API over a
``History``. ``viewer_node.py`` feeds the history from the DSR.

    GET /api/graph[?seq=N]              the snapshot now (or at seq N), our snapshot JSON format
    GET /api/deltas?since=S[&limit=L]   accepted deltas after S: {"first_seq", "seq", "deltas"}
    GET /api/transform?from=A&to=B[&seq=N]   B's pose in A's frame: {"matrix", "translation",
                                        "quaternion_wxyz", "chain"}
    GET /api/events                     Server-Sent Events: "hello", then "delta" per accepted
                                        delta (with a readable "text") and "reset" after a
                                        resynchronisation
    GET /api/info                       {"replay": null} live, or {"replay": "FILE.mcap"} when
                                        the history is a recording (``dsr view --replay``)
    GET /api/image?node=N&attr=A[&seq=S]  a binary value's bytes (a camera image), with its
                                        element type and shape in X-DSR-Dtype and X-DSR-Shape

A binary value appears in the JSON by what it is, without its bytes (``binary.summary``):
``{"$binary": "uint8", "shape": [480, 640, 3], "size": 921600}``. Bytes that went by before the
viewer listened to their topic are asked of the server (``fetch_blob``), and served only if they
are still that seq's value (the same digest).

Protected as web/guard.py says: an allowed Host, the access token (printed at start), a CSP;
it serves its page, its two files and the one library file it uses, nothing else.
"""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from importlib import resources
from pathlib import Path

from aiohttp import web

from dsr_graph.exceptions import LookupFailed, SeqUnavailable
from dsr_graph.formats import dsr_json
from dsr_graph.model import rigid
from dsr_graph.model.binary import ELEMENT_OF, BlobRef
from dsr_graph.protocol.blobs import binary_value, holder_of
from dsr_graph.protocol.delta_text import delta_text
from dsr_graph.protocol.history import History
from dsr_graph.web.events import Broadcaster, dumps
from dsr_graph.web.guard import LOOPBACK, protect

WEB = Path(str(resources.files("dsr_graph").joinpath("web")))
VENDOR = {"cytoscape.min.js": WEB / "node_modules" / "cytoscape" / "dist" / "cytoscape.min.js"}
PAGE_FILES = ("viewer.css", "viewer.js")  # all that /static/ serves


def _seq(request: web.Request, history: History) -> int:
    text = request.query.get("seq")
    if text is None:
        return history.seq
    try:
        return int(text)
    except ValueError:
        raise web.HTTPBadRequest(text=f"seq must be an integer, got {text!r}") from None


def _graph(request: web.Request, history: History):
    if history.graph is None:
        raise web.HTTPServiceUnavailable(text="the viewer has not received the graph yet")
    seq = _seq(request, history)
    try:
        return history.graph_at(seq), seq
    except SeqUnavailable as e:
        raise web.HTTPNotFound(text=str(e)) from None


def make_app(
    history: History,
    events: Broadcaster,
    replay: str | None = None,
    token: str | None = None,
    hosts: frozenset[str] = LOOPBACK,
    fetch_blob: Callable[[str, str, str, str | None], Awaitable[bytes | None]] | None = None,
) -> web.Application:
    """The viewer over ``history``: live (fed as the DSR changes) or a ``replay`` (the name of
    the recording it was read from). ``token``: the access token every request needs (None:
    none, for tests of the API alone); ``hosts``: the Host names served; ``fetch_blob(node,
    attribute, digest, at)``: the bytes of a value the history holds by digest only, asked of the
    server or, for sensor data, of its writer ``at`` (None: gone)."""

    async def fetched(node: str, attr: str, ref: BlobRef, seq: int):
        if fetch_blob is None:
            raise web.HTTPNotFound(text=f"{node}.{attr}: its bytes have not reached the viewer")
        try:
            data = await fetch_blob(node, attr, ref.digest, ref.at)
        except TimeoutError:
            raise web.HTTPServiceUnavailable(
                text=f"{node}.{attr}: {holder_of(ref.at)} did not answer"
            ) from None
        if data is None:
            holder = f"its writer, {ref.at}," if ref.at else "the server"
            raise web.HTTPNotFound(text=f"{node}.{attr}: {holder} no longer holds seq {seq}'s")
        return binary_value(ref.dtype, ref.shape, data)

    async def index(request: web.Request) -> web.FileResponse:
        return web.FileResponse(WEB / "viewer.html")

    async def page_file(request: web.Request) -> web.FileResponse:
        name = request.match_info["name"]
        if name not in PAGE_FILES:
            raise web.HTTPNotFound()
        return web.FileResponse(WEB / name)

    async def vendor(request: web.Request) -> web.FileResponse:
        path = VENDOR.get(request.match_info["name"])
        if path is None or not path.exists():
            raise web.HTTPNotFound(
                text="unknown library (run scripts/setup.sh to install the viewer's libraries)"
            )
        return web.FileResponse(path)

    async def graph(request: web.Request) -> web.Response:
        g, seq = _graph(request, history)
        return web.json_response(dsr_json.to_json(g, "snapshot", seq=seq), dumps=dumps)

    async def image(request: web.Request) -> web.Response:
        g, seq = _graph(request, history)
        node, attr = request.query.get("node"), request.query.get("attr")
        found = g.find(node) if node else None
        if found is None or attr not in found.attrs:
            raise web.HTTPNotFound(text=f"no attribute {attr!r} on node {node!r} at seq {seq}")
        value = found.attrs[attr]
        if isinstance(value, BlobRef):
            value = await fetched(node, attr, value, seq)
        if isinstance(value, bytes):
            body, dtype, shape = value, "bytes", [len(value)]
        elif hasattr(value, "dtype") and value.dtype in ELEMENT_OF:
            body, dtype, shape = value.tobytes(), ELEMENT_OF[value.dtype], list(value.shape)
        else:
            raise web.HTTPBadRequest(text=f"{node}.{attr} is not a binary value")
        headers = {"X-DSR-Dtype": dtype, "X-DSR-Shape": ",".join(map(str, shape))}
        return web.Response(body=body, content_type="application/octet-stream", headers=headers)

    async def deltas(request: web.Request) -> web.Response:
        try:
            since = int(request.query.get("since", history.first_seq))
            limit = min(int(request.query.get("limit", 1000)), 10000)
        except ValueError:
            raise web.HTTPBadRequest(text="since and limit are integers") from None
        return web.json_response(
            {
                "first_seq": history.first_seq,
                "seq": history.seq,
                "deltas": [dict(d, text=delta_text(d)) for d in history.since(since, limit)],
            },
            dumps=dumps,
        )

    async def transform(request: web.Request) -> web.Response:
        g, seq = _graph(request, history)
        frm, to = request.query.get("from"), request.query.get("to")
        if not frm or not to:
            raise web.HTTPBadRequest(text="give from and to (node names)")
        try:
            answer = rigid.pose_json(g.transform(frm, to))
            answer["chain"] = g.chain(frm, to)
        except LookupFailed as e:
            raise web.HTTPNotFound(text=str(e)) from None
        answer["seq"] = seq
        return web.json_response(answer)

    async def stream(request: web.Request) -> web.StreamResponse:
        return await events.stream(
            request, first=lambda: [("hello", {"seq": history.seq, "first_seq": history.first_seq})]
        )

    async def info(request: web.Request) -> web.Response:
        return web.json_response({"replay": replay})

    app = web.Application()
    protect(app, hosts, token)
    app.router.add_get("/", index)
    app.router.add_get("/static/{name}", page_file)
    app.router.add_get("/vendor/{name}", vendor)
    app.router.add_get("/api/graph", graph)
    app.router.add_get("/api/deltas", deltas)
    app.router.add_get("/api/transform", transform)
    app.router.add_get("/api/events", stream)
    app.router.add_get("/api/info", info)
    app.router.add_get("/api/image", image)
    return app
