"""dsr_graph: the Deep State Representation graph model, its delta protocol and tools.

The model (graph, transactions, formats) imports no ROS; ROS plumbing lives in the node modules.
"""

from importlib.metadata import PackageNotFoundError, version

try:  # the version is stated once, in package.xml; setup.py copies it into the metadata
    __version__ = version("dsr_graph")
except PackageNotFoundError:
    __version__ = "unknown"
