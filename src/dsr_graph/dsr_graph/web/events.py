"""Server-Sent Events for every open page of a web app (aiohttp; no ROS): ``publish`` from the
asyncio loop, ``stream`` as the handler of an events URL."""

from __future__ import annotations

import asyncio
import json
from collections.abc import Callable
from typing import Any

from aiohttp import web

from dsr_graph.model.binary import summary


def dumps(data: Any, **kwargs: Any) -> str:
    """JSON for a page: a binary value (a camera image) by what it is, never its bytes."""
    return json.dumps(data, default=summary, **kwargs)


class Broadcaster:
    """Events for every connected page (Server-Sent Events); lives in the asyncio loop."""

    def __init__(self) -> None:
        self._queues: set[asyncio.Queue] = set()

    @property
    def listening(self) -> bool:
        """A page is connected: an event's data is worth making (the viewer's text of a delta)."""
        return bool(self._queues)

    def publish(self, kind: str, data: Any) -> None:
        if not self._queues:  # no page open: nothing is encoded for no one
            return
        text = f"event: {kind}\ndata: {dumps(data, separators=(',', ':'))}\n\n"
        for queue in list(self._queues):
            if queue.qsize() > 1000:  # a page that stopped reading: drop it, it reconnects
                self._queues.discard(queue)
            else:
                queue.put_nowait(text)

    async def stream(
        self, request: web.Request, first: Callable[[], list] | None = None
    ) -> web.StreamResponse:
        response = web.StreamResponse(
            headers={"Content-Type": "text/event-stream", "Cache-Control": "no-cache"}
        )
        await response.prepare(request)
        queue: asyncio.Queue = asyncio.Queue()
        self._queues.add(queue)
        try:
            for kind, data in first() if first else []:
                await response.write(f"event: {kind}\ndata: {dumps(data)}\n\n".encode())
            while True:
                try:
                    text = await asyncio.wait_for(queue.get(), timeout=15)
                except TimeoutError:
                    text = ": keep-alive\n\n"
                await response.write(text.encode())
        except (ConnectionResetError, asyncio.CancelledError):
            pass
        finally:
            self._queues.discard(queue)
        return response
