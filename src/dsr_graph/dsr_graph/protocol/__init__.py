"""How the DSR server and its agents talk, without ROS: the server core (validate, apply, number),
the replica an agent keeps, the history a viewer keeps, read-only queries, readable delta text,
topic names, and a whole DSR in one process (``local_bus``) for tests."""
