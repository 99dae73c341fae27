"""The exceptions and the warning category of gapack."""

from __future__ import annotations

__all__ = ["GapackError", "ConfigError", "InputError", "Interrupted", "GapackWarning"]


class GapackError(Exception):
    """A run that failed (a scene that cannot be packed, a file that cannot
    be written), and the base class of gapack's other errors."""


class ConfigError(GapackError, ValueError):
    """A config that is not valid, with where it is at fault.

    ``str(err)`` is the command line's one-line message,
    ``origin:line:column: key: reason`` (a scene over the ``[limits]`` ends
    with ``, or pass force=True to go ahead`` where the command line says
    ``--force``); the parts are attributes:
    ``origin`` (the file's path, ``<string>`` or ``<dict>``), ``line`` and
    ``column`` (from 1, in the TOML text; for a dict, in
    ``gapack.to_toml(config)``) and ``key`` (``domain.width``; ``None`` for
    some syntax errors).
    """

    def __init__(self, message, origin=None, line=None, column=None, key=None):
        super().__init__(message)
        self.origin = origin
        self.line = line
        self.column = column
        self.key = key


class InputError(GapackError, ValueError):
    """A request the config does not fit: ``gapack.optimise`` on a config
    without ``[optimise]``, a job that does not return one packing."""


class Interrupted(KeyboardInterrupt):
    """A run stopped by ``KeyboardInterrupt`` (Ctrl-C, the notebook's stop
    button) that had something to keep: ``result`` holds it (for pack,
    optimise and layer a ``Packing`` with ``interrupted`` true, also as
    ``packing``). A subclass of ``KeyboardInterrupt``: a script still stops."""

    def __init__(self, message, result=None):
        super().__init__(message)
        self.result = result

    @property
    def packing(self):
        """The best packing found before the stop (``result``)."""
        return self.result


class GapackWarning(UserWarning):
    """Something the user asked for that a run cannot or will not do (a
    table the job ignores, a target out of reach, a bent grading): the
    same sentences the command line prints as ``warning: …``."""
