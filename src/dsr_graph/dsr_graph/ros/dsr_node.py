"""The one shape of every node of the suite, as py_trees_ros has it: ``__init__`` declares the
parameters and builds pure state; ``setup()`` attaches publishers, subscriptions, services and
timers, and fails loudly with a typed error when something is not ready; ``run()`` spins (a node
that also serves a web page overrides it); ``close()`` releases what ``setup()`` took.

``main_for(NodeClass)`` is every node's ``main``: init, build, set up, run, and always shut down
cleanly; any error of the suite (``DsrError``: a locked or corrupt state directory, a scenario
that cannot be used, a server that does not answer), a parameter out of its range, a bad file or
a taken port becomes one fatal log line and exit code 1 instead of a traceback.
"""

from __future__ import annotations

from collections.abc import Callable

import rclpy
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.node import Node

from dsr_graph.exceptions import DsrError


class DsrNode(Node):
    def setup(self) -> None:
        """Attach publishers, subscriptions, services and timers (the second phase)."""

    def run(self) -> int | None:
        """Serve until shut down; the exit code (None: 0)."""
        rclpy.spin(self)
        return None

    def close(self) -> None:
        """Release what ``setup()`` took (files, locks); called once, also after a failure."""


def run_node(make_node: Callable[[], DsrNode], args: list[str] | None = None) -> int:
    rclpy.init(args=args)
    node: DsrNode | None = None
    try:
        node = make_node()
        node.setup()
        return node.run() or 0
    except (KeyboardInterrupt, ExternalShutdownException):
        return 0
    except (DsrError, ParameterException, OSError, ValueError) as e:
        logger = node.get_logger() if node is not None else rclpy.logging.get_logger("dsr")
        logger.fatal(str(e))
        return 1
    finally:
        if node is not None:
            node.close()
            node.destroy_node()
        rclpy.try_shutdown()


def main_for(node_class: Callable[[], DsrNode]) -> Callable[[list[str] | None], int]:
    """The console script's ``main`` of a node class."""

    def main(args: list[str] | None = None) -> int:
        return run_node(node_class, args)

    main.__doc__ = (
        f"Run {getattr(node_class, '__name__', 'the node')} until shut down; the exit code."
    )
    return main
