"""The console scripts every package's setup.py declares (what `ros2 pkg executables` lists and
the launch file may start), read from the sources."""

import re
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"


def console_scripts() -> dict[tuple[str, str], str]:
    """(package, executable) -> module, from every setup.py."""
    found = {}
    for setup in SRC.glob("*/setup.py"):
        for name, module in re.findall(r'"(\w+) = ([\w.]+):main"', setup.read_text()):
            found[(setup.parent.name, name)] = module
    return found
