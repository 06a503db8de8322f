"""Audio on ROS topics (plumbing): audio_common_msgs/AudioDataStamped chunks of 16 kHz mono
PCM16 (S16LE), the stream's AudioInfo latched on ``<topic>/info``, as ROS's audio_common
publishes audio."""

from __future__ import annotations

import numpy as np
from audio_common_msgs.msg import AudioData, AudioDataStamped, AudioInfo
from rclpy.node import Node
from rclpy.qos import DurabilityPolicy, HistoryPolicy, QoSProfile, ReliabilityPolicy
from rclpy.time import Time

from clarc_agents.asr.audio import RATE
from dsr_graph.ros.qos import qos_latched

CHUNK = 0.05  # s of audio a message carries
CHUNK_SAMPLES = int(CHUNK * RATE)


def qos_audio() -> QoSProfile:
    """Reliable and 10 s deep: a busy reader gets the stream late, never with holes (a hole
    inside an answer would change the words)."""
    return QoSProfile(
        history=HistoryPolicy.KEEP_LAST,
        depth=int(10 / CHUNK),
        reliability=ReliabilityPolicy.RELIABLE,
        durability=DurabilityPolicy.VOLATILE,
    )


def audio_message(samples: np.ndarray, stamp: float) -> AudioDataStamped:
    """``samples`` (int16) whose first was captured (or played) at ``stamp`` (epoch s)."""
    message = AudioDataStamped(audio=AudioData(data=samples.astype("<i2").tobytes()))
    message.header.stamp = Time(nanoseconds=int(stamp * 1e9)).to_msg()
    return message


def samples_of(message: AudioDataStamped) -> tuple[bytes, float]:
    """The chunk's PCM16 bytes and its stamp (epoch s); ValueError for an odd length."""
    data = bytes(message.audio.data)
    if len(data) % 2:
        raise ValueError(f"an audio chunk of {len(data)} bytes: 16-bit samples have even length")
    stamp = message.header.stamp.sec + message.header.stamp.nanosec / 1e9
    return data, stamp


def audio_publishers(node: Node, topic: str):
    """The stream's publisher and its AudioInfo's, published latched on ``<topic>/info`` (keep
    both)."""
    info = node.create_publisher(AudioInfo, f"{topic}/info", qos_latched())
    info.publish(
        AudioInfo(
            channels=1,
            sample_rate=RATE,
            sample_format="S16LE",
            bitrate=16 * RATE,
            coding_format="wave",
        )
    )
    return node.create_publisher(AudioDataStamped, topic, qos_audio()), info
