"""The one shape of every node of the suite, as py_trees_ros has it: the class method
``declare_node_parameters(node)`` declares the parameters (so ``--help`` can list them without
making a node); ``__init__`` builds pure state; ``setup()`` attaches publishers, subscriptions,
services and timers, and fails loudly with a typed error when something is not ready; ``run()``
spins (a node that also serves a web page overrides it); ``close()`` releases what ``setup()``
took.

``main_for(NodeClass)`` is every node's ``main``: ``--help`` prints the node's parameters and
exits with no side effect; otherwise init, build, set up, run, and always shut down cleanly. Any
error of the suite (``DsrError``: a locked or corrupt state directory, a scenario that cannot be
used, a server that does not answer), a missing or out-of-range parameter, a bad file or a taken
port becomes one fatal log line and exit code 1 instead of a traceback; SIGINT and SIGTERM end
it with exit 0, also while it waits for the DSR server.

SIGINT and SIGTERM stop a node alike (``StopSignals``): the first raises KeyboardInterrupt in
the main thread, which cuts a wait short (never inside a spin's callbacks), and a node spins
until ``stop_requested()``, which knows of a signal from the instant it came, also when its
KeyboardInterrupt was swallowed on the way (seen under load, when rclpy's handler was the one:
4 of 300 stops in a stress of SIGINTs at random moments left nodes spinning until launch killed
them). rclpy's own handlers are off: they shut ROS down from a thread of their own, which
crashed nodes at a launch's end (stop_signals.py). A signal that lands during the imports,
before ``run_node`` installs the handlers, ends the process as Python's default does.
"""

from __future__ import annotations

import faulthandler
import os
import sys
import traceback
from collections.abc import Callable

import rclpy
from rclpy.event_handler import PublisherEventCallbacks, SubscriptionEventCallbacks
from rclpy.exceptions import ParameterException
from rclpy.executors import ExternalShutdownException
from rclpy.experimental import EventsExecutor
from rclpy.node import Node
from rclpy.signals import SignalHandlerOptions

from dsr_graph.exceptions import DsrError
from dsr_graph.formats.private_files import set_private_umask
from dsr_graph.ros import dds_deadlock, dds_teardown, process_gc
from dsr_graph.ros.exit_timer import TEARDOWN_LIMIT, exit_if_stuck, exit_now
from dsr_graph.ros.parameters import check_required, help_text
from dsr_graph.ros.stop_signals import StopSignals, stopping_anyway

NO_DEFAULT_EVENTS = {"use_default_callbacks": False}  # see DsrNode.create_publisher
# seconds the DDS participant's deletion may take at the end (launch sends SIGTERM after 5)
STOP_POLL = 0.5  # seconds: the longest a stop rclpy missed goes unseen by a spinning node


class DsrNode(Node):
    NAME = ""  # the node's name unless remapped
    # What run() spins (called with context=): rclpy's C++ events executor, not the wait set
    # Python rebuilds every turn. An agent's delta after another callback waited a turn of
    # 0.3 ms on the SingleThreadedExecutor (bench/latency.py's stages); the server on it, side
    # by side with itself on the old one, made a change visible at p50 0.76x and 0.86x in two
    # runs (bench --baseline). As on that one, a handler that blocks holds the node's other
    # callbacks (the recogniser runs in a thread of its own; the simulated devices' espeak
    # calls block, as they did). rclpy's signal thread, which crashed both executors at a
    # launch's end, is off in every node (stop_signals.py).
    EXECUTOR: Callable = EventsExecutor
    stops: StopSignals | None = None  # run_node's: the process's SIGINT and SIGTERM
    _spinner = None  # the executor spin_once made

    def __init__(self, node_name: str = "", **kwargs) -> None:
        super().__init__(node_name or self.NAME, **kwargs)
        self.declare_node_parameters(self)
        check_required(self)

    @classmethod
    def declare_node_parameters(cls, node) -> None:
        """Declare the node's parameters on ``node`` (this node, or a list for ``--help``)."""

    def setup(self) -> None:
        """Attach publishers, subscriptions, services and timers (the second phase)."""

    def run(self) -> int | None:
        """Serve until shut down; the exit code (None: 0)."""
        while not self.stop_requested():
            self.spin_once(STOP_POLL)
        return None

    def spin_once(self, timeout_sec: float) -> None:
        """One turn of this node's executor (``EXECUTOR``, never rclpy's global one)."""
        if self._spinner is None:
            self._spinner = type(self).EXECUTOR(context=self.context)  # a factory is not bound
            self._spinner.add_node(self)
        stops = self.stops
        if stops is not None:  # a stop is seen by stop_requested() after the turn, not inside it
            stops.interrupting = False
        try:
            self._spinner.spin_once(timeout_sec=timeout_sec)
        finally:
            if stops is not None:
                stops.interrupting = True

    def stop_spinning(self) -> None:
        if self._spinner is not None:
            self._spinner.shutdown(timeout_sec=0)
            self._spinner = None

    def stop_requested(self) -> bool:
        """ROS is shut down, or SIGINT or SIGTERM arrived (also one rclpy did not see)."""
        return not self.context.ok() or (self.stops is not None and self.stops.arrived())

    def close(self) -> None:
        """Release what ``setup()`` took (files, locks); called once, also after a failure."""

    # No input kills a node: a callback that raises on a message or a request (a bug the
    # message revealed) is logged with its traceback, and the node goes on.
    def create_subscription(self, msg_type, topic, callback, qos_profile, **kwargs):
        def guarded(msg):
            try:
                callback(msg)
            except Exception:
                self.get_logger().error(
                    f"internal error on a message on {topic} (ignored): {traceback.format_exc()}"
                )

        kwargs.setdefault("event_callbacks", SubscriptionEventCallbacks(**NO_DEFAULT_EVENTS))
        return super().create_subscription(msg_type, topic, guarded, qos_profile, **kwargs)

    def create_timer(self, timer_period_sec, callback, *args, **kwargs):
        def guarded():
            try:
                callback()
            except Exception:
                if self.stop_requested():
                    return  # what a stop cut short (a publish after the context was shut down)
                raise

        return super().create_timer(timer_period_sec, guarded, *args, **kwargs)

    # rclpy gives every publisher and subscription two QoS-event handlers of its own (a warning
    # on an incompatible QoS or type), and its executor puts them all in the wait set on every
    # spin: left out, the server took 30.6% of a core under the camera stream instead of 35.9%
    # (bench camera, same hour). A mismatch is still reported: by the other end (ros2 topic
    # echo, any rclpy or rclcpp node keeps its own) and by `ros2 topic info -v`.
    def create_publisher(self, msg_type, topic, qos_profile, **kwargs):
        kwargs.setdefault("event_callbacks", PublisherEventCallbacks(**NO_DEFAULT_EVENTS))
        return super().create_publisher(msg_type, topic, qos_profile, **kwargs)

    def create_service(self, srv_type, srv_name, callback, **kwargs):
        def guarded(request, response):
            try:
                return callback(request, response)
            except Exception as e:
                self.get_logger().error(
                    f"internal error on a request to {srv_name}: {traceback.format_exc()}"
                )
                response = srv_type.Response()
                if hasattr(response, "error"):
                    response.error = f"internal error (nothing changed): {e!r}"[:1000]
                return response

        return super().create_service(srv_type, srv_name, guarded, **kwargs)


DEADLOCKED = 4  # the exit code of a node whose DDS participant Fast DDS deadlocked
CUT_OFF = 5  # ... of an agent its participant cut off from the DSR server (protocol/cut_off.py)
# a running node is ended only after its event thread has waited on a lock this long without
# running (a stop's teardown takes dds_deadlock.STALL: what it misjudges is only left undestroyed)
WATCH_STALL = 5.0


def _cut_off(node: DsrNode) -> Callable[[list[int]], None]:
    """What a node does when Fast DDS deadlocks its participant (dds_deadlock.py): its peers
    have dropped it and nothing brings it back, so it says why and ends at once, as if killed
    (its launch restarts it; what it stored is as durable as after a kill)."""

    def end(jammed: list[int]) -> None:
        if node.stop_requested():
            return  # a stop is under way: its teardown leaves the participant as it is
        node.get_logger().fatal(
            f"{dds_deadlock.describe(jammed, WATCH_STALL)}; exiting to be restarted"
        )
        exit_now(DEADLOCKED)

    return end


def run_node(make_node: Callable[[], DsrNode], args: list[str] | None = None) -> int:
    # a crash in C (rclpy, Fast DDS) writes the Python stacks to the node's log: seen once, a
    # panel's SIGSEGV at the end of a ros2 launch, with nothing to say where it was
    faulthandler.enable()
    set_private_umask()  # whatever the node writes is its user's alone
    process_gc.use_dsr_policy()
    stops = StopSignals().install()
    # rclpy's handlers shut the context down from a thread of theirs while the main thread
    # stops on the same signal (stop_signals.py): only the main thread stops ROS here
    rclpy.init(args=args, signal_handler_options=SignalHandlerOptions.NO)
    node: DsrNode | None = None
    DsrNode.stops = stops
    try:
        node = make_node()
        dds_deadlock.watch(_cut_off(node), stall=WATCH_STALL)
        node.setup()
        return node.run() or 0
    except (KeyboardInterrupt, ExternalShutdownException):
        return 0
    except Exception as e:
        # Whatever a SIGINT or SIGTERM caused (a wait cut short, a message's conversion
        # interrupted) is a stop, also before rclpy has shut the context down.
        if stops.arrived() or not rclpy.ok():
            return 0
        if not isinstance(e, (DsrError, ParameterException, OSError, ValueError)):
            raise
        name = getattr(make_node, "NAME", "") or "dsr"
        logger = node.get_logger() if node is not None else rclpy.logging.get_logger(name)
        logger.fatal(str(e))
        return 1
    finally:
        if node is not None:
            node.stop_spinning()
            node.close()
            with exit_if_stuck(TEARDOWN_LIMIT):  # the process ends here anyway
                dds_teardown.destroy_node(node)
        rclpy.try_shutdown()
        stops.uninstall()


def _own_arguments(args: list[str]) -> list[str]:
    """The arguments before ``--ros-args`` (the program name left out)."""
    own = args[1:]
    return own[: own.index("--ros-args")] if "--ros-args" in own else own


def main_for(node_class: type[DsrNode]) -> Callable[[list[str] | None], int]:
    """The console script's ``main`` of a node class."""

    def main(args: list[str] | None = None) -> int:
        argv = sys.argv if args is None else args
        own = _own_arguments(argv)
        if "-h" in own or "--help" in own:
            print(help_text(node_class, os.path.basename(argv[0]) if argv else node_class.NAME))
            return 0
        if own:
            print(
                f"{node_class.NAME}: unexpected argument(s) {' '.join(own)}; parameters are "
                "given as --ros-args -p name:=value (--help lists them)",
                file=sys.stderr,
            )
            return 2
        code = run_node(node_class, args)
        stopping_anyway()
        return code

    main.__doc__ = (
        f"Run {getattr(node_class, '__name__', 'the node')} until shut down; the exit code."
    )
    return main
