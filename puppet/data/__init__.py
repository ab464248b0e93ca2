"""Loading and validating the data files: characters, scenes, interfaces, scripts."""

from puppet.data.errors import DataError

__all__ = ["DataError"]
