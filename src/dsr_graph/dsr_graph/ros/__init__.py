"""Everything that imports rclpy or ROS messages: the node shape and main, parameters, QoS, timers,
JSON topics, the agent runtime (``DsrAgent``), short-lived sessions, and the server, viewer and
rule-agent nodes."""
