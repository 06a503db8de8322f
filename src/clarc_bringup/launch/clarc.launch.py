"""The whole CLARC suite on a ROS 2 Jazzy install, as ``scripts/launch.sh`` runs it here:

    ros2 launch clarc_bringup clarc.launch.py [scenario:=FILE] [time_scale:=0.1] [start:=true]
        [state_dir:=DIR] [db:=FILE] [viewer_port:=8080] [dashboard_port:=8081]
        [record:=FILE.mcap] [policy_file:=FILE.yaml] [keystore:=DIR] [security:=enforce]
        [discovery:=localhost]

Every node is respawned when it dies (``respawn=True``, as launch.sh supervises them); the
monitor prints the test read from the DSR and, when it exits (the test is finished, or it gave
up), the launch shuts down. With ``start:=true`` (the default) Start is pressed for the
scenario's patient (a request in the DSR, which PELEA takes whenever it runs); with
``start:=false`` press it on the clinician's dashboard. ``record:=FILE.mcap`` records the run
with dsr_recorder (it starts with the others here; launch.sh starts it first and stops it last).

The DSR's traffic is signed (docs/explanation/who-may-do-what.md): ``keystore:=DIR`` names a
keystore (``dsr keystore init/add``), made or completed with a key for every node of the suite; by
default a new one per launch under ``$XDG_STATE_HOME/dsr/keystores``. ``security:=permissive``
or ``off`` relaxes it. Discovery stays on this machine (``discovery:=localhost``, as launch.sh);
``discovery:=subnet`` opens it to a second host on the same network.
"""

from datetime import UTC, datetime

from launch import LaunchDescription
from launch.actions import (
    DeclareLaunchArgument,
    OpaqueFunction,
    SetEnvironmentVariable,
    Shutdown,
    UnsetEnvironmentVariable,
)
from launch.conditions import IfCondition, LaunchConfigurationNotEquals
from launch.substitutions import LaunchConfiguration, PathJoinSubstitution
from launch_ros.actions import Node
from launch_ros.substitutions import FindPackageShare

RESPAWN_DELAY = 0.5  # seconds, as launch.sh


def supervised(package: str, executable: str, **parameters) -> Node:
    """A node of the suite, respawned when it dies."""
    return Node(
        package=package,
        executable=executable,
        parameters=[parameters] if parameters else [],
        respawn=True,
        respawn_delay=RESPAWN_DELAY,
        output="screen",
    )


def press_start(context):
    """Start for the scenario's patient and test (read from the scenario file, as launch.sh
    does)."""
    from clarc_sim.patient.scenario import load

    scenario = load(LaunchConfiguration("scenario").perform(context))
    arguments = ["start", scenario.patient, "--test", scenario.test]
    arguments += ["--language", scenario.language]
    # named as the policy and the keystore know it
    return [Node(package="clarc_sim", executable="clarc", name="clarc_start", arguments=arguments)]


def speaker(context):
    """The robot's speaker, in the voice of the scenario's language (as launch.sh does)."""
    from clarc_sim.patient.scenario import load, voice_for

    language = load(LaunchConfiguration("scenario").perform(context)).language
    scale = LaunchConfiguration("time_scale")
    audio = LaunchConfiguration("audio")
    return [
        supervised("clarc_sim", "tts", time_scale=scale, audio=audio, voice=voice_for(language))
    ]


def secure(context):
    """The keystore of this launch (made or completed: every node of the suite a key) and the
    variables every node reads (DSR_KEYSTORE, DSR_SECURITY); nothing with security:=off."""
    from clarc_sim.console.suite_keystore import suite_keystore
    from dsr_graph.formats.default_paths import state_path

    mode = LaunchConfiguration("security").perform(context)
    if mode not in ("enforce", "permissive", "off"):
        raise ValueError(f"security:={mode}: it is enforce, permissive or off")
    if mode == "off":
        return [
            UnsetEnvironmentVariable("DSR_KEYSTORE"),
            SetEnvironmentVariable("DSR_SECURITY", mode),
        ]
    root = LaunchConfiguration("keystore").perform(context) or state_path(
        "dsr", f"keystores/{datetime.now(UTC).strftime('%Y%m%d-%H%M%S')}"
    )
    keystore = suite_keystore(root)
    return [
        SetEnvironmentVariable("DSR_KEYSTORE", str(keystore.root)),
        SetEnvironmentVariable("DSR_SECURITY", mode),
    ]


def discovery(context):
    """Who this launch's nodes find: this machine only (the default), or the subnet."""
    wanted = LaunchConfiguration("discovery").perform(context).upper()
    if wanted not in ("LOCALHOST", "SUBNET"):
        raise ValueError(f"discovery:={wanted.lower()}: it is localhost or subnet")
    return [SetEnvironmentVariable("ROS_AUTOMATIC_DISCOVERY_RANGE", wanted)]


def generate_launch_description() -> LaunchDescription:
    share = FindPackageShare("clarc_bringup")
    scale = LaunchConfiguration("time_scale")
    arguments = [
        DeclareLaunchArgument(
            "scenario",
            default_value=PathJoinSubstitution([share, "scenarios", "default.yaml"]),
            description="the patient's scenario (YAML)",
        ),
        DeclareLaunchArgument(
            "world_file",
            default_value=PathJoinSubstitution([share, "worlds", "clarc_room.json"]),
            description="the DSR's world when state_dir holds no graph yet",
        ),
        DeclareLaunchArgument(
            "policy_file",
            default_value=PathJoinSubstitution([share, "policy", "clarc.yaml"]),
            description="who may write what in the DSR (docs/FORMAT.md)",
        ),
        DeclareLaunchArgument("time_scale", default_value="0.1", description="0.1: 10x fast"),
        DeclareLaunchArgument(
            "state_dir", default_value="", description="the DSR's state (empty: per user)"
        ),
        DeclareLaunchArgument(
            "db", default_value="", description="CGAmed's results store (empty: per user)"
        ),
        DeclareLaunchArgument("viewer_port", default_value="8080"),
        DeclareLaunchArgument("dashboard_port", default_value="8081"),
        DeclareLaunchArgument("start", default_value="true", description="press Start"),
        DeclareLaunchArgument("timeout", default_value="600.0", description="seconds"),
        DeclareLaunchArgument(
            "record", default_value="", description="record the run to this MCAP file"
        ),
        DeclareLaunchArgument(
            "keystore", default_value="", description="the DSR's keystore (empty: a new one)"
        ),
        DeclareLaunchArgument(
            "security", default_value="enforce", description="enforce, permissive or off"
        ),
        DeclareLaunchArgument(
            "discovery", default_value="localhost", description="localhost, or subnet (2 hosts)"
        ),
        DeclareLaunchArgument(
            "camera_hz",
            default_value="0.0",
            description="the Kinect's colour and depth images a second, into the DSR (0: off)",
        ),
        DeclareLaunchArgument(
            "audio",
            default_value="false",
            choices=["true", "false"],
            description="the loop with sound: espeak-ng voices, the asr node (time_scale:=1.0)",
        ),
    ]
    nodes = [
        supervised(
            "dsr_graph",
            "dsr_server",
            world_file=LaunchConfiguration("world_file"),
            state_dir=LaunchConfiguration("state_dir"),
            policy_file=LaunchConfiguration("policy_file"),
        ),
        OpaqueFunction(function=speaker),
        supervised("clarc_sim", "microphone", time_scale=scale, audio=LaunchConfiguration("audio")),
        Node(
            package="clarc_agents",
            executable="asr",
            respawn=True,
            respawn_delay=RESPAWN_DELAY,
            output="screen",
            condition=IfCondition(LaunchConfiguration("audio")),
        ),
        supervised("clarc_sim", "touchscreen"),
        supervised(
            "clarc_sim", "kinect", time_scale=scale, camera_hz=LaunchConfiguration("camera_hz")
        ),
        Node(
            package="clarc_agents",
            executable="camera",
            respawn=True,
            respawn_delay=RESPAWN_DELAY,
            output="screen",
            condition=LaunchConfigurationNotEquals("camera_hz", "0.0"),
        ),
        supervised("clarc_agents", "person", time_scale=scale),
        supervised("clarc_agents", "gait_analyser", time_scale=scale),
        supervised("clarc_agents", "speech", time_scale=scale),
        supervised("clarc_agents", "panel", time_scale=scale),
        supervised("clarc_agents", "pelea", time_scale=scale),
        supervised(
            "clarc_sim", "patient", time_scale=scale, scenario=LaunchConfiguration("scenario")
        ),
        supervised("dsr_graph", "dsr_viewer", port=LaunchConfiguration("viewer_port")),
        supervised(
            "clarc_sim",
            "cgamed",
            db=LaunchConfiguration("db"),
            port=LaunchConfiguration("dashboard_port"),
        ),
        Node(
            package="dsr_graph",
            executable="dsr_recorder",
            parameters=[{"output": LaunchConfiguration("record")}],
            respawn=True,
            respawn_delay=RESPAWN_DELAY,
            output="screen",
            condition=LaunchConfigurationNotEquals("record", ""),
        ),
        Node(
            package="clarc_sim",
            executable="clarc_monitor",
            parameters=[
                {
                    "timeout": LaunchConfiguration("timeout"),
                    "since": datetime.now(UTC).isoformat(timespec="seconds"),
                }
            ],
            output="screen",
            on_exit=Shutdown(reason="the monitor ended: the test is finished or timed out"),
        ),
        OpaqueFunction(function=press_start, condition=IfCondition(LaunchConfiguration("start"))),
    ]
    # the suite's Fast DDS profile (dsr_graph/config): a node killed outright is noticed as gone
    # in 2 s, so its restarted self is not taken for a second node of that name; camera images
    # fit the shared-memory segment without pushing out the deltas sent beside them
    profile = SetEnvironmentVariable(
        "FASTRTPS_DEFAULT_PROFILES_FILE",
        PathJoinSubstitution([FindPackageShare("dsr_graph"), "config", "fastdds_profile.xml"]),
    )
    setting = [OpaqueFunction(function=secure), OpaqueFunction(function=discovery)]
    return LaunchDescription([profile, *arguments, *setting, *nodes])
