"""The Kinect stand-in's cameras and the camera agent's reading of their images (pure parts):
the room with the patient drawn where their face is, each frame told from the last; images as
sensor_msgs/Image carry, back to the arrays the DSR holds (colour as it is, depth in metres);
a malformed image is refused naming what is wrong."""

import array

import numpy as np
import pytest
from sensor_msgs.msg import Image

from clarc_agents.nodes.camera_node import pixels
from clarc_sim.devices.camera_images import CameraModel
from clarc_sim.devices.kinect_node import image_message


def test_the_patient_is_drawn_where_the_face_is_and_frames_differ():
    camera = CameraModel(640, 480)
    empty_rgb, empty_depth = camera.frame(0, None)
    rgb, depth = camera.frame(1, (1500.0, 0.0, 0.0))  # 1.5 m ahead, centred
    assert rgb.shape == (480, 640, 3) and depth.dtype == np.uint16
    assert depth[240, 320] == 1500 and empty_depth[240, 320] == 4000  # the face, the wall
    assert not np.array_equal(camera.frame(2, None)[0], empty_rgb)  # the frame's mark
    left, _ = camera.frame(1, (1500.0, 500.0, 0.0))  # half a metre to the left
    assert left[240, 320].tolist() != rgb[240, 320].tolist()


def test_images_come_back_as_the_dsr_holds_them():
    rgb, depth = CameraModel(64, 48).frame(3, (1000.0, 0.0, 0.0))
    stamp = Image().header.stamp
    back = pixels(image_message(rgb, "rgb8", stamp))
    assert back.dtype == np.uint8 and np.array_equal(back, rgb)
    metres = pixels(image_message(depth, "16UC1", stamp))
    assert metres.dtype == np.float32 and np.allclose(metres, depth / 1000.0)
    padded = Image(encoding="rgb8", height=2, width=2, step=8)  # rows padded to 8 bytes
    padded.data = array.array("B", bytes(range(16)))
    assert pixels(padded).tolist() == [[[0, 1, 2], [3, 4, 5]], [[8, 9, 10], [11, 12, 13]]]


@pytest.mark.parametrize(
    "image, error",
    [
        (Image(encoding="bgr8", height=1, width=1, step=3, data=[1, 2, 3]), "rgb8, 16UC1 or 32FC1"),
        (Image(encoding="rgb8", height=2, width=2, step=6, data=[0] * 6), "got step 6 and 6 bytes"),
        (Image(encoding="16UC1", height=1, width=4, step=4, data=[0] * 4), "8 bytes a row"),
    ],
)
def test_a_malformed_image_is_refused_naming_what_is_wrong(image, error):
    with pytest.raises(ValueError, match=error):
        pixels(image)
