"""Checking input files against the JSON schemas shipped in ``beeoptics/io/schemas``.

A schema's ``default`` values are filled in while it is checked, and the
first violation is raised as an :class:`~beeoptics.io.errors.InputError`
naming the file and the dotted path of the offending field. The workflow's
configuration is checked the same way against its own schema
(:func:`validate_config`).
"""

import copy
import difflib
from collections.abc import Mapping
import math
import re
from functools import cache
from pathlib import Path

import yaml
from jsonschema import Draft202012Validator, validators

from beeoptics.io.errors import InputError

#: The schemas: the workflow's config, an eye class, a scene.
SCHEMAS = Path(__file__).parent / "schemas"
CONFIG_SCHEMA = SCHEMAS / "config.schema.yaml"


def _with_defaults(cls):
    check_properties = cls.VALIDATORS["properties"]

    def properties(validator, props, instance, schema):
        if isinstance(instance, dict):
            for name, sub in props.items():
                if "default" in sub and name not in instance:
                    # A copy: a mutable default ({} or []) must not be shared between files.
                    instance[name] = copy.deepcopy(sub["default"])
        yield from check_properties(validator, props, instance, schema)

    return validators.extend(cls, {"properties": properties})


@cache
def _validator(schema_name):
    return _schema_validator(SCHEMAS / f"{schema_name}.schema.yaml")


@cache
def _schema_validator(schema_path):
    text = Path(schema_path).read_text()
    return _with_defaults(Draft202012Validator)(yaml.load(text, Loader=yaml.CSafeLoader))


def _field_and_message(error):
    """The dotted path of the offending field, and what is wrong with it."""
    path = [str(p) for p in error.absolute_path]
    message = error.message
    extra = []
    if error.validator == "additionalProperties" and error.validator_value is False:
        allowed = sorted(error.schema.get("properties", {}))
        extra = sorted(map(str, set(error.instance) - set(allowed)))
    if extra:
        key = extra[0]
        path.append(key)
        close = difflib.get_close_matches(key, allowed, n=1)
        message = f"unknown key {key!r}; " + (
            f"did you mean {close[0]!r}?" if close else f"allowed here: {', '.join(allowed)}"
        )
    elif error.validator == "required":
        path.append(next(k for k in error.validator_value if k not in error.instance))
    elif error.validator in ("type", "oneOf", "minProperties", "maxProperties") and "title" in error.schema:
        # A value of the wrong kind or shape is told what the field takes (the schema's title names it).
        message = f"{error.instance!r} is not {error.schema['title']}"
    return ".".join(path), message


def _non_finite(data, path=()):
    """The dotted path of the first NaN or infinite number in parsed YAML, or None.

    JSON Schema's bounds do not catch NaN (every comparison with it is
    false), and YAML reads ``.nan`` and ``.inf`` as numbers.
    """
    if isinstance(data, float) and not math.isfinite(data):
        return ".".join(path)
    items = data.items() if isinstance(data, dict) else enumerate(data) if isinstance(data, list) else ()
    for key, value in items:
        found = _non_finite(value, (*path, str(key)))
        if found is not None:
            return found
    return None


def _check(data, validator, path):
    if not isinstance(data, dict):
        raise InputError(path, "", "expected a mapping of keys to values")
    errors = sorted(validator.iter_errors(data), key=lambda e: [(isinstance(k, str), k) for k in e.absolute_path])
    if errors:
        raise InputError(path, *_field_and_message(errors[0]))
    field = _non_finite(data)
    if field is not None:
        raise InputError(path, field, "must be a finite number, not NaN or infinity")
    return data


def validate(data, schema_name, path):
    """Check ``data`` against a packaged schema, filling in defaults in place.

    Parameters
    ----------
    data : dict
        Parsed file contents.
    schema_name : str
        ``"eye"`` or ``"scene"``.
    path : str or Path
        The file the data came from, for the error message.

    Raises
    ------
    InputError
    """
    return _check(data, _validator(schema_name), path)


@cache
def _config_defaults():
    return validate_config({}, CONFIG_SCHEMA, folders=False)


def config_defaults():
    """The workflow's config with every default filled in from :data:`CONFIG_SCHEMA`, a fresh copy.

    The one source of every default: the workflow, the command line and the
    library's functions (their keyword defaults) all read it, so that each
    door gives the same result.
    """
    return copy.deepcopy(_config_defaults())


def config_default(key):
    """The default of one config key, dotted (``"colour.background"``), from :func:`config_defaults`."""
    value = _config_defaults()
    for part in key.split("."):
        value = value[part]
    return copy.deepcopy(value)


#: Where each list of classes in the config finds its folders, and the file each folder holds.
CONFIG_FOLDERS = {"eyes": ("eyes_dir", "eye.yaml"), "scenes": ("scenes_dir", "scene.yaml")}


def validate_config(config, schema_path, source="config", folders=True, overrides=None):
    """Check the workflow's configuration, filling in defaults in place.

    The same check as the packaged schemas get: the first violation of
    ``schema_path`` (:data:`CONFIG_SCHEMA`) as one line naming ``source``
    (or "command line", for a key the command line set) and the dotted key,
    with a suggestion for a misspelt key; then, with ``folders``, that every
    eye class and scene named, in the run or in a sweep, has its folder, and
    that a named adapting background is a material of each scene, so that a
    typo stops the run before any job starts. Relative folders are taken
    from the working directory, as the rules take them.

    The extras, flights, polarisation and detection, are then narrowed to
    the run's ``eyes`` and ``scenes`` (:func:`within_run`), and what those
    that run need is checked. In an extra, a name that no folder holds is
    taken for another folder's (the default flight's meadow, in a run of
    your own scenes) unless it is close to one that is (a misspelling).

    Snakemake reads the values of a nested ``--config`` mapping as text
    (``--config trace='{parts: 16}'`` gives ``"16"``): text where the schema
    wants a number is read as one first.

    Parameters
    ----------
    config : dict
        The merged configuration (Snakemake's ``config``).
    schema_path : str or Path
    source : str or Path
        The config file(s), for the error message.
    overrides : mapping, optional
        What the command line set (Snakemake's ``--config``).

    Raises
    ------
    InputError
    """
    validator = _schema_validator(Path(schema_path))
    _numbers_from_text(config, validator.schema)
    try:
        _check(config, validator, source)
        if folders:
            _check_names(config, source)
        within_run(config)
        if folders:
            _check_folders(config, source)
    except InputError as e:
        if overrides and _sets(overrides, e.field):
            raise InputError("command line (--config)", e.field, str(e).removeprefix(f"{e.path}: {e.field}: ")) \
                from None
        raise
    return config


def within_run(config):
    """Narrow the extras to the run's eyes and scenes, in place.

    A user asking for the drone in the meadow gets the drone in the meadow:
    a flight runs for those of its eyes that are among ``eyes``, and only if
    its scene is among ``scenes`` (and not at all if set to null); polarisation, the detection survey and
    navigation run for their eyes and scenes that are in the run (both or neither). Sweeps
    and the comparison name what they run on their own.
    """
    eyes, scenes = config["eyes"], config["scenes"]
    config["flights"] = {name: {**flight, "eyes": [e for e in flight["eyes"] if e in eyes]}
                         for name, flight in config["flights"].items()
                         if flight is not None and flight["scene"] in scenes and set(flight["eyes"]) & set(eyes)}
    for key in ("polarisation", "detection", "navigation"):
        section = config[key]
        kept = [e for e in section["eyes"] if e in eyes], [s for s in section["scenes"] if s in scenes]
        section["eyes"], section["scenes"] = kept if all(kept) else ([], [])
    return config


def _numbers_from_text(data, schema):
    """Read text as a number, in place, wherever the schema wants a number or an integer, and "null" as
    null where it allows null."""
    if isinstance(data, dict):
        for key, value in data.items():
            sub = schema.get("properties", {}).get(key) or schema.get("additionalProperties")
            if isinstance(sub, dict):
                kind = sub.get("type", ())
                if value == "null" and "null" in kind:
                    data[key] = None
                elif isinstance(value, str) and (kind in ("integer", "number") or "number" in kind):
                    # A type that is a list ("number or the word auto") reads text as a number where it is one.
                    data[key] = _number(value, kind if kind == "integer" else "number")
                else:
                    _numbers_from_text(value, sub)
    elif isinstance(data, list) and isinstance(schema.get("items"), dict):
        items = schema["items"]
        for k, item in enumerate(data):
            # A list's numbers too (a sweep's values: --config sweeps='{s: {delta_rho_deg: [1.5, 4]}}').
            if isinstance(item, str) and items.get("type") in ("integer", "number"):
                data[k] = _number(item, items["type"])
            else:
                _numbers_from_text(item, items)


def _number(text, kind):
    """``text`` as an int or a float if it is one, else unchanged (the schema then names it)."""
    for parse in ((int,) if kind == "integer" else (int, float)):
        try:
            return parse(text)
        except ValueError:
            continue
    return text


def _sets(overrides, field):
    """Whether the dotted ``field`` lies within what ``overrides`` set."""
    node = overrides
    for part in field.split("."):
        if isinstance(node, Mapping) and part in node:
            node = node[part]
        elif isinstance(node, (list, tuple)) and part.isdigit():
            return True
        else:
            return False
    return True


#: The config's sections that run only for the run's eyes and scenes (:func:`within_run`).
EXTRAS = ("flights.", "polarisation.", "detection.")


def _check_names(config, source):
    """Every eye class and scene named has its folder: in an extra, a name no folder holds is another
    folder's (not in this run) unless it is close to one that is (a misspelling)."""
    for key, (dir_key, filename) in CONFIG_FOLDERS.items():
        root = Path(config[dir_key])
        named = [(f"{key}.{i}", n) for i, n in enumerate(config[key])]
        named += [(f"sweeps.{s}.{key}.{i}", n) for s, sweep in config.get("sweeps", {}).items()
                  for i, n in enumerate(sweep.get(key, []))]
        named += [(f"flights.{f}.eyes.{i}", n) if key == "eyes" else (f"flights.{f}.scene", n)
                  for f, flight in config.get("flights", {}).items() if flight is not None
                  for i, n in enumerate(flight["eyes"] if key == "eyes" else [flight["scene"]])]
        named += [(f"polarisation.{key}.{i}", n) for i, n in enumerate(config["polarisation"][key])]
        named += [(f"comparison.eyes.{i}", n) for i, n in enumerate(config["comparison"]["eyes"] if key == "eyes"
                                                                      else [])]
        named += [(f"detection.{key}.{i}", n) for i, n in enumerate(config["detection"][key])]
        for field, name in named:
            if not (root / name / filename).is_file():
                found = sorted(p.parent.name for p in root.glob(f"*/{filename}"))
                close = difflib.get_close_matches(name, found, n=1)
                if field.startswith(EXTRAS) and not close:
                    continue
                raise InputError(
                    source, field,
                    f"no {key[:-1]} {name!r}: {root / name / filename} does not exist "
                    f"({dir_key} {str(root)!r} holds {', '.join(found) or 'none'})"
                    + (f"; did you mean {close[0]!r}?" if close else ""),
                )


def _check_folders(config, source):
    """What the run's extras need is there, and a named background is a material of each scene."""
    for i, name in enumerate(config["polarisation"]["eyes"]):
        eye = load_yaml(Path(config["eyes_dir"]) / name / "eye.yaml")
        if not isinstance(eye, dict) or "dorsal_rim" not in eye:
            raise InputError(source, f"polarisation.eyes.{i}",
                             f"the eye {name!r} has no dorsal rim area (a dorsal_rim section in its eye.yaml), "
                             "which the polarisation stages need")
    for i, name in enumerate(config["detection"]["scenes"]):
        if not (Path(config["scenes_dir"]) / name / "meadow.yaml").is_file():
            raise InputError(source, f"detection.scenes.{i}", f"the scene {name!r} has no meadow.yaml: the survey "
                             "approaches a generated meadow's flowers")
    root = Path(config["scenes_dir"])
    for name, flight in config.get("flights", {}).items():
        if not (root / flight["scene"] / flight["path"]).is_file():
            raise InputError(source, f"flights.{name}.path",
                             f"no flight {root / flight['scene'] / flight['path']} (the path is relative to the "
                             "scene's folder)")
    scenes = [*config["scenes"], *(n for sweep in config.get("sweeps", {}).values() for n in sweep["scenes"])]
    for name in dict.fromkeys(scenes):
        check_background(root / name / "scene.yaml", config["colour"]["background"], source, "colour.background")


def check_background(scene_file, background, source, field):
    """Refuse a named adapting background that is not a material of the scene.

    ``"scene"`` (the scene's mean) is always there. The error names
    ``source`` and ``field``: the config key that asked for it, or the scene file.
    """
    if background == "scene":
        return
    scene = load_yaml(scene_file)
    materials = (scene.get("materials") if isinstance(scene, dict) else None) or {}
    if background not in materials:
        raise InputError(source, field, f"no material {background!r} in {scene_file} "
                         f"(its materials: {', '.join(materials) or 'none'})")


class _Loader(yaml.CSafeLoader):
    """PyYAML's safe loader, reading floats as YAML 1.2 does (so that 1e6 is a number).

    LibYAML's parser, not PyYAML's own: the same documents, parsed ten times as fast (every
    workflow job reads its config, eyes, scenes and their schemas).
    """


_Loader.add_implicit_resolver(
    "tag:yaml.org,2002:float",
    re.compile(r"^[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?$|^[-+]?\.(?:inf|Inf|INF)$|^\.(?:nan|NaN|NAN)$"),
    list("-+0123456789."),
)


def load_yaml(path):
    """Parse a YAML file, turning a missing file or a syntax error into an InputError."""
    try:
        with open(path) as f:
            return yaml.load(f, Loader=_Loader)
    except FileNotFoundError:
        raise InputError(path, "", "no such file") from None
    except yaml.YAMLError as e:
        mark = getattr(e, "problem_mark", None)
        where = f"line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(e, "problem", None) or " ".join(str(e).split())
        raise InputError(path, where, f"not valid YAML: {problem}") from None
    except UnicodeDecodeError:
        raise InputError(path, "", "not valid YAML: not a text file") from None
