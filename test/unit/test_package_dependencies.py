"""Each ROS package declares what its code imports (its package.xml, with rosdep keys), or, where
rosdep has no key, the import is in ros-pip-requirements.txt: so that `rosdep install` and that
one pip step give a normal Jazzy install everything `ros2 run` needs."""

import ast
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[2]
PACKAGES = ["dsr_graph", "clarc_agents", "clarc_sim"]
# import name -> rosdep key (ROS packages are their own key)
ROSDEP = {
    "numpy": "python3-numpy",
    "transforms3d": "python3-transforms3d",
    "yaml": "python3-yaml",
    "aiohttp": "python3-aiohttp",
    "jsonschema": "python3-jsonschema",
    "cryptography": "python3-cryptography",
    "nacl": "python3-nacl",
}
ROS_PACKAGES = {
    "rclpy",
    "std_msgs",
    "geometry_msgs",
    "rcl_interfaces",
    "builtin_interfaces",
    "visualization_msgs",
    "sensor_msgs",
    "tf2_msgs",
    "hri_msgs",
    "audio_common_msgs",
    "dsr_msgs",
    "ament_index_python",
    "rosidl_adapter",
    *PACKAGES,
}
PIP = {  # import name -> PyPI name
    "orjson": "orjson",
    "pyperplan": "pyperplan",
    "mcap": "mcap",
    "mcap_ros2": "mcap-ros2-support",
    "aiohttp_session": "aiohttp-session",
    "argon2": "argon2-cffi",
    "bvhio": "bvhio",
    "pocketsphinx": "pocketsphinx",
    "soxr": "soxr",
    "faster_whisper": "faster-whisper",
    "onnxruntime": "onnxruntime",
    "tokenizers": "tokenizers",
    "text_to_num": "text2num",
}


def imports_of(package: str) -> set[str]:
    """Top-level modules imported anywhere in the package's Python code, stdlib left out."""
    found = set()
    for path in (REPO / "src" / package / package).rglob("*.py"):
        if "node_modules" in path.parts:
            continue
        for node in ast.walk(ast.parse(path.read_text(), str(path))):
            if isinstance(node, ast.Import):
                found |= {alias.name.split(".")[0] for alias in node.names}
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                found.add(node.module.split(".")[0])
    return {name for name in found if name not in sys.stdlib_module_names} - {package}


def declared(package: str) -> set[str]:
    root = ET.parse(REPO / "src" / package / "package.xml").getroot()
    kinds = ("depend", "exec_depend", "build_export_depend")
    return {e.text.strip() for kind in kinds for e in root.iter(kind)}


def pip_listed() -> set[str]:
    lines = (REPO / "ros-pip-requirements.txt").read_text().splitlines()
    return {line.split("==")[0].strip() for line in lines if line.strip() and line[0] != "#"}


@pytest.mark.parametrize("package", PACKAGES)
def test_every_import_is_declared_or_a_documented_pip_step(package):
    keys = declared(package)
    for name in sorted(imports_of(package)):
        if name in PIP:
            assert PIP[name] in pip_listed(), f"{package} imports {name}: not in ros-pip-..."
            continue
        assert name in ROSDEP or name in ROS_PACKAGES, f"{package} imports {name}: no rosdep key"
        key = ROSDEP.get(name, name)
        assert key in keys, f"{package} imports {name} but its package.xml lacks <exec_depend>{key}"


def test_the_pip_list_holds_only_what_is_imported_and_pinned_as_in_requirements():
    from clarc_agents.asr.models import MODELS

    imported = set().union(*(imports_of(p) for p in PACKAGES))
    # found by the recognisers, not imported; a model in parts names every package of it
    weights = {p for m in MODELS for p in (m.package, *(more[0] for more in m.more))}
    assert pip_listed() == {PIP[name] for name in imported if name in PIP} | weights
    pinned = {
        line.split("#")[0].strip() for line in (REPO / "requirements.txt").read_text().splitlines()
    }
    for line in (REPO / "ros-pip-requirements.txt").read_text().splitlines():
        if line.strip() and not line.startswith("#"):
            assert line.strip() in pinned, f"{line} differs from requirements.txt"
