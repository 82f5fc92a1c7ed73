"""The package version (one place; imports nothing, so every module may import it)."""
__version__ = "0.1.0"
