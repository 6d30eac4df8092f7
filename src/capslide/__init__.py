"""capslide: finite element simulations of adhesive friction of a soft cap on a rigid substrate.

Layers, lowest first (a module imports only from its own layer or lower ones; tests/test_layers.py checks it):
``config``/``params``/``states`` -> ``laws`` -> ``fem`` -> ``solvers`` -> ``model`` -> ``loadpath`` -> ``io`` ->
``driver`` -> ``studies`` -> ``figures`` -> ``cli`` and ``api`` (the Python interface, also as ``capslide.run`` etc.).
"""

from .version import __version__

API = ("load_config", "run", "open_case", "open_cases", "config_of", "collect", "slide", "to_si")
__all__ = ["__version__", *API]


def __getattr__(name: str):
    """The Python interface (:mod:`capslide.api`), imported on first use: the command line does not pay for it."""
    if name in API:
        from . import api

        return getattr(api, name)
    raise AttributeError(f"module 'capslide' has no attribute {name!r}")
