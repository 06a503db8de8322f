"""The raw-rclpy baseline of the DSR server: republishes every String from one topic to another,
with the same QoS and the server's executor, and nothing else. Usage: relay.py IN_TOPIC OUT_TOPIC"""

import sys

import rclpy
from rclpy.executors import ExternalShutdownException
from std_msgs.msg import String

from dsr_graph.ros.dsr_node import DsrNode
from dsr_graph.ros.qos import qos_stream


def main() -> int:
    rclpy.init()
    node = rclpy.create_node("bench_relay")
    out = node.create_publisher(String, sys.argv[2], qos_stream())
    node.create_subscription(String, sys.argv[1], out.publish, qos_stream())
    try:
        # spun as the server is (DsrNode.spin_once: rclpy.spin with this executor kept a core
        # busy and relayed nothing, in these wheels)
        executor = DsrNode.EXECUTOR()
        executor.add_node(node)
        while rclpy.ok():
            executor.spin_once(timeout_sec=0.5)
    except (KeyboardInterrupt, ExternalShutdownException):
        pass
    finally:
        node.destroy_node()
        rclpy.try_shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
