"""dsr_graph: the Deep State Representation graph model, its delta protocol and tools.

The model, formats, protocol and rules import no ROS; the ROS plumbing lives in ``ros/``, the
web in ``web/``, the ``dsr`` command in ``cli/`` (docs/explanation/architecture.md, "The house").
"""

from importlib.metadata import PackageNotFoundError, version

try:  # the version is stated once, in package.xml; setup.py copies it into the metadata
    __version__ = version("dsr_graph")
except PackageNotFoundError:
    __version__ = "unknown"
