import os
import xml.etree.ElementTree as ET

from setuptools import find_packages, setup

PACKAGE = "dsr_graph"
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
        ("share/" + PACKAGE + "/config", ["config/fastdds_profile.xml"]),
    ],
    package_data={
        PACKAGE: [
            "data/*.json",
            "web/*.html",
            "web/*.js",
            "web/*.css",
            "web/package*.json",
            # the viewer's library, fetched by `npm ci` in web/ (scripts/setup.sh does it)
            "web/node_modules/cytoscape/dist/cytoscape.min.js",
        ]
    },
    entry_points={
        "console_scripts": [
            "dsr = dsr_graph.cli.main:main",
            "dsr_server = dsr_graph.ros.server_node:main",
            "dsr_rule_agent = dsr_graph.ros.rule_agent_node:main",
            "dsr_viewer = dsr_graph.ros.viewer_node:main",
            "dsr_recorder = dsr_graph.ros.recorder_node:main",
        ]
    },
    install_requires=["setuptools"],
    zip_safe=False,
    description=ET.parse(os.path.join(HERE, "package.xml")).getroot().findtext("description"),
    license="Apache-2.0",
)
