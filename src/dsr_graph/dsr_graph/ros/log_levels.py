"""Logging at a level named by pure code ("info", "warning", "error"). rclpy keeps one context
per calling line and refuses a second severity from the same line, so each level is called
from a line of its own, never through ``getattr(logger, level)``."""

from __future__ import annotations


def log_at(logger, level: str, message: str) -> None:
    if level == "error":
        logger.error(message)
    elif level == "warning":
        logger.warning(message)
    else:
        logger.info(message)
