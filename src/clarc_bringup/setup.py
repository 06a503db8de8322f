import os
import xml.etree.ElementTree as ET
from glob import glob

from setuptools import setup

PACKAGE = "clarc_bringup"
HERE = os.path.dirname(os.path.abspath(__file__))
# The version is stated once, in package.xml.
VERSION = ET.parse(os.path.join(HERE, "package.xml")).getroot().findtext("version")
SHARE = "share/" + PACKAGE

setup(
    name=PACKAGE,
    version=VERSION,
    packages=[PACKAGE],
    # worlds/ and scenarios/ are links to the repository's folders: installed as files
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + PACKAGE]),
        (SHARE, ["package.xml"]),
        (SHARE + "/launch", glob("launch/*.launch.py")),
        (SHARE + "/worlds", glob("worlds/*.json")),
        (SHARE + "/scenarios", glob("scenarios/*.yaml")),
        (SHARE + "/policy", glob("policy/*.yaml")),
    ],
    install_requires=["setuptools"],
    zip_safe=False,
    description=ET.parse(os.path.join(HERE, "package.xml")).getroot().findtext("description"),
    license="Apache-2.0",
)
