"""dsr_graph: the Deep State Representation graph model, its delta protocol and tools.

The model, formats, protocol and rules import no ROS; the ROS plumbing lives in ``ros/``, the
web in ``web/``, the ``dsr`` command in ``cli/`` (docs/explanation/architecture.md, "The house").
"""


def __getattr__(name: str) -> str:
    # __version__ on first use: importlib.metadata costs every agent process 30-60 ms of CPU
    # at start-up, and only the recorder and the dsr command ask for it.
    if name != "__version__":
        raise AttributeError(f"module 'dsr_graph' has no attribute {name!r}")
    from importlib.metadata import PackageNotFoundError, version

    try:  # the version is stated once, in package.xml; setup.py copies it into the metadata
        return version("dsr_graph")
    except PackageNotFoundError:
        return "unknown"
