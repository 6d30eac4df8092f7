"""The installed capslide version."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("capslide")
except PackageNotFoundError:  # running from a source tree without installation
    __version__ = "0+unknown"
