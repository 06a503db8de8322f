"""What a user runs around a test: the ``clarc`` command and the launch's monitor."""
