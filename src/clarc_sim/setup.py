import os
import xml.etree.ElementTree as ET

from setuptools import find_packages, setup

PACKAGE = "clarc_sim"
HERE = os.path.dirname(os.path.abspath(__file__))
# The version is stated once, in package.xml.
VERSION = ET.parse(os.path.join(HERE, "package.xml")).getroot().findtext("version")

setup(
    name=PACKAGE,
    version=VERSION,
    packages=find_packages(exclude=["test", "test.*"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + PACKAGE]),
        ("share/" + PACKAGE, ["package.xml"]),
    ],
    package_data={PACKAGE: ["hospital/web/*.html", "hospital/web/*.js", "hospital/web/*.css"]},
    entry_points={
        "console_scripts": [
            "clarc = clarc_sim.console.clarc_cli:main",
            "tts = clarc_sim.devices.tts_node:main",
            "microphone = clarc_sim.devices.microphone_node:main",
            "touchscreen = clarc_sim.devices.touchscreen_node:main",
            "kinect = clarc_sim.devices.kinect_node:main",
            "patient = clarc_sim.patient.patient_node:main",
            "cgamed = clarc_sim.hospital.cgamed_node:main",
            "clarc_monitor = clarc_sim.console.monitor_node:main",
        ]
    },
    install_requires=["setuptools"],
    zip_safe=False,
    description=ET.parse(os.path.join(HERE, "package.xml")).getroot().findtext("description"),
    license="Apache-2.0",
)
