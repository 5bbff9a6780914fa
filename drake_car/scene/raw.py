"""Raw YAML against a schema: a scene's (or a car file's) keys and values walked before Drake's
``yaml_load_typed`` builds the dataclasses, so that a wrong key or value is reported with its
whole key path as one line (``SceneError``)."""

import dataclasses
import typing

from pydrake.common.yaml import yaml_load_typed

from drake_car.law.checks import excerpt, one_line
from drake_car.law.errors import InputError
from drake_car.scene.guard import YamlInputError


class SceneError(InputError):
    """A scene is malformed or asks for something impossible; the message names where, the key
    path, the value and what is allowed."""


def guarded(check, *args):
    try:
        return check(*args)
    except YamlInputError as e:
        raise SceneError(str(e)) from None


def typed(where, **kwargs):
    try:
        return yaml_load_typed(**kwargs)
    except Exception as e:  # what the raw check did not catch
        raise SceneError(f"{where}: {one_line(e)}") from None


def _fields(schema):
    if dataclasses.is_dataclass(schema):
        hints = typing.get_type_hints(schema)
        return {f.name: hints[f.name] for f in dataclasses.fields(schema)}
    return {f.name: f.type for f in getattr(schema, "__fields__", ())}


def _name(key):
    return key or "the scene"


def check_raw(data, schema, where, key):
    """Walks raw YAML ``data`` against ``schema``; raises SceneError at the first key whose
    value cannot be what the schema asks."""
    def fail(value, requirement):
        raise SceneError(f"{where}: {_name(key)} = {excerpt(value)} {requirement}")

    origin = typing.get_origin(schema)
    if origin is typing.Union:
        options = [t for t in typing.get_args(schema) if t is not type(None)]
        if data is None:
            if len(options) < len(typing.get_args(schema)):
                return
            fail(data, "must be given")
        if len(options) == 1:
            return check_raw(data, options[0], where, key)
        tag = data.get("_tag") if isinstance(data, dict) else None
        names = {t.__name__: t for t in options}
        if tag is None:
            return check_raw(data, options[0], where, key)
        if tag.lstrip("!") not in names:
            fail(tag, f"must be one of {', '.join('!' + n for n in names)}")
        body = {k: v for k, v in data.items() if k != "_tag"}
        return check_raw(body, names[tag.lstrip("!")], where, key)
    if origin in (list, typing.List):
        (item,) = typing.get_args(schema)
        if not isinstance(data, list):
            fail(data, "must be a list")
        for i, value in enumerate(data):
            check_raw(value, item, where, f"{key}[{i}]")
        return
    if schema is float:
        if isinstance(data, bool) or not isinstance(data, (int, float, str)):
            fail(data, "must be a number")
        if isinstance(data, str):
            try:
                float(data)
            except ValueError:
                fail(data, "must be a number")
        return
    if schema is bool:
        if not isinstance(data, bool):
            fail(data, "must be true or false")
        return
    if schema is str:
        if not isinstance(data, str):
            fail(data, "must be a string")
        return
    if schema is int:
        if isinstance(data, bool) or not isinstance(data, int):
            fail(data, "must be an integer")
        return
    fields = _fields(schema)
    if not fields and not dataclasses.is_dataclass(schema):
        return
    if data is None:
        return
    if not isinstance(data, dict):
        fail(data, f"must be a mapping of {', '.join(fields) or 'nothing'}")
    for name, value in data.items():
        if name == "_tag":
            fail(value, f"must not carry a tag ({schema.__name__} has no variants)")
        if name not in fields:
            inner = f"{key}.{name}" if key else name
            raise SceneError(f"{where}: unknown key {excerpt(inner)}"
                             + (f"; {_name(key)} has {', '.join(fields)}" if fields else ""))
        check_raw(value, fields[name], where, f"{key}.{name}" if key else name)
