"""What the Speech and Panel agents do when their rules fire, apart from ROS: the processes their
grammars name, and what happens when a device reports back. The nodes in ``nodes/`` connect
them to the devices' topics; tests run them on a ``LocalBus``."""
