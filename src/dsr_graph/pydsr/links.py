"""How a ``DSRGraph`` reaches a DSR: both links send transactions and wait for their verdict,
keep a replica, and call a listener with every delta applied to it.

- ``LocalLink``: a graph of this process's own, started from a world file (CORTEX's first agent
  reading its config file): the server's core in-process (``protocol/local_bus.py``), so writes
  are checked, answered and turned into deltas exactly as by ``dsr_server``. Each one is fresh.
- ``RosLink``: an agent of the running ``dsr_server`` (``ros/agent.py``) under the ROS node name
  the program gave. Its executor runs on a thread of its own, in a ROS context of its own; the
  replica is read and written under ``lock``, which that thread holds only while it runs a
  callback.
"""

from __future__ import annotations

import atexit
import contextlib
import threading
import time
from collections.abc import Callable
from typing import Any

from dsr_graph.exceptions import TimedOutError
from dsr_graph.model.binary import BlobRef
from dsr_graph.model.graph import Graph
from dsr_graph.protocol.local_bus import LocalBus
from dsr_graph.protocol.server_core import Result

Listener = Callable[[list[dict[str, Any]], bool], None]


class LocalLink:
    def __init__(self, graph: Graph, name: str):
        self.bus = LocalBus(graph, start_time=time.time())
        self.agent = self.bus.agent(name)
        self.lock = contextlib.nullcontext()  # one thread: nothing to guard
        self.name = name

    @property
    def graph(self) -> Graph:
        return self.agent.graph

    def add_listener(self, listener: Listener) -> None:
        self.agent.add_listener(listener)

    def transact(self, doc: dict[str, Any], timeout: float) -> Result:
        results: list[Result] = []
        self.bus.now = max(self.bus.now, time.time())  # the deltas' stamps are real times
        self.agent.send(doc, results.append)
        self.bus.run(until=lambda: bool(results), limit=timeout)
        return results[0]

    def binary(self, node: str, attribute: str, timeout: float) -> Any:
        """A binary value (bytes or an array) as the graph holds it; None if it has none."""
        found = self.graph.find(node)
        return None if found is None else found.attrs.get(attribute)

    def close(self) -> None:
        pass


class RosLink:
    def __init__(self, name: str, timeout: float):
        import rclpy
        from rclpy.context import Context
        from rclpy.executors import SingleThreadedExecutor

        from dsr_graph.ros.agent import DsrAgent

        self.name = name
        self.lock = threading.RLock()
        self._closed = False
        self.context = Context()
        rclpy.init(context=self.context)
        try:
            from dsr_graph.ros.dds_deadlock import new_event_threads

            with new_event_threads() as self._event_threads:
                self.node = rclpy.create_node(name, context=self.context)
            self.executor = SingleThreadedExecutor(context=self.context)
            self.executor.add_node(self.node)
            self.agent = DsrAgent()
            self.agent.setup(self.node, timeout_sec=timeout)
            from dsr_graph.protocol.topic_names import GET_BLOB
            from dsr_msgs.srv import GetBlob

            self._blob_clients = {GET_BLOB: self.node.create_client(GetBlob, GET_BLOB)}
            self._thread = threading.Thread(target=self._spin, name=f"pydsr {name}", daemon=True)
            self._running = True
            self._thread.start()
            # CORTEX programs never close their graph: at exit the ROS thread must be stopped
            # before the interpreter goes (else rclpy's wait aborts the process)
            atexit.register(self.close)
            self._wait(lambda: self.agent.ready, timeout, "the DSR server's snapshot")
        except BaseException:
            self.close()
            raise

    @property
    def graph(self) -> Graph:
        return self.agent.graph

    def add_listener(self, listener: Listener) -> None:
        with self.lock:
            self.agent.add_listener(listener)

    def transact(self, doc: dict[str, Any], timeout: float) -> Result:
        done = threading.Event()
        results: list[Result] = []

        def verdict(result: Result) -> None:
            results.append(result)
            done.set()

        with self.lock:
            self.agent.send(doc, verdict)
        if not done.wait(timeout):
            raise TimedOutError(f"no verdict from the DSR server within {timeout} s")
        return results[0]

    def binary(self, node: str, attribute: str, timeout: float) -> Any:
        """A binary value (bytes or an array): the replica's, or, where it holds only the
        value's digest (the bytes were not sent to it), the server's (dsr/get_blob), or for
        sensor data its writer's (dsr/get_blob/<node name>)."""
        with self.lock:
            found = self.graph.find(node)
            value = None if found is None else found.attrs.get(attribute)
        if not isinstance(value, BlobRef):
            return value
        from dsr_graph.protocol.blobs import holder_of
        from dsr_graph.ros.blob_service import value_of
        from dsr_msgs.srv import GetBlob

        deadline = time.monotonic() + timeout
        service = holder_of(value.at)  # sensor data: its writer alone holds the bytes
        with self.lock:
            if service not in self._blob_clients:
                self._blob_clients[service] = self.node.create_client(GetBlob, service)
            client = self._blob_clients[service]
        # a request sent before the service is matched is lost: on a busy machine a program's
        # first request can come before discovery has matched it
        self._wait(client.service_is_ready, timeout, service)
        done = threading.Event()
        with self.lock:
            future = client.call_async(GetBlob.Request(node=node, attribute=attribute))
        future.add_done_callback(lambda f: done.set())
        if not done.wait(max(0.0, deadline - time.monotonic())):
            with self.lock:
                client.remove_pending_request(future)
            raise TimedOutError(f"no answer from {service} within {timeout} s")
        return value_of(future.result())

    def _spin(self) -> None:
        from rclpy.executors import (
            ExternalShutdownException,
            ShutdownException,
            TimeoutException,
        )

        while self._running:
            try:
                handler, _, _ = self.executor.wait_for_ready_callbacks(timeout_sec=0.1)
            except TimeoutException:
                continue
            except (ShutdownException, ExternalShutdownException):
                return
            with self.lock:
                handler()
            if handler.exception() is not None:
                self.node.get_logger().error(f"a callback failed: {handler.exception()!r}")

    def _wait(self, ready: Callable[[], bool], timeout: float, what: str) -> None:
        deadline = time.monotonic() + timeout
        while True:
            with self.lock:
                if ready():
                    return
            if time.monotonic() >= deadline:
                raise TimedOutError(f"{what} did not come within {timeout} s")
            time.sleep(0.01)

    def close(self) -> None:
        if self._closed:
            return
        self._closed = True
        atexit.unregister(self.close)
        self._running = False
        thread = getattr(self, "_thread", None)
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=5.0)
        executor = getattr(self, "executor", None)
        if executor is not None:
            executor.shutdown(timeout_sec=1.0)
        node = getattr(self, "node", None)
        if node is not None:
            from dsr_graph.ros import dds_teardown

            if not dds_teardown.destroy_node(node, self._event_threads, (executor, self.context)):
                return  # Fast DDS deadlocked its participant: left as it is (dds_deadlock)
        if self.context.ok():
            self.context.try_shutdown()
