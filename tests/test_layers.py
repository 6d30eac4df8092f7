"""The package's layers, checked on the imports of every module (parsed, not run).

Lowest first; a module may import from its own layer and the layers below it, never from one above. The
numerics (laws to the load path) import neither xarray nor matplotlib; only the figures import matplotlib.
"""

import ast
from pathlib import Path

import pytest

from conftest import ROOT

PACKAGE = ROOT / "src" / "capslide"
LAYERS = [
    ("version", "config", "config_rules", "params", "constants", "states"),  # parameters and typed states
    ("laws",),  # pure physics laws
    ("fem",),  # discretization
    ("solvers",),  # Newton, linear solvers
    ("model",),  # the bordered system and its setup
    ("loadpath",),  # continuation, the cap's legs, measures
    ("io",),  # files
    ("driver",),  # a case observed
    ("studies",),  # verification, stability, convergence, study expansion
    ("figures",),  # matplotlib
    ("cli", "api", "__main__", "__init__"),  # the command line, the Python interface and the package front
]
NUMERICS = ("laws", "fem", "solvers", "model", "loadpath")


def layer_of(name: str) -> int:
    top = name.split(".")[1] if "." in name else "__init__"
    for i, names in enumerate(LAYERS):
        if top in names:
            return i
    raise AssertionError(f"module {name} is in no layer: add its folder to LAYERS")


def module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" and len(parts) > 1 else parts)


def _is_module(name: str) -> bool:
    rel = Path(*name.split(".")[1:])
    return (PACKAGE / rel).with_suffix(".py").is_file() or (PACKAGE / rel / "__init__.py").is_file()


def imports(path: Path, name: str | None = None) -> list[str]:
    """Absolute names of everything a module imports (``from a import b`` counts as a.b when b is a module)."""
    name = name or module_name(path)
    package = name if path.name == "__init__.py" else name.rsplit(".", 1)[0]
    out = []
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            out += [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                anchor = package.split(".")
                anchor = anchor[: len(anchor) - node.level + 1]
                base = ".".join([*anchor, base] if base else anchor)
            for alias in node.names:
                full = f"{base}.{alias.name}"
                out.append(full if full.startswith("capslide.") and _is_module(full) else base)
    return out


MODULES = sorted(PACKAGE.rglob("*.py"))


def test_every_module_is_in_a_layer():
    assert len(MODULES) > 30
    for path in MODULES:
        layer_of(module_name(path))


def upward_imports(path: Path, name: str | None = None) -> list[str]:
    """The imports of a module that reach a higher layer than its own."""
    me = name or module_name(path)
    return [f"{me} (layer {layer_of(me)}) imports {t} (layer {layer_of(t)})" for t in imports(path, me)
            if (t == "capslide" or t.startswith("capslide.")) and layer_of(t) > layer_of(me)]


@pytest.mark.parametrize("path", MODULES, ids=[str(p.relative_to(PACKAGE)) for p in MODULES])
def test_no_module_imports_a_higher_layer(path):
    assert upward_imports(path) == []


@pytest.mark.parametrize("path", MODULES, ids=[str(p.relative_to(PACKAGE)) for p in MODULES])
def test_plotting_and_datasets_stay_in_their_layers(path):
    me = module_name(path)
    top = me.split(".")[1] if "." in me else ""
    third_party = {t.split(".")[0] for t in imports(path)}
    if top != "figures":
        assert "matplotlib" not in third_party, me
    if top in NUMERICS:
        assert not third_party & {"xarray", "netCDF4", "yaml", "snakemake"}, me


def test_the_check_sees_an_upward_import(tmp_path):
    """A model module that imports the driver, or the package's front, is caught."""
    planted = tmp_path / "planted.py"
    planted.write_text("from ..driver.case import run_case\nfrom .. import figures\nimport capslide.cli\n")
    found = upward_imports(planted, "capslide.model.planted")
    assert [f.split(" imports ")[1].split()[0] for f in found] == ["capslide.driver.case", "capslide.figures", "capslide.cli"]
