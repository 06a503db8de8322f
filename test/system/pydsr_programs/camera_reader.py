"""A pydsr agent that reads the camera's latest images (CORTEX's camera_api) and prints their
shapes, types and checksums as one JSON line: its replica holds only their digests, so the
images come from the agent that wrote them (dsr/get_blob/<node name>)."""

import json
import zlib

from pydsr import DSRGraph, camera_api

g = DSRGraph(0, "camera_reader", 9)
camera = camera_api(g, g.get_node("kinect"))
rgb, depth = camera.get_rgb_image(), camera.get_depth_image()
print(
    json.dumps(
        {
            "rgb": [list(rgb.shape), str(rgb.dtype), zlib.crc32(rgb.tobytes())],
            "depth": [list(depth.shape), str(depth.dtype), zlib.crc32(depth.tobytes())],
            "size": [camera.width, camera.height],
        }
    ),
    flush=True,
)
