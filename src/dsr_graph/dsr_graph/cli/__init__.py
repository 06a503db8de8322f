"""``dsr``, the command line: ``main`` finds the verbs in ``verb/``; ``api/`` holds what they
share."""
