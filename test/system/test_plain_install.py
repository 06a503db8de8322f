"""The normal ROS 2 path: dsr_graph built by colcon into a fresh install space *without*
--symlink-install (a copy, as `colcon build` on a Jazzy machine makes it), then the server and the
viewer run from that install, and the viewer's page and its assets (the cytoscape library
included) are served from the installed package."""

import os
import subprocess
import urllib.request
from pathlib import Path

import pytest

from browser import free_port
from ros_processes import wait_for

REPO = Path(__file__).resolve().parents[2]


TOKEN = "plain-install-token"


def fetch(url: str) -> tuple[int, bytes]:
    request = urllib.request.Request(url, headers={"Authorization": f"Bearer {TOKEN}"})
    try:
        with urllib.request.urlopen(request, timeout=5) as response:
            return response.status, response.read()
    except OSError:
        return 0, b""


@pytest.mark.timeout(300)
def test_a_plain_install_serves_the_viewer_with_its_assets(ros, tmp_path):
    build = subprocess.run(
        [
            "colcon",
            "--log-base",
            str(tmp_path / "log"),
            "build",
            "--base-paths",
            str(REPO / "src"),
            "--packages-select",
            "dsr_graph",
            "--build-base",
            str(tmp_path / "build"),
            "--install-base",
            str(tmp_path / "install"),
        ],
        capture_output=True,
        text=True,
        timeout=240,
        cwd=tmp_path,
    )
    assert build.returncode == 0, build.stdout[-3000:] + build.stderr[-3000:]
    prefix = tmp_path / "install" / "dsr_graph"
    site = next(prefix.glob("lib/python3*/site-packages"))
    assert not (site / "dsr_graph").is_symlink() and (site / "dsr_graph" / "web").is_dir()
    env = {"PYTHONPATH": f"{site}{os.pathsep}{os.environ.get('PYTHONPATH', '')}"}
    where = subprocess.run(
        [str(prefix / "lib" / "dsr_graph" / "dsr_server"), "--help"],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, **env},
    )
    assert where.returncode == 0 and "state_dir" in where.stdout, where.stderr
    imported = subprocess.run(
        ["python", "-c", "import dsr_graph.web.viewer_app as v; print(v.VENDOR)"],
        capture_output=True,
        text=True,
        timeout=60,
        env={**os.environ, **env},
    )
    assert str(site) in imported.stdout, imported.stdout + imported.stderr  # the copy runs

    ros.procs.start(
        "server",
        [
            str(prefix / "lib" / "dsr_graph" / "dsr_server"),
            "--ros-args",
            "-p",
            f"state_dir:={tmp_path / 'state'}",
            "-p",
            f"world_file:={REPO / 'worlds' / 'clarc_room.json'}",
        ],
        **env,
    )
    port = free_port()
    ros.procs.start(
        "viewer",
        [
            str(prefix / "lib" / "dsr_graph" / "dsr_viewer"),
            *("--ros-args", "-p", f"port:={port}", "-p", f"token:={TOKEN}"),
        ],
        **env,
    )
    url = f"http://127.0.0.1:{port}"
    wait_for(lambda: fetch(url + "/api/graph")[0] == 200, 60, "the installed viewer")
    status, page = fetch(url + "/")
    assert status == 200 and b"<html" in page.lower()
    for asset in ("/vendor/cytoscape.min.js", "/static/viewer.js", "/static/viewer.css"):
        status, body = fetch(url + asset)
        assert status == 200 and len(body) > 100, asset
