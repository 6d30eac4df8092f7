"""capslide: finite element simulations of adhesive friction of a soft cap on a rigid substrate.

Layers, lowest first (a module imports only from its own layer or lower ones; tests/test_layers.py checks it):
``config``/``params``/``states`` -> ``laws`` -> ``fem`` -> ``solvers`` -> ``model`` -> ``loadpath`` -> ``io`` ->
``driver`` -> ``studies`` -> ``figures`` -> ``cli``.
"""

from .version import __version__

__all__ = ["__version__"]
