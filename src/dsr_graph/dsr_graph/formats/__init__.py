"""Files: our JSON format (worlds, snapshots), CORTEX worlds, reading and writing world files,
the server's durable state (snapshot + journal), default paths. Pure: no ROS import."""
