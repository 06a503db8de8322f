"""The CLARC agents as ROS nodes: Speech, Panel and Person (each a grammar and its processes) and
PELEA (the executive connected to the DSR, CGAmed and the clinician)."""
