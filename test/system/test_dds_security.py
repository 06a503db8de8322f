"""DDS security on these machines: the Fast DDS in the PyPI Jazzy wheels is built without its
security plugins, so a participant asked to enforce security cannot even be created. This test
pins that fact (docs/explanation/who-may-do-what.md, "DDS security"): if a future wheel has the
plugins, it fails, and the keystore, the enclaves and the test that an unauthenticated
participant cannot publish to dsr/transactions (issue 11) become possible."""

import os
import subprocess
import sys

from ros_processes import fresh_domain_id

PROBE = """
import rclpy
rclpy.init(args=["probe", "--ros-args", "--enclave", "/probe"])
try:
    rclpy.create_node("probe")
    print("SECURE NODE CREATED")
except Exception as e:
    print(e)
"""


def test_the_wheels_fast_dds_has_no_security_plugins(tmp_path):
    (tmp_path / "enclaves" / "probe").mkdir(parents=True)
    env = dict(
        os.environ,
        ROS_DOMAIN_ID=str(fresh_domain_id()),
        ROS_AUTOMATIC_DISCOVERY_RANGE="LOCALHOST",
        ROS_SECURITY_ENABLE="true",
        ROS_SECURITY_STRATEGY="Enforce",
        ROS_SECURITY_KEYSTORE=str(tmp_path),
    )
    done = subprocess.run(
        [sys.executable, "-c", PROBE], capture_output=True, text=True, timeout=60, env=env
    )
    out = done.stdout + done.stderr
    assert "SECURE NODE CREATED" not in out
    assert "This Fast DDS version doesn't have the security libraries" in out, out[-2000:]
