"""Configuration files: load, merge, override, validate, fill defaults.

A configuration is a nested dict read from one or more YAML files (later
files update earlier ones), changed by dotted-key overrides
(``friction.s_cut=0``), completed by the chosen numerical ``preset`` (its
values fill only keys nothing else sets), then validated against ``config.schema.yaml`` (the
same file Snakemake validates with). Every problem is reported as a
:class:`ConfigError` whose message is one line naming the key, the value
and what is allowed.
"""

from __future__ import annotations

import copy
import difflib
import functools
import json
import math
import re
from collections.abc import Iterable, Mapping
from importlib import resources
from pathlib import Path
from typing import Any

import jsonschema
import yaml

__all__ = ["ConfigError", "SPHERE_ELEMENTS", "schema", "load_yaml", "merge", "apply_overrides", "apply_settings",
           "override_args", "retyped", "apply_preset", "check_schema", "check_finite", "validate", "load_config", "flatten"]


SPHERE_ELEMENTS = ("H1", "H2")  # mesh.element of the 3D sphere: trilinear or triquadratic hexahedra


class ConfigError(ValueError):
    """A bad configuration; the message is one line for the user."""


class _Loader(yaml.SafeLoader):
    """SafeLoader that also reads YAML 1.2 floats such as ``2e6`` as numbers, and refuses duplicate keys."""

    def construct_mapping(self, node, deep=False):
        seen = set()
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=deep)
            if key in seen:
                raise yaml.constructor.ConstructorError(None, None, f"duplicate key {key!r}", key_node.start_mark)
            seen.add(key)
        return super().construct_mapping(node, deep=deep)


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:[0-9][0-9_]*(?:\.[0-9_]*)?|\.[0-9_]+)(?:[eE][-+]?[0-9]+)?$|^[-+]?\.(?:inf|Inf|INF)$|^\.(?:nan|NaN|NAN)$"),
    list("-+0123456789."),
)
# integers keep their own (earlier, more specific) resolver
_Loader.yaml_implicit_resolvers = {
    k: sorted(v, key=lambda item: item[0] != "tag:yaml.org,2002:int") for k, v in _Loader.yaml_implicit_resolvers.items()
}


def _yaml_load(text: str):
    return yaml.load(text, Loader=_Loader)  # noqa: S506 (a SafeLoader subclass)


@functools.cache
def schema() -> dict:
    """The JSON schema of a configuration (packaged YAML file)."""
    text = resources.files("capslide").joinpath("config.schema.yaml").read_text()
    return yaml.safe_load(text)


def scenes() -> list[str]:
    """The names of the packaged scenes (``capslide/scenes/NAME.yaml``): complete configurations to start from."""
    folder = resources.files("capslide").joinpath("scenes")
    return sorted(p.name.removesuffix(".yaml") for p in folder.iterdir() if p.name.endswith(".yaml"))


def scene_path(name: str) -> Path:
    """The file of the packaged scene ``name``; ConfigError naming the scenes (and the closest one) otherwise."""
    if name not in scenes():
        close = difflib.get_close_matches(name, scenes(), n=1)
        hint = f"; did you mean '{close[0]}'?" if close else ""
        raise ConfigError(f"scene = {name!r} is not allowed: must be one of the packaged scenes ({', '.join(scenes())})"
                          f"{hint}")
    return Path(str(resources.files("capslide").joinpath("scenes", f"{name}.yaml")))


def _config_file(path: str | Path) -> Path:
    """``path`` itself, or the packaged scene it names: a bare name (no folder, no suffix) that is not a file here."""
    path = Path(path)
    if path.suffix == "" and path.parent == Path(".") and not path.exists():
        return scene_path(path.name)
    return path


def load_yaml(path: str | Path) -> dict:
    """Read one YAML mapping from ``path`` (or the packaged scene it names); errors name the file."""
    path = _config_file(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as err:
        raise ConfigError(f"cannot read config file '{path}': {err.strerror}") from None
    except UnicodeDecodeError:
        raise ConfigError(f"config file '{path}' is not a text (UTF-8) file") from None
    try:
        data = _yaml_load(text)
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        where = f" line {mark.line + 1}" if mark is not None else ""
        problem = getattr(err, "problem", None) or "invalid YAML"
        raise ConfigError(f"config file '{path}'{where}: {problem}") from None
    if data is None:
        return {}
    if not isinstance(data, dict):
        raise ConfigError(f"config file '{path}' must hold a mapping of sections, not {type(data).__name__}")
    return data


def merge(base: Mapping, update: Mapping) -> dict:
    """Recursive dict update: ``update`` wins, nested mappings are merged."""
    out = copy.deepcopy(dict(base))
    for key, value in update.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), Mapping):
            out[key] = merge(out[key], value)
        else:
            out[key] = copy.deepcopy(value)
    return out


def _parse_override(item: str) -> tuple[list[str], Any]:
    key, sep, text = item.partition("=")
    key = key.strip()
    if not sep or not key or any(not part for part in key.split(".")):
        raise ConfigError(f"override '{item}' must look like section.key=value")
    try:
        value = _yaml_load(text) if text.strip() else None
    except yaml.YAMLError:
        value = text
    return key.split("."), value


def _section(config: dict, path: list[str], what: str) -> dict:
    """The section holding dotted ``path``'s last key, created where missing; ``what`` names the source in errors."""
    node = config
    for part in path[:-1]:
        child = node.get(part)
        if child is None:
            child = node[part] = {}
        elif not isinstance(child, dict):
            raise ConfigError(f"{what}: '{part}' is a value, not a section")
        node = child
    return node


def apply_overrides(config: Mapping, overrides: Iterable[str]) -> dict:
    """Apply ``section.key=value`` overrides; values are parsed as YAML scalars."""
    out = copy.deepcopy(dict(config))
    for item in overrides:
        path, value = _parse_override(item)
        _section(out, path, f"override '{item}'")[path[-1]] = value
    return out


def apply_settings(config: Mapping, settings: Mapping[str, Any]) -> dict:
    """Set dotted keys to values: ``{"friction.s_cut": 0.5}`` (the typed form of :func:`apply_overrides`)."""
    out = copy.deepcopy(dict(config))
    for key, value in settings.items():
        path = str(key).split(".")
        if any(not part for part in path):
            raise ConfigError(f"setting '{key}' must be a dotted key like section.key")
        _section(out, path, f"setting '{key}'")[path[-1]] = copy.deepcopy(value)
    return out


def _override_text(value: Any) -> str:
    """YAML text that reads back as ``value``: plain for strings that need no quotes, JSON otherwise."""
    if isinstance(value, str):
        try:
            if _yaml_load(value) == value:
                return value
        except yaml.YAMLError:
            pass
    return json.dumps(value)


def retyped(value: Any) -> Any:
    """A value given as text (Snakemake's --config reads nested values as strings) read as YAML: '0.5' -> 0.5."""
    if isinstance(value, list):
        return [retyped(v) for v in value]
    if isinstance(value, Mapping):
        return {k: retyped(v) for k, v in value.items()}
    if not isinstance(value, str):
        return value
    try:
        return _yaml_load(value)
    except yaml.YAMLError:
        return value


def override_args(settings: Mapping[str, Any]) -> list[str]:
    """``key=value`` override strings (for ``--set``) whose values read back as the same YAML values."""
    return [f"{key}={_override_text(value)}" for key, value in settings.items()]


def _dotted(path: Iterable) -> str:
    """``section.key[2]`` from a path of keys and list indices."""
    text = ""
    for p in path:
        text += f"[{p}]" if isinstance(p, int) else (f".{p}" if text else str(p))
    return text or "<top level>"


def _allowed(spec: Mapping) -> str:
    """Describe what a schema node allows, for error messages."""
    if "enum" in spec:
        return "one of " + ", ".join(map(str, spec["enum"]))
    kind = spec.get("type", "value")
    kind = " or ".join(kind) if isinstance(kind, list) else kind
    bounds = []
    for word, sym in (("minimum", ">="), ("exclusiveMinimum", ">"), ("maximum", "<="), ("exclusiveMaximum", "<")):
        if word in spec:
            bounds.append(f"{sym} {spec[word]}")
    return f"{kind} {' and '.join(bounds)}".strip()


def _message(err: jsonschema.ValidationError) -> str:
    key = _dotted(err.absolute_path)
    spec = err.schema if isinstance(err.schema, Mapping) else {}
    if err.validator == "additionalProperties":
        allowed = sorted(spec.get("properties", {}))
        extra = sorted(set(err.instance) - set(allowed))
        where = f"{key}." if err.absolute_path else ""
        close = difflib.get_close_matches(str(extra[0]), allowed, n=1)
        hint = f"; did you mean '{where}{close[0]}'?" if close else ""
        return f"unknown key '{where}{extra[0]}' (allowed here: {', '.join(allowed)}){hint}"
    if err.validator == "required":
        missing = err.message.split("'")[1]
        where = f"{key}." if err.absolute_path else ""
        kind = "section" if not err.absolute_path else "key"
        return f"missing {kind} '{where}{missing}'"
    if err.validator == "type" and spec.get("type") == "object":
        return f"'{key}' must be a section (mapping of keys), got {err.instance!r}"
    return f"{key} = {err.instance!r} is not allowed: must be {_allowed(spec)}"


def _fill_defaults(config: dict, spec: Mapping) -> None:
    for name, sub in spec.get("properties", {}).items():
        if name not in config and "default" in sub:
            config[name] = copy.deepcopy(sub["default"])
        if isinstance(config.get(name), dict):
            _fill_defaults(config[name], sub)


def apply_preset(config: Mapping) -> dict:
    """Fill the keys of the chosen ``preset`` (a name in ``presets``) that the configuration does not set."""
    out = copy.deepcopy(dict(config))
    name = out.get("preset")
    if name is None:
        return out
    presets = out.get("presets") or {}
    if not isinstance(name, str) or not isinstance(presets, Mapping) or name not in presets:
        allowed = ", ".join(map(str, presets)) if isinstance(presets, Mapping) and presets else "none defined"
        raise ConfigError(f"preset = {name!r} is not allowed: must be one of the names in presets ({allowed})")
    values = presets[name]
    if not isinstance(values, Mapping):
        raise ConfigError(f"presets.{name} must be a mapping of dotted config keys to values, got {values!r}")
    for key, value in values.items():
        if isinstance(value, Mapping):
            raise ConfigError(f"presets.{name}.{key} must be a value: a preset maps dotted keys (mesh.size: 8) to values")
        path = str(key).split(".")
        _section(out, path, f"presets.{name}: '{key}'").setdefault(path[-1], copy.deepcopy(value))
    return out


def _non_finite(value, path: list) -> tuple[str, float] | None:
    """The dotted key and value of the first NaN or infinite number in a nested configuration, or None."""
    if isinstance(value, float) and not math.isfinite(value):
        return _dotted(path), value
    items = value.items() if isinstance(value, Mapping) else enumerate(value) if isinstance(value, list) else ()
    for key, item in items:
        found = _non_finite(item, [*path, key])
        if found:
            return found
    return None


def check_finite(instance, prefix: str = "") -> None:
    """Raise ConfigError naming the first NaN or +-inf anywhere in ``instance`` (no bound of a schema catches NaN)."""
    found = _non_finite(instance, [])
    if found:
        raise ConfigError(f"{prefix}{found[0]} = {found[1]!r} is not allowed: must be a finite number")


def check_schema(instance, spec: Mapping, prefix: str = "") -> None:
    """Raise ConfigError with a one-line message (``prefix`` first) for the shallowest violation of ``spec``."""
    errors = list(jsonschema.Draft202012Validator(spec).iter_errors(instance))
    if errors:
        # Report the shallowest problem first (a missing section before its keys).
        first = min(errors, key=lambda e: (len(e.absolute_path), _dotted(e.absolute_path)))
        raise ConfigError(prefix + _message(first))


def validate(config: Mapping) -> dict:
    """Validate against the schema, fill defaults, check cross-key rules.

    Returns a new, complete configuration; raises :class:`ConfigError`.
    """
    check_finite(config)
    out = apply_preset(config)
    check_schema(out, schema())
    _fill_defaults(out, schema())
    from .config_rules import check_consistency, derive_from_maugis_lambda, derive_mu_DI  # rules raise ConfigError

    derive_from_maugis_lambda(out)
    derive_mu_DI(out)
    check_consistency(out)
    return out


def load_config(paths: Iterable[str | Path], overrides: Iterable[str] = (),
                settings: Mapping[str, Any] | None = None) -> dict:
    """Read, merge (in order), change by ``settings`` (dotted key -> value) and ``overrides`` (``key=value``
    strings, applied last), and validate configuration files; a bare name (``"cap"``) is a packaged scene."""
    config: dict = {}
    for path in paths:
        config = merge(config, load_yaml(path))
    return validate(apply_overrides(apply_settings(config, settings or {}), overrides))


def flatten(config: Mapping, prefix: str = "", whole_below: Iterable[str] = ()) -> dict[str, Any]:
    """Flatten nested sections to ``{"section.key": value}`` (None kept); the entries of the sections named in
    ``whole_below`` stay whole (``study.models``: each model is a map of dotted keys, not a nested section)."""
    out: dict[str, Any] = {}
    whole_below = tuple(whole_below)
    for key, value in config.items():
        name = f"{prefix}{key}"
        if isinstance(value, Mapping) and prefix[:-1] not in whole_below:
            out.update(flatten(value, f"{name}.", whole_below))
        else:
            out[name] = value
    return out
