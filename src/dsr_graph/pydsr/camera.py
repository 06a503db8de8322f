"""CORTEX's camera API (``camera_api(g, camera_node)``, in CORTEX's C++ and its Python binding
of old): a camera node's images and intrinsics. The DSR's camera nodes (the Kinect stand-in's
``kinect``) hold ``cam_rgb``, height x width x 3 RGB bytes, and ``cam_depth``, height x width
metres (float32, 0: no reading); an agent's replica holds an image's digest when its bytes were
not sent to it, and the image is then asked of the agent that wrote it
(``dsr/get_blob/<node name>``: the server never holds sensor data's bytes).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from pydsr.elements import Node

RGB, DEPTH = "cam_rgb", "cam_depth"
IMAGE_WAIT = 10.0  # seconds for the server's answer


class camera_api:  # noqa: N801 (CORTEX's name)
    def __init__(self, graph: Any, camera: Node):
        self._g = graph
        self._name = camera.name
        self._id = camera.id
        self._attrs: dict[str, Any] = {}
        self.reload_camera()

    def reload_camera(self) -> None:
        """Read the camera node's intrinsics again (they are read once, as CORTEX does)."""
        node = self._g.get_node(self._name)
        self._attrs = {} if node is None else {k: a.value for k, a in node.attrs.items()}

    def _image(self, attribute: str) -> np.ndarray | None:
        value = self._g._link.binary(self._name, attribute, IMAGE_WAIT)
        if isinstance(value, bytes):
            return np.frombuffer(value, dtype=np.uint8)
        return value if isinstance(value, np.ndarray) else None

    def get_rgb_image(self) -> np.ndarray | None:
        """The latest colour image, height x width x 3 uint8 (RGB); None if the node has none."""
        return self._image(RGB)

    def get_depth_image(self) -> np.ndarray | None:
        """The latest depth image, height x width float32 metres; None if the node has none."""
        return self._image(DEPTH)

    def _shape(self) -> tuple[int, int]:
        image = self.get_rgb_image()
        if image is not None and image.ndim >= 2:
            return int(image.shape[0]), int(image.shape[1])
        return 0, 0

    @property
    def id(self) -> int:
        return self._id

    @property
    def width(self) -> int:
        return int(self._attrs.get("cam_rgb_width") or self._shape()[1])

    @property
    def height(self) -> int:
        return int(self._attrs.get("cam_rgb_height") or self._shape()[0])

    @property
    def focal_x(self) -> float:
        return float(self._attrs.get("cam_rgb_focalx", 0))

    @property
    def focal_y(self) -> float:
        return float(self._attrs.get("cam_rgb_focaly", 0))

    @property
    def focal(self) -> float:
        return self.focal_x
