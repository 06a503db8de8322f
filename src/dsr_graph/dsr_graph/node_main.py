"""The one ``main()`` shape of every node of the suite: init, build the node, run its body
(set-up, then spin or serve), and always shut down cleanly; start-up problems become a fatal log
line and exit code 1 instead of a traceback."""

from __future__ import annotations

from typing import Callable, List, Optional

import rclpy
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node

from .exceptions import DsrError


def run_node(make_node: Callable[[], Node], body: Callable[[Node], Optional[int]],
             args: Optional[List[str]] = None) -> int:
    rclpy.init(args=args)
    node = make_node()
    try:
        return body(node) or 0
    except (KeyboardInterrupt, ExternalShutdownException):
        return 0
    except (DsrError, OSError, ValueError) as e:  # a locked state dir, a taken port, a bad file
        node.get_logger().fatal(str(e))
        return 1
    finally:
        node.destroy_node()
        rclpy.try_shutdown()


def setup_and_spin(node: Node) -> None:
    """The body of most nodes: ``node.setup()``, then spin until shut down."""
    node.setup()
    rclpy.spin(node)
