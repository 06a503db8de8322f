"""Every node of the suite has the one shape: its constructor only declares parameters (each with
a description) and attaches nothing; ``--help`` lists them with no side effect; a start-up
failure is one fatal line and exit code 1; SIGTERM while it waits for the server is a clean
stop."""

import importlib
import os
import signal
import subprocess
import time
from pathlib import Path

import pytest
import rclpy
from rclpy.context import Context
from rclpy.parameter import Parameter

from ros_processes import fresh_domain_id, wait_for

SRC = Path(__file__).resolve().parents[2] / "src"
NODES = [
    ("dsr_graph.ros.server_node", "DsrServer"),
    ("dsr_graph.ros.viewer_node", "Viewer"),
    ("dsr_graph.ros.rule_agent_node", "RuleAgentNode"),
    ("dsr_graph.ros.recorder_node", "Recorder"),
    ("clarc_agents.nodes.speech_node", "SpeechAgent"),
    ("clarc_agents.nodes.panel_node", "PanelAgent"),
    ("clarc_agents.nodes.person_node", "PersonAgent"),
    ("clarc_agents.nodes.pelea_node", "PeleaNode"),
    ("clarc_agents.nodes.gait_analyser_node", "GaitAnalyserNode"),
    ("clarc_agents.nodes.camera_node", "CameraAgent"),
    ("clarc_agents.nodes.asr_node", "AsrAgent"),
    ("clarc_sim.devices.tts_node", "TtsStandIn"),
    ("clarc_sim.devices.microphone_node", "MicrophoneStandIn"),
    ("clarc_sim.devices.touchscreen_node", "TouchscreenStandIn"),
    ("clarc_sim.devices.kinect_node", "KinectStandIn"),
    ("clarc_sim.patient.patient_node", "SimulatedPatient"),
    ("clarc_sim.hospital.cgamed_node", "CgamedStandIn"),
    ("clarc_sim.console.monitor_node", "Monitor"),
]


def test_every_console_script_node_is_listed_here():
    scripts = []
    for setup in SRC.glob("*/setup.py"):
        scripts += [
            line.split("=", 1)[1].strip().strip('",').split(":")[0]
            for line in setup.read_text().splitlines()
            if "_node:main" in line
        ]
    assert sorted(scripts) == sorted(module for module, _ in NODES)


@pytest.fixture
def context():
    ctx = Context()
    rclpy.init(context=ctx, domain_id=fresh_domain_id())
    try:
        yield ctx
    finally:
        rclpy.try_shutdown(context=ctx)


@pytest.mark.parametrize(("module", "name"), NODES)
def test_the_constructor_declares_and_attaches_nothing(module, name, context, monkeypatch):
    node_class = getattr(importlib.import_module(module), name)
    real_init = rclpy.node.Node.__init__

    required = [Parameter(n, value="given") for n in ("scenario", "grammar_file", "output")]

    def in_our_context(self, node_name, *args, **kwargs):  # the node classes take no context
        real_init(self, node_name, *args, context=context, parameter_overrides=required, **kwargs)

    monkeypatch.setattr(rclpy.node.Node, "__init__", in_our_context)
    node = node_class()
    try:
        assert not list(node.subscriptions) and not list(node.timers) and not list(node.clients)
        assert [p.topic_name for p in node.publishers] == ["/parameter_events"]
        ours = [
            n for n in node._parameters if n != "use_sim_time" and not n.startswith("qos_overrides")
        ]
        assert ours or name in ("TouchscreenStandIn",), f"{name} declares no parameter"
        for parameter in ours:
            assert node.describe_parameter(parameter).description, (
                f"{name}.{parameter} has no description"
            )
    finally:
        node.destroy_node()


def fatal_exit(procs, name, argv):
    proc = procs.start(name, argv)
    proc.wait(timeout=60)
    return proc.returncode, procs.log(name)


def test_a_second_server_on_a_locked_state_dir_ends_with_one_fatal_line(ros):
    state = ros.tmp / "state"
    ros.procs.start_server(state)
    wait_for(lambda: (state / "snapshot.json").exists(), 30, "the first server's state")
    code, log = fatal_exit(
        ros.procs,
        "second",
        ["dsr_server", "--ros-args", "-p", f"state_dir:={state}", "-r", "__node:=dsr_server_2"],
    )
    assert code == 1
    assert "Traceback" not in log
    fatal = [line for line in log.splitlines() if "FATAL" in line]
    assert len(fatal) == 1 and str(state) in fatal[0] and "in use" in fatal[0]


def test_a_corrupt_state_dir_ends_with_one_fatal_line(ros):
    state = ros.tmp / "state"
    state.mkdir()
    (state / "snapshot.json").write_text("{not json")
    code, log = fatal_exit(
        ros.procs, "corrupt", ["dsr_server", "--ros-args", "-p", f"state_dir:={state}"]
    )
    assert code == 1
    assert "Traceback" not in log
    fatal = [line for line in log.splitlines() if "FATAL" in line]
    assert len(fatal) == 1 and str(state) in fatal[0]


def test_a_state_dir_made_from_another_world_is_refused_unless_told_to_resume(ros):
    from conftest import CORTEX_WORLDS

    state = ros.tmp / "state"
    room = Path(__file__).resolve().parents[2] / "worlds" / "clarc_room.json"
    other = sorted(CORTEX_WORLDS.glob("*.json"))[0]
    ros.procs.start_server(state, room)
    wait_for(lambda: (state / "snapshot.json").exists(), 30, "the first server's state")
    ros.procs.stop("server")
    ros.procs.start_server(state, room, name="restart")  # the same world: a restart
    wait_for(lambda: "restored" in ros.procs.log("restart"), 30, "the restart")
    ros.procs.stop("restart")
    argv = ["dsr_server", "--ros-args", "-p", f"state_dir:={state}", "-p", f"world_file:={other}"]
    code, log = fatal_exit(ros.procs, "other", argv)
    assert code == 1 and "Traceback" not in log
    fatal = [line for line in log.splitlines() if "FATAL" in line]
    assert len(fatal) == 1 and str(room.resolve()) in fatal[0] and str(other.resolve()) in fatal[0]
    assert "resume:=true" in fatal[0]
    ros.procs.start("resumed", [*argv, "-p", "resume:=true"])
    wait_for(lambda: "restored" in ros.procs.log("resumed"), 30, "the resumed server")
    assert "going on with it (resume:=true)" in ros.procs.log("resumed")


def test_a_parameter_out_of_its_range_ends_the_node_naming_it(ros):
    code, log = fatal_exit(ros.procs, "kinect", ["kinect", "--ros-args", "-p", "rate_hz:=0.0"])
    assert code == 1 and "Traceback" not in log
    fatal = [line for line in log.splitlines() if "FATAL" in line]
    assert len(fatal) == 1 and "rate_hz" in fatal[0]


def test_a_bad_scenario_ends_the_patient_with_its_line(ros, tmp_path):
    bad = tmp_path / "bad.yaml"
    bad.write_text("patient: Carlos\nitems:\n  feeding: {answer: 7}\n")
    code, log = fatal_exit(
        ros.procs, "patient", ["patient", "--ros-args", "-p", f"scenario:={bad}"]
    )
    assert code == 1 and "Traceback" not in log
    assert f"{bad}:3" in log


SCRIPTS = {
    module: line.split("=", 1)[0].strip().strip('"')
    for setup in SRC.glob("*/setup.py")
    for line in setup.read_text().splitlines()
    if "_node:main" in line
    for module in [line.split("=", 1)[1].strip().strip('",').split(":")[0]]
}


@pytest.mark.parametrize(("module", "name"), NODES)
def test_help_lists_every_parameter_and_touches_nothing(module, name, tmp_path):
    node_class = getattr(importlib.import_module(module), name)
    env = dict(os.environ, XDG_STATE_HOME=str(tmp_path / "state"), HOME=str(tmp_path))
    env["XDG_DATA_HOME"] = str(tmp_path / "data")
    done = subprocess.run(
        [SCRIPTS[module], "--help"], capture_output=True, text=True, timeout=60, env=env
    )
    assert done.returncode == 0 and not done.stderr.strip(), done.stderr
    assert done.stdout.startswith(f"usage: {SCRIPTS[module]}")
    assert f"node name: {node_class.NAME}" in done.stdout
    from dsr_graph.ros.parameters import ParameterList

    listed = ParameterList(node_class.NAME)
    node_class.declare_node_parameters(listed)
    for declared in listed.declared:
        assert f"  {declared.name} (" in done.stdout
        assert declared.descriptor.description in done.stdout
    assert list(tmp_path.iterdir()) == [], "--help wrote files"


def test_an_unexpected_argument_is_named_and_nothing_starts():
    done = subprocess.run(["dsr_server", "world.json"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 2 and "unexpected argument(s) world.json" in done.stderr


@pytest.mark.parametrize(
    ("script", "parameter"),
    [("patient", "scenario"), ("dsr_rule_agent", "grammar_file"), ("dsr_recorder", "output")],
)
def test_a_missing_required_parameter_is_named(ros, script, parameter):
    code, log = fatal_exit(ros.procs, script, [script])
    assert code == 1 and "Traceback" not in log
    fatal = [line for line in log.splitlines() if "FATAL" in line]
    assert len(fatal) == 1 and f"parameter {parameter} is required" in fatal[0]


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT])
def test_a_stop_while_waiting_for_the_server_is_clean(ros, sig):
    proc = ros.procs.start("speech", ["speech"])  # no server in this domain: it waits
    # its node in the ROS graph: its stop handlers are in place (run_node installs them before
    # rclpy.init); a fixed sleep let a loaded machine's SIGINT land in its imports (exit -2)
    wait_for(
        lambda: "speech" in ros.session.node.get_node_names(), 60, "speech's node", ros.session
    )
    time.sleep(1.0)  # inside DsrAgent.setup's wait for the server (20 s)
    assert proc.poll() is None, ros.procs.log("speech")
    proc.send_signal(sig)
    proc.wait(timeout=30)
    assert proc.returncode == 0 and "Traceback" not in ros.procs.log("speech")


INTERRUPTED = """
import os, signal, sys
import rclpy
from dsr_graph.ros.dsr_node import DsrNode, main_for

class Interrupted(DsrNode):
    NAME = "interrupted"

    def setup(self):
        # rclpy's own handlers are off in every node: rclpy.ok() stays true after the signal
        assert rclpy.signals.get_current_signal_handlers_options().name == "NO"
        self.create_timer(0.2, self.tick)

    def tick(self):
        # What a launch's closing SIGINT did to the person and speech nodes: it landed while
        # rclpy's C++ code took a message, and the KeyboardInterrupt raised inside the message's
        # conversion came out of pybind as a RuntimeError.
        try:
            if {sig} is not None:
                os.kill(os.getpid(), {sig})  # its Python handler runs here (SIGINT's raises)
        except KeyboardInterrupt:
            pass
        raise RuntimeError("Unable to convert call argument '0' to Python object")

sys.exit(main_for(Interrupted)())
"""


@pytest.mark.parametrize("sig", ["signal.SIGINT", "signal.SIGTERM", None])
def test_an_error_a_stop_signal_caused_is_a_stop_and_any_other_a_crash(ros, sig):
    program = ros.tmp / "interrupted.py"
    program.write_text(INTERRUPTED.format(sig=sig))
    proc = ros.procs.start("interrupted", ["python", program])
    proc.wait(timeout=60)
    log = ros.procs.log("interrupted")
    if sig is None:
        assert proc.returncode == 1 and "Unable to convert call argument" in log, log
    else:
        assert proc.returncode == 0 and "Traceback" not in log, log


STOPPED = """
import os, signal, sys, time
from dsr_graph.ros.dsr_node import DsrNode, main_for

class Stopped(DsrNode):
    NAME = "stopped"

    def setup(self):
        raise KeyboardInterrupt  # stopped at once: its exit code is 0

code = main_for(Stopped)()
os.kill(os.getpid(), signal.{sig})  # launch's SIGTERM 5 s after its SIGINT, while it ends
time.sleep(0.5)
sys.exit(code)
"""


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_a_stop_signal_while_the_process_ends_keeps_its_exit_code(ros, sig):
    program = ros.tmp / "stopped.py"
    program.write_text(STOPPED.format(sig=sig))
    proc = ros.procs.start("stopped", ["python", program])
    proc.wait(timeout=60)
    assert proc.returncode == 0, ros.procs.log("stopped")


def test_setup_attaches_what_the_constructor_did_not(context):
    """The other half of the shape: setup() attaches the topics."""
    from clarc_sim.devices.microphone_node import MicrophoneStandIn

    real_init = rclpy.node.Node.__init__
    try:
        rclpy.node.Node.__init__ = lambda self, n, *a, **k: real_init(
            self, n, *a, context=context, **k
        )
        node = MicrophoneStandIn()
    finally:
        rclpy.node.Node.__init__ = real_init
    try:
        node.setup()
        assert [s.topic_name for s in node.subscriptions] == ["/clarc/sim/patient/voice"]
        assert "/clarc/asr" in [p.topic_name for p in node.publishers]
    finally:
        node.destroy_node()


MISSED = """
import signal, sys
from dsr_graph.ros.dsr_node import DsrNode, main_for

class Missed(DsrNode):
    NAME = "missed"

    def setup(self):
        # A stop whose KeyboardInterrupt is swallowed on the way (here: no handler raises it),
        # what a SIGINT during start-up did to nodes that then spun until launch killed them.
        signal.signal(signal.SIGINT, lambda *_: None)
        signal.signal(signal.SIGTERM, lambda *_: None)
        print("spinning", flush=True)

sys.exit(main_for(Missed)())
"""


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_spinning_node_stops_on_a_signal_whose_interrupt_was_swallowed(ros, sig):
    program = ros.tmp / "missed.py"
    program.write_text(MISSED)
    proc = ros.procs.start("missed", ["python", program])
    wait_for(lambda: "spinning" in ros.procs.log("missed"), 60, "the node to spin")
    proc.send_signal(sig)
    proc.wait(timeout=30)
    assert proc.returncode == 0 and "Traceback" not in ros.procs.log("missed")


WHOLE = """
import os, signal, sys, time
from dsr_graph.ros.dsr_node import DsrNode, main_for

class Whole(DsrNode):
    NAME = "whole"

    def setup(self):
        self.create_timer(0.2, self.tick)

    def tick(self):
        os.kill(os.getpid(), signal.{sig})  # arrives inside the callback
        time.sleep(0.2)  # Python runs the handler here: nothing may be raised
        print("the callback ran to its end", flush=True)

sys.exit(main_for(Whole)())
"""


@pytest.mark.parametrize("sig", ["SIGINT", "SIGTERM"])
def test_a_stop_never_tears_a_callback_in_half(ros, sig):
    """A stop that lands while a callback runs is seen after it (a transaction is never half
    applied); the events executor logged a KeyboardInterrupt raised there as FATAL."""
    program = ros.tmp / "whole.py"
    program.write_text(WHOLE.format(sig=sig))
    proc = ros.procs.start("whole", ["python", program])
    proc.wait(timeout=60)
    log = ros.procs.log("whole")
    assert proc.returncode == 0 and "the callback ran to its end" in log, log
    assert "FATAL" not in log and "Traceback" not in log, log
