"""What the Kinect stand-in's cameras see (pure): a colour image (RGB, 8 bits a channel) and a
depth image (millimetres, 16 bits, 0 where there is no reading, as a Kinect v2 gives it) of the
room in front of the robot, with the patient in it when present, at ``width`` x ``height``.

The room is drawn once; each frame copies it and draws the person as a filled silhouette (an
ellipse for the head, a rectangle for the body) where their face is, the colour image dimmed
slightly with the frame's number so consecutive frames differ, so a reader can tell one frame
from the next. A frame costs a copy of each image and a few slices: 30 Hz at 640 x 480 is
cheap next to carrying the images.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

FOCAL = 525.0  # pixels: a Kinect's colour camera at 640 x 480
WALL_MM = 4000  # the back wall's distance
NO_READING = 0  # a depth pixel without a reading


class CameraModel:
    def __init__(self, width: int = 640, height: int = 480):
        self.width, self.height = width, height
        self.focal = FOCAL * width / 640.0
        rows = np.linspace(0.0, 1.0, height, dtype=np.float32)[:, None]
        cols = np.linspace(0.0, 1.0, width, dtype=np.float32)[None, :]
        room = np.empty((height, width, 3), dtype=np.uint8)
        room[..., 0] = (90 + 60 * rows + 0 * cols).astype(np.uint8)  # a warm wall, lit from above
        room[..., 1] = (80 + 50 * rows + 20 * cols).astype(np.uint8)
        room[..., 2] = (70 + 30 * cols + 0 * rows).astype(np.uint8)
        floor = int(height * 0.62)
        room[floor:] = (110, 100, 90)
        self.room_rgb = room
        depth = np.full((height, width), WALL_MM, dtype=np.uint16)
        # the floor comes nearer towards the bottom of the image; its farthest edge: no reading
        below = np.arange(height - floor, dtype=np.float32)
        depth[floor:] = (WALL_MM - below * (WALL_MM - 900) / max(len(below), 1))[:, None]
        depth[:, :4] = NO_READING
        self.room_depth = depth

    def frame(self, number: int, face_mm: Sequence[float] | None) -> tuple[np.ndarray, np.ndarray]:
        """The colour and depth images of frame ``number``; ``face_mm``: where the person's face
        is (x forward, y left, z up, mm, in the Kinect's frame), None when no one is there."""
        rgb = self.room_rgb.copy()
        depth = self.room_depth.copy()
        shade = number % 16
        rgb[: self.height // 8] -= np.uint8(shade)  # the frame's mark, top of the image
        if face_mm is not None and face_mm[0] > 300.0:
            self._person(rgb, depth, face_mm)
        return rgb, depth

    def _person(self, rgb: np.ndarray, depth: np.ndarray, face: Sequence[float]) -> None:
        x, y, z = (float(v) for v in face[:3])
        u = int(round(self.width / 2 - self.focal * y / x))  # image column of the face
        v = int(round(self.height / 2 - self.focal * z / x))  # image row
        head = max(int(self.focal * 110.0 / x), 2)  # a 22 cm head, in pixels
        body_w, body_h = 2 * head, int(self.focal * 900.0 / x)
        top, left = v + head, u - body_w // 2
        rows = slice(max(top, 0), min(top + body_h, self.height))
        cols = slice(max(left, 0), min(left + body_w, self.width))
        rgb[rows, cols] = (40, 70, 140)  # a blue jumper
        depth[rows, cols] = np.uint16(min(x + 100.0, 65535.0))
        r0, r1 = max(v - head, 0), min(v + head, self.height)
        c0, c1 = max(u - head, 0), min(u + head, self.width)
        if r0 < r1 and c0 < c1:
            yy, xx = np.ogrid[r0:r1, c0:c1]
            inside = (yy - v) ** 2 + (xx - u) ** 2 <= head**2
            rgb[r0:r1, c0:c1][inside] = (210, 170, 140)
            depth[r0:r1, c0:c1][inside] = np.uint16(min(x, 65535.0))
