"""dsr/get_blob from a replica's side: the bytes of a binary value that the replica holds only
by its digest (``BlobRef``: the bytes went by before it listened to their topic), asked of the
server, or for sensor data of the agent that wrote it (``dsr/get_blob/<node name>``: the server
never holds them). The request is sent from any thread (rclpy's client is thread-safe); its
answer comes on the thread that spins the node."""

from __future__ import annotations

import array
import asyncio
from collections import OrderedDict
from typing import Any

from dsr_graph.model.binary import BYTES
from dsr_graph.protocol.blobs import binary_value, digest_of, holder_of
from dsr_graph.protocol.queries import read_binary
from dsr_graph.protocol.topic_names import GET_BLOB
from dsr_msgs.srv import GetBlob

GET_BLOB_TYPE = "dsr_msgs/srv/GetBlob"


def blob_answer(graph, request: GetBlob.Request, response: GetBlob.Response, seq: int):
    """dsr/get_blob's answer from ``graph`` (the server's, or the writer's replica for sensor
    data): the bytes of the value, or why not, naming where sensor data's bytes are."""
    answer = read_binary(graph, request.node, request.attribute)
    response.found, response.error, response.seq = answer.found, answer.error, seq
    if answer.found:
        response.dtype = answer.dtype
        response.shape = list(answer.shape)
        response.data = array.array("B", answer.data)  # one copy, not element by element
    return response


def value_of(answer: GetBlob.Response) -> Any | None:
    """The binary value (bytes or a read-only array) in the server's answer; None if not found."""
    if not answer.found:
        return None
    shape = tuple(answer.shape) if answer.dtype != BYTES else None
    return binary_value(answer.dtype, shape, bytes(answer.data))


class AsyncBlobClient:
    """dsr/get_blob for an asyncio loop (a web app) beside a node spun in another thread. The
    last few values fetched are kept (an inspector that shows the same image again asks once)."""

    KEPT = 4

    def __init__(self, node, timeout: float):
        self.node = node
        self.clients = {GET_BLOB: node.create_client(GetBlob, GET_BLOB)}
        self.timeout = timeout
        self._kept: OrderedDict[str, bytes] = OrderedDict()  # digest -> bytes, newest last

    def discover(self) -> None:
        """A client for every agent's dsr/get_blob/<node name> the ROS graph shows (sensor
        data's bytes are with their writer). Call it on the thread that spins the node: made
        from another thread while an events executor spins, a client hangs its maker (seen
        here with rclpy's EventsExecutor; the SingleThreadedExecutor does not)."""
        prefix = self.node.resolve_topic_name(GET_BLOB) + "/"
        for name, types in self.node.get_service_names_and_types():
            owner = name[len(prefix) :]
            service = holder_of(owner)
            if name.startswith(prefix) and "/" not in owner and service not in self.clients:
                if types == [GET_BLOB_TYPE]:
                    self.clients[service] = self.node.create_client(GetBlob, service)

    async def fetch(
        self, node: str, attribute: str, digest: str, at: str | None = None
    ) -> bytes | None:
        """The bytes of ``node.attribute`` if the server (for sensor data, the node ``at`` that
        wrote it) holds the value of that ``digest`` still (None: missing, or changed since);
        ``TimeoutError`` when it does not answer in time (or ``at`` is not found running)."""
        if digest in self._kept:
            return self._kept[digest]
        service = holder_of(at)
        loop = asyncio.get_running_loop()
        deadline = loop.time() + self.timeout
        # a request sent before the service is matched is lost, never answered
        while (client := self.clients.get(service)) is None or not client.service_is_ready():
            if loop.time() >= deadline:
                raise TimeoutError(f"{service} is not offered (no such node running)")
            await asyncio.sleep(0.02)
        answered: asyncio.Future = loop.create_future()

        def hand_over(future) -> None:  # the ROS thread
            if not loop.is_closed():  # the web side may have stopped meanwhile
                loop.call_soon_threadsafe(_settle, answered, future)

        request = GetBlob.Request(node=node, attribute=attribute)
        sent = client.call_async(request)
        sent.add_done_callback(hand_over)
        try:
            answer = await asyncio.wait_for(answered, max(0.0, deadline - loop.time()))
        except TimeoutError:
            client.remove_pending_request(sent)  # an answer that comes later is dropped
            raise
        if not answer.found:
            return None
        data = bytes(answer.data)
        if digest_of(data) != digest:
            return None
        self._kept[digest] = data
        while len(self._kept) > self.KEPT:
            self._kept.popitem(last=False)
        return data


def _settle(answered: asyncio.Future, future) -> None:
    if answered.done():  # timed out meanwhile
        return
    if future.exception() is not None:
        answered.set_exception(future.exception())
    else:
        answered.set_result(future.result())
