"""The camera agent: the Kinect's colour and depth images into the DSR, as CORTEX's camera
agents put them, on the ``kinect`` node: ``cam_rgb`` (height x width x 3, uint8) and
``cam_depth`` (height x width, float32 metres, 0: no reading), both volatile (sensor data, never
journalled), with ``cam_rgb_width``, ``cam_rgb_height``, ``cam_rgb_depth``, ``cam_depth_width``
and ``cam_depth_height`` written once. The images travel beside the JSON as bytes
(dsr_graph/protocol/blobs.py). At most ``IN_FLIGHT`` transactions are on their way, each with the
newest pair of images: a DSR that falls behind gets fewer images, never old ones
(``images_skipped`` counts them).

ROS Parameters: node (the DSR node the images go on, default "kinect"), setup_timeout (20).
Subscriptions: clarc/kinect/rgb (rgb8), clarc/kinect/depth (16UC1 millimetres or 32FC1
metres), sensor_msgs/Image, best effort; the DSR topics (DsrAgent).
"""

from __future__ import annotations

import time

import numpy as np
from sensor_msgs.msg import Image

from clarc_agents import topics
from dsr_graph.ros.agent import DsrAgent
from dsr_graph.ros.dsr_node import DsrNode, main_for
from dsr_graph.ros.parameters import declare, declare_setup_timeout, float_param, param
from dsr_graph.ros.qos import qos_images

REPORT_EVERY = 10.0  # seconds between the log lines counting images
# transactions of images on their way at once: a second one is sent while the first is being
# applied, so the round trip to the server does not halve the rate
IN_FLIGHT = 2


def pixels(msg: Image) -> np.ndarray:
    """An image's pixels as the DSR holds them: rgb8 -> uint8 rows x columns x 3; a depth image
    (16UC1 millimetres, 32FC1 metres) -> float32 metres. ValueError names what is wrong."""
    rows, cols = int(msg.height), int(msg.width)
    data = np.frombuffer(msg.data, dtype=np.uint8)
    if msg.encoding == "rgb8":
        shape, dtype = (rows, cols, 3), np.dtype("u1")
    elif msg.encoding == "16UC1":
        shape, dtype = (rows, cols), np.dtype(">u2" if msg.is_bigendian else "<u2")
    elif msg.encoding == "32FC1":
        shape, dtype = (rows, cols), np.dtype(">f4" if msg.is_bigendian else "<f4")
    else:
        raise ValueError(f"image encoding {msg.encoding!r}: rgb8, 16UC1 or 32FC1 only")
    row_bytes = cols * dtype.itemsize * (shape[2] if len(shape) == 3 else 1)
    if msg.step < row_bytes or len(data) < msg.step * rows:
        raise ValueError(
            f"a {cols}x{rows} {msg.encoding} image needs {row_bytes} bytes a row, "
            f"got step {msg.step} and {len(data)} bytes"
        )
    image = data[: msg.step * rows].reshape(rows, msg.step)[:, :row_bytes].view(dtype)
    image = image.reshape(shape)
    if msg.encoding == "16UC1":
        return image.astype(np.float32) * np.float32(0.001)
    return image.astype(np.float32) if msg.encoding == "32FC1" else image


class CameraAgent(DsrNode):
    NAME = "camera"

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        declare(node, "node", "kinect", "the DSR node the images are written on", read_only=True)
        declare_setup_timeout(node, 20.0)

    def __init__(self):
        super().__init__()
        self.dsr = DsrAgent()
        self._rgb: np.ndarray | None = None
        self._depth: np.ndarray | None = None
        self._in_flight = 0
        self._sizes_written = False
        self.images_taken = self.images_written = self.images_skipped = 0
        self._reported = time.monotonic()

    def setup(self) -> None:
        self.dsr.describe(can_do=["see"], listens_to=[topics.KINECT_RGB, topics.KINECT_DEPTH])
        self.dsr.setup(self, timeout_sec=float_param(self, "setup_timeout"))
        self.create_subscription(Image, topics.KINECT_RGB, self.on_rgb, qos_images())
        self.create_subscription(Image, topics.KINECT_DEPTH, self.on_depth, qos_images())
        self.get_logger().info(f"camera agent up: images go on the DSR's {param(self, 'node')!r}")

    def on_rgb(self, msg: Image) -> None:
        self._take(msg, "rgb")

    def on_depth(self, msg: Image) -> None:
        self._take(msg, "depth")

    def _take(self, msg: Image, which: str) -> None:
        try:
            image = pixels(msg)
        except ValueError as e:  # a malformed image never kills the agent
            self.get_logger().error(f"ignoring a {which} image: {e}", throttle_duration_sec=5.0)
            return
        if which == "rgb":
            self.images_taken += 1
            if self._rgb is not None:
                self.images_skipped += 1  # replaced before it could be written
            self._rgb = image
        else:
            self._depth = image
        self._write()

    def _write(self) -> None:
        if self._in_flight >= IN_FLIGHT or self._rgb is None or self._depth is None:
            return
        if not self.dsr.synced or param(self, "node") not in self.dsr.graph:
            return
        node = param(self, "node")
        if not self._sizes_written:  # durable, so apart: a transaction of images alone is
            # volatile (never journalled), one with anything else would not be
            (height, width, depth), (d_height, d_width) = self._rgb.shape, self._depth.shape
            sizes = {
                "cam_rgb_width": width,
                "cam_rgb_height": height,
                "cam_rgb_depth": depth,
                "cam_depth_width": d_width,
                "cam_depth_height": d_height,
            }
            self._sizes_written = True
            self.dsr.send({"ops": [{"op": "set_node_attrs", "node": node, "attrs": sizes}]})
        attrs = {"cam_rgb": self._rgb, "cam_depth": self._depth}
        self._rgb = self._depth = None
        self._in_flight += 1
        op = {"op": "set_node_attrs", "node": node, "attrs": attrs}
        self.dsr.send({"ops": [op]}, self._written)

    def _written(self, result) -> None:
        self._in_flight -= 1
        if result.accepted:
            self.images_written += 1
        else:
            self.get_logger().warning(
                f"images not written: {result.error}", throttle_duration_sec=5.0
            )
        now = time.monotonic()
        if now - self._reported >= REPORT_EVERY:
            self._reported = now
            self.report()
        self._write()

    def report(self) -> None:
        self.get_logger().info(
            f"images: {self.images_taken} taken, {self.images_written} written, "
            f"{self.images_skipped} replaced by a newer one before the DSR took them"
        )

    def close(self) -> None:
        self.report()
        super().close()


main = main_for(CameraAgent)
