"""gapack: dense 2D disk packings for DEM simulations, from Python.

The same jobs as the ``gapack`` command line and service, on the same
library: a config (a path, TOML text, or a dict shaped like the TOML) in,
a :class:`Packing` out, its disks as numpy arrays and its files written on
demand, byte for byte as the command line writes them for the same config
and seed.

>>> import gapack
>>> p = gapack.pack({"domain": {"shape": "rectangle", "width": 20, "height": 10},
...                  "grading": {"uniform": [1.0, 2.0]}}, seed=1)
>>> p.x.dtype, len(p) == p.summary["particles"]
(dtype('float64'), True)

Runs release the GIL; ``KeyboardInterrupt`` (Ctrl-C, the notebook's stop
button) stops a run through the job's cancel token within milliseconds and
raises :class:`Interrupted` holding the best packing found (or returns it,
with ``on_interrupt="return"``). Errors are :class:`GapackError`\\ s; a bad
config raises :class:`ConfigError` with ``line``, ``column`` and ``key``.
"""

from __future__ import annotations

import os
import sys
import warnings
from typing import Any, Callable, Iterable, Optional

import numpy as np

from . import _gapack
from ._config import load as _load
from ._config import to_toml
from ._errors import ConfigError, GapackError, GapackWarning, InputError, Interrupted
from ._gapack import Packing
from ._notebook import Summary

__version__ = _gapack.__version__

#: Every output format ``Packing.write(formats=…)`` and ``[output] formats`` know.
FORMATS = tuple(_gapack.FORMATS)

__all__ = [
    "pack",
    "optimise",
    "optimize",
    "layer",
    "validate",
    "verify",
    "run",
    "to_toml",
    "Packing",
    "Summary",
    "FORMATS",
    "GapackError",
    "ConfigError",
    "InputError",
    "Interrupted",
    "GapackWarning",
]


def pack(
    config: Any,
    seed: Optional[int] = None,
    *,
    force: bool = False,
    progress: Optional[bool] = None,
    on_interrupt: str = "raise",
) -> Packing:
    """Pack the config's scene (``gapack pack``) and return the packing.

    ``config``: a path, TOML text or a dict shaped like the TOML. ``seed``
    overrides the config's. ``force`` goes ahead past ``[limits]``.
    ``progress``: a tqdm bar for large packs (``None``: when tqdm is
    installed and the run is shown in a terminal or a notebook).
    ``on_interrupt``: on ``KeyboardInterrupt``, ``"raise"`` :class:`Interrupted`
    holding what was finished, or ``"return"`` it.
    """
    return _job("pack", config, seed, None, force, progress, on_interrupt)


def optimise(
    config: Any,
    seed: Optional[int] = None,
    on_generation: Optional[Callable[[dict], Any]] = None,
    *,
    force: bool = False,
    progress: Optional[bool] = None,
    on_interrupt: str = "raise",
) -> Packing:
    """Search for the config's ``[optimise]`` target porosity (``gapack
    optimise``) and return the best packing; ``Packing.history`` holds the
    convergence.

    ``on_generation(gen)`` is called after each generation with a dict:
    ``stage`` (``"optimise"``, or ``"layering"`` when the config lays
    materials out after), ``index`` (0 is the initial population), ``best``,
    ``feasible``, ``mean``, ``worst``, ``evaluations``, ``seconds``. An
    exception it raises stops the search and is raised. Other arguments as
    :func:`pack`.
    """
    return _job("optimise", config, seed, on_generation, force, progress, on_interrupt)


optimize = optimise


def layer(
    config: Any,
    seed: Optional[int] = None,
    on_generation: Optional[Callable[[dict], Any]] = None,
    *,
    force: bool = False,
    progress: Optional[bool] = None,
    on_interrupt: str = "raise",
) -> Packing:
    """Pack the scene and lay the ``[[materials]]`` out along the
    ``[layering]`` profile (``gapack layer``); ``Packing.material`` holds
    each disk's material. ``on_generation`` and the rest as :func:`optimise`."""
    return _job("layer", config, seed, on_generation, force, progress, on_interrupt)


def validate(
    config: Any, job: Optional[str] = None, seed: Optional[int] = None, *, force: bool = False
) -> dict:
    """Check a config without running it (``gapack validate``): a dict with
    ``valid``, ``job`` (the job it would run: ``sweep``, ``optimise``,
    ``layer`` or ``pack`` by its tables, or ``job``), ``config``, ``seed``,
    ``out`` (where the command line would write), ``warnings`` and ``plan``
    (the lines ``gapack validate`` prints: scene, estimates, outputs).
    Raises :class:`ConfigError` for a bad config."""
    text, origin, path = _load(config)
    return _gapack.validate(text, origin, path, job, seed, force)


def verify(
    x: Iterable[float],
    y: Iterable[float],
    r: Iterable[float],
    config: Any,
    material: Optional[Iterable[int]] = None,
    *,
    angle: Optional[Iterable[float]] = None,
    a: Optional[Iterable[float]] = None,
    b: Optional[Iterable[float]] = None,
    alpha: Optional[Iterable[float]] = None,
    beta: Optional[Iterable[float]] = None,
) -> dict:
    """Check disks (centres ``x``, ``y`` and radii ``r`` in mm, from gapack or
    any tool) against the config's domain and grading with gapack's
    independent check (``gapack verify``): its own pair search, not the
    generator's. A dict: ``verdict`` (``"valid"``, ``"valid, grading not
    checked"`` or ``"FAILED"``), ``valid`` (no overlap beyond 1e-9 of the
    radii sum, nothing outside), ``grading_kept``, ``particles``,
    ``malformed``, ``overlaps``, ``overlaps_complete`` (``False`` when
    disks pile up and ``overlaps`` is a lower bound: each disk's search stops
    soon after its first overlap), ``worst_overlap`` (``(i, j, depth)`` or
    ``None``), ``outside``, ``worst_outside`` (``(i, mm)``), ``domain_area``,
    ``solid_area``, ``porosity``, ``psd_ks`` and ``ks_limit``.
    ``material`` (indices into the config's materials) checks a size-graded
    config's disks each against their material's grading. With ``angle``,
    ``a``, ``b``, ``alpha`` and ``beta`` (all five, as a shapes
    ``Packing`` has them; ``r`` the area-equivalent radius) the particles
    are those superellipses: each close pair proved apart and each particle
    proved inside by support functions, the grading checked on the size
    the config's ``[shape]`` measures."""
    text, origin, _ = _load(config)
    arrays = [_column(name, v, np.float64) for name, v in (("x", x), ("y", y), ("r", r))]
    m = None if material is None else _column("material", material, np.int64)
    given = [v for v in (angle, a, b, alpha, beta) if v is not None]
    if given and len(given) != 5:
        raise ValueError("give all of angle, a, b, alpha and beta, or none")
    names = ("angle", "a", "b", "alpha", "beta")
    shapes = (
        [_column(n, v, np.float64) for n, v in zip(names, (angle, a, b, alpha, beta))]
        if given
        else None
    )
    return _gapack.verify(*arrays, text, origin, m, shapes)


def _column(name: str, values: Any, dtype: Any) -> np.ndarray:
    """``values`` as a contiguous one-dimensional array of ``dtype``; a
    table of any other shape is refused rather than flattened (a 2-D array
    flattened row by row would check disks that were never there)."""
    array = np.ascontiguousarray(values, dtype=dtype)
    if array.ndim != 1:
        raise ValueError(f"{name} must be a one-dimensional array, got shape {array.shape}")
    return array


def run(
    config: Any,
    job: Optional[str] = None,
    out: Optional[str] = None,
    seed: Optional[int] = None,
    *,
    force: bool = False,
    resume: bool = False,
    on_generation: Optional[Callable[[dict], Any]] = None,
    progress: Optional[bool] = None,
    on_interrupt: str = "raise",
) -> dict:
    """Run any job (``pack``, ``optimise``, ``layer``, ``compare``,
    ``stability``, ``sweep``; by default the one the config's tables name)
    straight into the folder ``out`` as the command line does, wells of a
    ``[fracture]`` batch and parameter studies included; ``resume`` goes on
    from the folder's checkpoint or ``sweep.csv``. Returns a dict: ``job``,
    ``location``, ``dir``, ``files``, ``interrupted``, ``notes`` and
    ``lines`` (the command line's result lines), and the job summary's
    figures where the job has them: ``particles`` and ``porosity`` (pack,
    layer, optimise; ``particles`` of every well of a ``[fracture]`` run),
    ``generations``, ``evaluations``, ``best_porosity`` and
    ``target_porosity`` (optimise). A ``KeyboardInterrupt`` keeps what was finished
    (written, as the command line does) and raises :class:`Interrupted` with
    this dict as ``result`` (or returns it, ``on_interrupt="return"``)."""
    _check_on_interrupt(on_interrupt)
    text, origin, path = _load(config)
    events = _Events(on_generation, progress)
    try:
        told, stopped = _gapack.run_to(
            text, origin, path, job, out, seed, force, resume, events
        )
    finally:
        events.close()
    if stopped and on_interrupt == "raise":
        raise Interrupted(f"{told['job']} stopped; what it finished is written in {told['dir']}", told)
    return told


def _check_on_interrupt(on_interrupt: str) -> None:
    if on_interrupt not in ("raise", "return"):
        raise ValueError(f'on_interrupt: "raise" or "return", got {on_interrupt!r}')


def _job(kind, config, seed, on_generation, force, progress, on_interrupt) -> Packing:
    _check_on_interrupt(on_interrupt)
    text, origin, path = _load(config)
    events = _Events(on_generation, progress)
    try:
        packing, stopped = _gapack.run(kind, text, origin, path, seed, force, events)
    finally:
        events.close()
    if stopped and on_interrupt == "raise":
        raise Interrupted(
            f"{kind} stopped by KeyboardInterrupt; the best packing found is the exception's .packing",
            packing,
        )
    return packing


def _in_notebook() -> bool:
    """Whether this runs in a Jupyter kernel (a notebook), not a terminal."""
    ipython = sys.modules.get("IPython")
    shell = ipython.get_ipython() if ipython is not None else None
    return shell is not None and getattr(shell, "kernel", None) is not None


def _bar_class():
    """The progress bar's class, or ``None`` without tqdm: in a notebook
    with ipywidgets, tqdm's notebook widget (``tqdm.notebook``); in one
    without, tqdm's text bar (the widget would fail); elsewhere
    ``tqdm.auto``'s choice."""
    try:
        if not _in_notebook():
            from tqdm.auto import tqdm

            return tqdm
        try:
            import ipywidgets  # noqa: F401
            from tqdm.notebook import tqdm
        except ImportError:
            from tqdm.std import tqdm
        return tqdm
    except ImportError:
        return None


def _shown() -> bool:
    """Whether a progress bar would be seen: a terminal, or a notebook."""
    if "ipykernel" in sys.modules:
        return True
    try:
        return sys.stderr.isatty()
    except (AttributeError, ValueError):
        return False


#: A pack shows a bar from this many disks (about a second), as the command line's.
_LARGE_PACK = 200_000


class _Events:
    """The job's events: warnings as GapackWarning, generations to the
    caller's ``on_generation``, progress to a tqdm bar."""

    def __init__(self, on_generation, progress):
        self.on_generation = on_generation
        if progress is None:
            progress = _shown()
        self.tqdm = _bar_class() if progress else None
        self.bar = None
        self.stage = None

    def __call__(self, event: dict) -> None:
        kind = event.get("event")
        if kind == "warning":
            warnings.warn(event["message"], GapackWarning, stacklevel=4)
        elif kind == "stage":
            self._start(event["stage"], event.get("total"))
        elif kind == "progress":
            if self.bar is not None and event["stage"] == self.stage:
                self.bar.n = min(event["done"], self.bar.total or event["done"])
                self.bar.refresh()
        elif kind == "generation":
            if self.bar is not None:
                what = "profile RMS" if event["stage"] == "layering" else "best porosity"
                self.bar.n = event["index"]
                self.bar.set_postfix_str(f"{what} {event['best']:.4f}")
            if self.on_generation is not None:
                self.on_generation(
                    {k: v for k, v in event.items() if k != "event"}
                )
        elif kind in ("well", "run") and self.bar is not None:
            self.bar.update(1)

    def _start(self, stage, total):
        if self.tqdm is None:
            return
        nested = stage == "pack" and self.stage not in (None, "pack")
        if nested:
            return
        self.close()
        self.stage = stage
        unit = {"pack": "disk", "optimise": "generation", "layering": "generation", "wells": "well"}
        if stage == "pack" and (total or 0) < _LARGE_PACK:
            return
        self.bar = self.tqdm(total=total, unit=unit.get(stage, "run"), desc=stage, leave=False)

    def close(self):
        if self.bar is not None:
            self.bar.close()
            self.bar = None
