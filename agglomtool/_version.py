"""The package version: one definition, read by the package and by every record it writes."""

__version__ = "0.1.0"
