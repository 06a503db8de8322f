import os
import xml.etree.ElementTree as ET

from setuptools import find_packages, setup

PACKAGE = "clarc_agents"
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
    package_data={
        PACKAGE: [
            "data/*.pddl",
            "grammars/*.yaml",
            "definitions/*.yaml",
            "definitions/*/*.yaml",
            "languages/*.yaml",
        ]
    },
    entry_points={
        "console_scripts": [
            "pelea = clarc_agents.nodes.pelea_node:main",
            "speech = clarc_agents.nodes.speech_node:main",
            "panel = clarc_agents.nodes.panel_node:main",
            "person = clarc_agents.nodes.person_node:main",
            "gait_analyser = clarc_agents.nodes.gait_analyser_node:main",
            "camera = clarc_agents.nodes.camera_node:main",
            "asr = clarc_agents.nodes.asr_node:main",
        ]
    },
    install_requires=["setuptools"],
    zip_safe=False,
    description=ET.parse(os.path.join(HERE, "package.xml")).getroot().findtext("description"),
    license="Apache-2.0",
)
