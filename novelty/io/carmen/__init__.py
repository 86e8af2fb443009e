"""CARMEN logs: laser scans and odometry, a line at a time, plain or gzipped (:mod:`novelty.io.carmen.log`)."""

from .log import CARMEN_MESSAGES, MAX_LINE, CarmenError, CarmenLog, read_carmen

__all__ = ["CarmenLog", "CarmenError", "read_carmen", "CARMEN_MESSAGES", "MAX_LINE"]
