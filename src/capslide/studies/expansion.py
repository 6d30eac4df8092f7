"""One study expansion: a study spec -> its runs, each a run id and the config overrides that make it.

Five kinds of spec share it: the workflow's ``study`` section (models x preloads, case files
``{model}_Fn{preload:+.3f}``), the stability suite (``config/stability.yaml``), the convergence study
(``config/convergence.yaml``, run ids ``{case}/{run}``), the options study (``config/options.yaml``, run ids
``{model}_{option}``) and the experiment study (``config/experiment.yaml``, the options study's format). Every
spec is checked against its schema, and every run's configuration (the config files plus its overrides) is
validated, when the workflow is parsed: a bad key or value stops before any job runs, with one line naming the
spec, the run and the key.
"""

from __future__ import annotations

import functools
import hashlib
from collections.abc import Iterable, Mapping
from importlib import resources
from pathlib import Path
from typing import Any

import yaml

from ..config import (
    ConfigError,
    apply_settings,
    check_finite,
    check_schema,
    load_config,
    load_yaml,
    merge,
    scene_path,
    schema,
    validate,
)
from ..io.normal_state import normal_config
from ..model import cost
from ..params import Parameters
from . import convergence

__all__ = ["KINDS", "runs", "case_name", "check_runs", "shares_normal_state", "results_name"]

KINDS = ("study", "stability", "convergence", "options", "experiment")


@functools.cache
def _spec_schema(kind: str) -> dict:
    if kind == "study":  # the 'study' section of the configuration schema
        return schema()["properties"]["study"]
    text = resources.files("capslide.studies").joinpath("schemas", f"{kind}.schema.yaml").read_text()
    return yaml.safe_load(text)


def case_name(model: str, preload: float) -> str:
    """File stem of a study case: ``DI_Fn+0.000``."""
    return f"{model}_Fn{float(preload):+.3f}"


def _study_runs(spec: Mapping) -> dict[str, dict]:
    """Full slides for models x preloads, then slides to the onset of full sliding for models x onset_preloads."""
    out: dict[str, dict] = {}
    seen: dict[str, float] = {}
    for key, onset in (("preloads", False), ("onset_preloads", True)):
        for model, sets in spec.get("models", {}).items():
            for preload in spec.get(key, []):
                name = case_name(model, preload)
                if name in seen and seen[name] != float(preload):
                    raise ConfigError(f"study.{key}: preloads {seen[name]!r} and {float(preload)!r} both name the case "
                                      f"file {name}.nc (preloads must differ in the third decimal)")
                if name in out:
                    continue
                seen[name] = float(preload)
                out[name] = {**sets, "loading.preload": float(preload), **({"loading.stop_at_onset": True} if onset else {})}
    return out


def shares_normal_state(config: Mapping, overrides: Mapping[str, Any]) -> bool:
    """Whether a run of a study (``config`` plus ``overrides``) can start from the normal state of ``config`` at
    the run's ``loading.preload``: its other overrides leave the normal configuration as it is (they act only from
    the slide on; a model whose friction acts from the first contact preloads itself)."""
    sets = {key: value for key, value in overrides.items() if key != "loading.preload"}
    return normal_config(apply_settings(config, sets), completed=False) == normal_config(config, completed=False)


def _stability_runs(spec: Mapping) -> dict[str, dict]:
    cases = spec["cases"]
    for name, case in cases.items():
        if "pull_off_fraction" in case and "pull_off" not in cases:
            raise ConfigError(f"cases.{name}.pull_off_fraction needs a case named 'pull_off'")
    return {name: {**spec.get("base", {}), **case.get("set", {})} for name, case in cases.items()}


def _convergence_runs(spec: Mapping) -> dict[str, dict]:
    try:
        convergence.check_spec(spec)
    except ValueError as err:
        raise ConfigError(str(err)) from None
    out = {}
    for r in convergence.study_runs(spec):
        out[f"{r.case}/{r.run_id}"] = convergence.run_overrides(spec, r.case, r.sweep, r.value)
    return out


def _options_runs(spec: Mapping) -> dict[str, dict]:
    models, options = spec["models"], spec["options"]
    if spec["reference"] not in options:
        raise ConfigError(f"reference = {spec['reference']!r} is not one of the options ({', '.join(options)})")
    out = {}
    for option, o in options.items():
        for model in o.get("models", list(models)):
            if model not in models:
                raise ConfigError(f"options.{option}.models: {model!r} is not one of the models ({', '.join(models)})")
            out[f"{model}_{option}"] = {**spec.get("base", {}), **models[model], **o.get("set", {})}
    return out


_EXPANDERS = {"study": _study_runs, "stability": _stability_runs, "convergence": _convergence_runs,
              "options": _options_runs, "experiment": _options_runs}


def runs(spec: Mapping, kind: str) -> dict[str, dict[str, Any]]:
    """Run id -> config overrides (dotted key -> value) of every run of a spec of ``kind`` (see KINDS).

    The spec is checked against its schema first; ConfigError (one line) when it is bad.
    """
    if kind not in _EXPANDERS:
        raise ValueError(f"unknown kind of study {kind!r} (allowed: {', '.join(KINDS)})")
    if not isinstance(spec, Mapping):
        raise ConfigError(f"a {kind} spec must be a mapping, not {type(spec).__name__}")
    if kind == "study":  # the 'study' section of a configuration: keys named from the top
        check_finite({"study": spec})
        check_schema({"study": spec}, {"type": "object", "properties": {"study": _spec_schema(kind)}})
    else:
        check_finite(spec)
        check_schema(spec, _spec_schema(kind))
    return _EXPANDERS[kind](spec)


def check_runs(run_overrides: Mapping[str, Mapping], config_files: Iterable[str | Path], skip: Iterable[str] = (),
               settings: Mapping[str, Any] | None = None, libraries: bool = True) -> None:
    """Validate the configuration of every run (config files, ``settings``, then its overrides); ConfigError naming
    the run. ``libraries``: also refuse a run whose ``solver.factorization`` names a library this Python lacks (False
    for a study outside the default targets, whose rules the workflow reads on every run: its jobs refuse it)."""
    base: dict = {}
    for path in config_files:
        base = merge(base, load_yaml(path))
    base = apply_settings(base, settings or {})
    skip = set(skip)
    for run, sets in run_overrides.items():
        if run in skip:
            continue
        try:
            config = validate(apply_settings(base, sets))
            if libraries and config["solver"]["factorization"] != "superlu":  # a library this Python may lack
                cost.check_factorization(Parameters.from_config(config))
        except ConfigError as err:
            raise ConfigError(f"run {run}: {err}") from None


def results_name(config: Mapping[str, Any]) -> str:
    """The name of a workflow configuration's results folder: its preset when ``config`` (validated) is the packaged
    study (scene ``cap``) at that preset, else the preset and the first 8 hex digits of a SHA-256 of the
    configuration's YAML text, so that two configurations never share a folder."""
    preset = config.get("preset") or "custom"
    try:
        packaged = load_config([scene_path("cap")], settings={"preset": config.get("preset")})
    except ConfigError:
        packaged = None
    if dict(config) == packaged:
        return str(preset)
    digest = hashlib.sha256(yaml.safe_dump(dict(config), sort_keys=True).encode()).hexdigest()[:8]  # study included
    return f"{preset}-{digest}"
