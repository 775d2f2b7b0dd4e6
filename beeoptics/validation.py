"""Checking input files against the JSON schemas shipped in ``beeoptics/schemas``.

A schema's ``default`` values are filled in while it is checked, and the
first violation is raised as an :class:`~beeoptics.errors.InputError`
naming the file and the dotted path of the offending field.
"""

import re
from functools import cache
from importlib import resources

import yaml
from jsonschema import Draft202012Validator, validators

from beeoptics.errors import InputError


def _with_defaults(cls):
    check_properties = cls.VALIDATORS["properties"]

    def properties(validator, props, instance, schema):
        if isinstance(instance, dict):
            for name, sub in props.items():
                if "default" in sub:
                    instance.setdefault(name, sub["default"])
        yield from check_properties(validator, props, instance, schema)

    return validators.extend(cls, {"properties": properties})


@cache
def _validator(schema_name):
    text = resources.files("beeoptics").joinpath("schemas", f"{schema_name}.schema.yaml").read_text()
    return _with_defaults(Draft202012Validator)(yaml.safe_load(text))


def _field(error):
    path = [str(p) for p in error.absolute_path]
    if error.validator == "additionalProperties":
        allowed = set(error.schema.get("properties", {}))
        path.append(sorted(set(error.instance) - allowed)[0])
    elif error.validator == "required":
        path.append(next(k for k in error.validator_value if k not in error.instance))
    return ".".join(path)


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
    if not isinstance(data, dict):
        raise InputError(path, "", "expected a mapping of keys to values")
    errors = sorted(_validator(schema_name).iter_errors(data), key=lambda e: list(e.absolute_path))
    if errors:
        raise InputError(path, _field(errors[0]), errors[0].message)
    return data


class _Loader(yaml.SafeLoader):
    """PyYAML's safe loader, reading floats as YAML 1.2 does (so that 1e6 is a number)."""


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
        raise InputError(path, "", f"not valid YAML: {e}") from None
