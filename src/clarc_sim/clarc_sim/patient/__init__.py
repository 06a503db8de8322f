"""The simulated patient: the scenario file, the script that decides what the patient does, and
the node that does it through the stand-in devices."""
