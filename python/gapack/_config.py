"""Configs from Python: a path, TOML text or a dict shaped like the TOML."""

from __future__ import annotations

import json
import math
import numbers
import os
import re
from collections.abc import Mapping
from typing import Any, Optional, Tuple

__all__ = ["load", "to_toml"]

_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def load(config: Any) -> Tuple[str, str, Optional[str]]:
    """The config's TOML text, its name in messages, and its path if it is a file.

    - a ``dict`` (any mapping) is written as TOML by :func:`to_toml`, named ``<dict>``;
    - an ``os.PathLike`` (``pathlib.Path``) is read, named by its path;
    - a ``str`` without a line break that names an existing file or ends in
      ``.toml`` is a path; any other ``str`` (or ``bytes``) is TOML text,
      named ``<string>``.
    """
    if isinstance(config, Mapping):
        return to_toml(config), "<dict>", None
    if isinstance(config, bytes):
        config = config.decode("utf-8")
    if isinstance(config, os.PathLike):
        return _read(os.fspath(config))
    if isinstance(config, str):
        if "\n" not in config and (config.endswith(".toml") or os.path.isfile(config)):
            return _read(config)
        return config, "<string>", None
    raise TypeError(
        f"config: expected a path, TOML text or a dict, got {type(config).__name__}"
    )


def _read(path: str) -> Tuple[str, str, str]:
    with open(path, encoding="utf-8") as f:
        return f.read(), path, path


def to_toml(config: Mapping) -> str:
    """``config``, a dict shaped like gapack's TOML, as TOML text.

    Tables are dicts, arrays of tables (``[[materials]]``) lists of dicts,
    everything else numbers, strings, booleans and (nested) lists of them;
    numpy scalars and arrays are taken as the numbers they hold. Keys keep
    their order, so the line and column of a ``ConfigError`` raised for a
    dict point into this text.
    """
    if not isinstance(config, Mapping):
        raise TypeError(f"config: expected a dict, got {type(config).__name__}")
    lines: list = []
    _table(lines, [], config, header=False)
    return "\n".join(lines) + "\n"


def _is_table_array(value: Any) -> bool:
    return (
        isinstance(value, (list, tuple))
        and len(value) > 0
        and all(isinstance(v, Mapping) for v in value)
    )


def _key(key: Any, path: list) -> str:
    if not isinstance(key, str):
        raise TypeError(f"{_dotted(path + [str(key)])}: keys must be strings, got {key!r}")
    return key if _BARE.match(key) else json.dumps(key, ensure_ascii=False)


def _dotted(path: list) -> str:
    return ".".join(path) if path else "config"


def _table(lines: list, path: list, table: Mapping, header: bool, array: bool = False) -> None:
    if header:
        if lines:
            lines.append("")
        name = ".".join(_key(k, path[:i]) for i, k in enumerate(path))
        lines.append(f"[[{name}]]" if array else f"[{name}]")
    nested = []
    for key, value in table.items():
        if isinstance(value, Mapping) or _is_table_array(value):
            nested.append((key, value))
        else:
            lines.append(f"{_key(key, path)} = {_value(value, path + [str(key)])}")
    for key, value in nested:
        _key(key, path)
        if isinstance(value, Mapping):
            _table(lines, path + [key], value, header=True)
        else:
            for item in value:
                _table(lines, path + [key], item, header=True, array=True)


def _value(value: Any, path: list) -> str:
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):
        value = value.tolist()  # numpy arrays and scalars
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, numbers.Integral):
        return str(int(value))
    if isinstance(value, numbers.Real):
        v = float(value)
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        text = repr(v)
        return text if any(c in text for c in ".en") else text + ".0"
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, Mapping):
        items = ", ".join(
            f"{_key(k, path)} = {_value(v, path + [str(k)])}" for k, v in value.items()
        )
        return "{" + items + "}"
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_value(v, path + [f"[{i}]"]) for i, v in enumerate(value)) + "]"
    raise TypeError(
        f"{_dotted(path)}: a config value must be a number, string, bool, list or dict, "
        f"got {type(value).__name__}"
    )
