"""CLARC's bringup: the launch file (launch/clarc.launch.py), the worlds and the scenarios,
installed in share/clarc_bringup by the package build."""
