"""The verbs of ``dsr``, one module each: ``HELP``, ``add_arguments(parser)``, ``run(args) -> int``,
and ``NAME`` when the verb's name is not the module's. Helpers they share: ``dsr_graph.cli.api``."""
