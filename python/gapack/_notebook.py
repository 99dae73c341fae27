"""The packing in a notebook: its summary read by attribute, its picture
and key figures (``_repr_png_``, ``_repr_html_``), a matplotlib drawing,
and pandas tables both ways.

matplotlib and pandas are optional: each is imported where it is needed,
and its absence is an ``ImportError`` that says what to install.
"""

from __future__ import annotations

import base64
import html as _html
import math
from typing import Any, Optional

import numpy as np

__all__ = ["Summary", "html", "plot", "to_pandas", "from_pandas"]

#: The extra that installs what the notebook features use.
_EXTRA = "pip install 'gapack[notebook]'"


class Summary(dict):
    """``summary.json`` as a dict whose keys also read as attributes
    (``p.summary.porosity``, ``p.summary.grading.ks`` for nested tables).

    It is a dict: indexing, ``in``, iteration, ``json.dumps`` and equality
    with a plain dict work as before. A key named like a dict method
    (``items``, ``keys``, …) is read by index.
    """

    __slots__ = ()

    # The figures every packing's summary has, typed for editors and type
    # checkers (annotations only: the values are the dict's).
    gapack_version: str
    config: str
    seed: int
    particles: int
    domain_area: float
    solid_area: float
    porosity: float
    psd_ks: float
    grading_kept: bool
    max_overlap: float
    coordination: float
    seconds: float

    def __getattr__(self, name: str) -> Any:
        try:
            return self[name]
        except KeyError:
            raise AttributeError(f"the summary has no {name!r}") from None

    def __dir__(self):
        return sorted(set(super().__dir__()) | {k for k in self if k.isidentifier()})

    def __repr__(self) -> str:
        return f"Summary({dict.__repr__(self)})"


def _need(module: str, what: str):
    """Import ``module``, or say what needs it and how to install it."""
    try:
        return __import__(module, fromlist=["_"])
    except ImportError as e:
        raise ImportError(
            f"{what} needs {module.split('.')[0]}, which is not installed: "
            f"pip install {module.split('.')[0]} (or {_EXTRA})"
        ) from e


def _figure(value: Any) -> str:
    """A number as the table shows it."""
    if isinstance(value, bool) or value is None:
        return str(value)
    if isinstance(value, float):
        if not math.isfinite(value):
            return str(value)
        return f"{value:.4f}" if abs(value) < 1e4 else f"{value:.4g}"
    return str(value)


def _domain_words(domain: dict) -> str:
    """The domain in a few words: ``rectangle 30 × 20 mm``."""
    shape = domain.get("shape", "?")
    if shape == "rectangle":
        size = f"{domain['width']:g} × {domain['height']:g} mm"
    elif shape == "circle":
        size = f"radius {domain['radius']:g} mm"
    elif shape == "trapezoid":
        size = f"{domain['bottom']:g}/{domain['top']:g} × {domain['height']:g} mm"
    else:
        size = f"{len(domain.get('vertices', []))} vertices"
    extra = ", periodic" if domain.get("periodic") else ""
    return f"{shape} {size}{extra}"


def _figures(packing) -> list:
    """The rows of the key figures table: (name, value)."""
    s = packing.summary
    rows = [
        ("job", packing.job + (" (interrupted)" if packing.interrupted else "")),
        ("particles", len(packing)),
        ("porosity", s.get("porosity")),
        ("domain", _domain_words(packing.domain)),
        ("seed", packing.seed),
    ]
    if "psd_ks" in s:
        ks = _figure(s["psd_ks"])
        kept = s.get("grading_kept")
        rows.append(("grading KS", ks + ("" if kept is None else (" (kept)" if kept else " (bent)"))))
    if packing.materials:
        rows.append(("materials", ", ".join(m["name"] for m in packing.materials)))
    for key, name in (
        ("target_porosity", "target porosity"),
        ("generations", "generations"),
        ("verdict", "verdict"),
        ("profile_rms_error", "profile RMS error"),
    ):
        if key in s:
            rows.append((name, s[key]))
    return rows


def html(packing) -> str:
    """The picture inline (a base64 PNG) beside a table of key figures."""
    png = base64.b64encode(packing._repr_png_()).decode("ascii")
    cells = "".join(
        f"<tr><th style='text-align:left'>{_html.escape(name)}</th>"
        f"<td style='text-align:left'>{_html.escape(_figure(value))}</td></tr>"
        for name, value in _figures(packing)
    )
    return (
        "<div style='display:flex;flex-wrap:wrap;gap:1em;align-items:flex-start'>"
        f"<img src='data:image/png;base64,{png}' style='max-width:640px;width:100%' "
        "alt='the packing'/>"
        f"<table>{cells}</table></div>"
    )


def to_pandas(packing):
    """One row per particle, the columns of ``packing.csv``."""
    pd = _need("pandas", "Packing.to_pandas")
    n = len(packing)
    columns = {"id": np.arange(n, dtype=np.int64), "x": packing.x, "y": packing.y, "r": packing.r}
    if packing.angle is not None:
        # As packing.csv: a superellipse's columns when there are any, a
        # polygon's template when there are any (its vertices and rounding
        # are in packing.csv).
        template = np.asarray(packing.template)
        names = ["angle"]
        if (template < 0).any():
            names += ["a", "b", "alpha", "beta"]
        if (template >= 0).any():
            names.append("template")
        for name in names:
            columns[name] = getattr(packing, name)
    if packing.material is not None:
        names = [m["name"] for m in packing.materials]
        columns["material"] = pd.Categorical.from_codes(packing.material, categories=names)
    df = pd.DataFrame({k: np.array(v, copy=True) if isinstance(v, np.ndarray) else v for k, v in columns.items()})
    # What from_pandas needs to make the same packing again.
    df.attrs["gapack"] = {"config": packing.toml, "origin": packing.config, "seed": packing.seed}
    return df


def _column(df, *names):
    for name in names:
        if name in df.columns:
            return name
    return None


def from_pandas(df, domain=None, config=None, seed=None):
    """The packing of the disks of ``df``: see ``Packing.from_pandas``."""
    from . import _gapack
    from ._config import load, to_toml

    recorded = getattr(df, "attrs", {}).get("gapack")
    if config is not None and domain is not None:
        raise ValueError("give domain= or config=, not both")
    if config is not None:
        text, origin, _ = load(config)
    elif domain is not None:
        text, origin = None, "<dict>"
    elif recorded:
        text, origin = recorded["config"], recorded.get("origin", "<string>")
        if seed is None:
            seed = recorded.get("seed")
    else:
        raise ValueError(
            "from_pandas: give domain= (a [domain] table as a dict) or config=; "
            "only a DataFrame made by Packing.to_pandas records its config"
        )
    x_name, y_name = _column(df, "x"), _column(df, "y")
    r_name, d_name = _column(df, "r", "radius"), _column(df, "d", "diameter")
    if x_name is None or y_name is None or (r_name is None and d_name is None):
        raise ValueError(f"from_pandas: the DataFrame needs x, y and r (or d) columns, has {list(df.columns)}")
    x = np.ascontiguousarray(df[x_name].to_numpy(), dtype=np.float64)
    y = np.ascontiguousarray(df[y_name].to_numpy(), dtype=np.float64)
    if r_name is not None:
        r = np.ascontiguousarray(df[r_name].to_numpy(), dtype=np.float64)
    else:
        r = np.ascontiguousarray(df[d_name].to_numpy(), dtype=np.float64) / 2.0
    if text is None:
        # A domain alone: the grading is the disks' own range of diameters.
        lo, hi = (float(2.0 * r.min()), float(2.0 * r.max())) if len(r) else (1.0, 1.0)
        grading = {"constant": lo} if lo == hi else {"uniform": [lo, hi]}
        text = to_toml({"domain": dict(domain), "grading": grading})
    material, names = None, None
    m = _column(df, "material")
    if m is not None:
        column = df[m]
        pd = _need("pandas", "Packing.from_pandas")
        if isinstance(column.dtype, pd.CategoricalDtype):
            names = [str(v) for v in column.astype(str)]
        elif pd.api.types.is_integer_dtype(column.dtype):
            material = np.ascontiguousarray(column.to_numpy(), dtype=np.int64)
        else:
            names = [str(v) for v in column]
    return _gapack.Packing._from_arrays(
        x, y, r, text, origin, seed, material=material, material_names=names
    )


def _values(packing, key: str) -> np.ndarray:
    """The numbers a drawing is coloured by: a column of ``to_pandas()``
    (``r``, ``angle``, …), or ``diameter``."""
    if key == "diameter":
        return 2.0 * np.asarray(packing.r)
    if key in ("x", "y", "r"):
        return np.asarray(getattr(packing, key))
    if key == "id":
        return np.arange(len(packing), dtype=float)
    column = getattr(packing, key, None) if key in ("angle", "a", "b", "alpha", "beta", "template") else None
    if column is None:
        raise ValueError(
            f"color_by: 'material', 'radius', 'diameter' or a numeric column of to_pandas(), got {key!r}"
        )
    return np.asarray(column, dtype=float)


def plot(packing, ax=None, color_by="material", **kw):
    """Draw the particles on ``ax``: see ``Packing.plot``."""
    _need("matplotlib", "Packing.plot")
    from matplotlib.collections import EllipseCollection
    from matplotlib.patches import Patch

    if ax is None:
        import matplotlib.pyplot as plt

        _, ax = plt.subplots()
    n = len(packing)
    xy = np.column_stack([packing.x, packing.y])
    width, height, angle = 2.0 * packing.r, 2.0 * packing.r, np.zeros(n)
    if packing.angle is not None:
        # Superellipses as ellipses of their semi-axes; polygons as their
        # disks of the same area.
        ellipse = np.isfinite(packing.a)
        width = np.where(ellipse, 2.0 * np.nan_to_num(packing.a), width)
        height = np.where(ellipse, 2.0 * np.nan_to_num(packing.b), height)
        angle = np.where(ellipse, np.degrees(packing.angle), 0.0)
    style = {"edgecolor": "0.2", "linewidth": 0.2 if n > 2000 else 0.5}
    style.update(kw)
    legend = None
    if color_by == "material" and packing.material is None:
        color_by = "radius"
    if color_by == "material":
        import matplotlib

        cmap = matplotlib.colormaps["tab10"]
        names = [m["name"] for m in packing.materials]
        style.setdefault("facecolors", cmap(np.asarray(packing.material) % 10))
        legend = [Patch(facecolor=cmap(i % 10), edgecolor="0.2", label=name) for i, name in enumerate(names)]
        values = None
    else:
        key = {"radius": "r", "size": "r"}.get(color_by, color_by)
        values = _values(packing, key)
        style.setdefault("cmap", "viridis")
    collection = EllipseCollection(
        width, height, angle, units="xy", offsets=xy, offset_transform=ax.transData, **style
    )
    if values is not None and "facecolors" not in kw:
        collection.set_array(values)
    ax.add_collection(collection)
    outline = np.asarray(packing.domain["outline"])
    closed = np.vstack([outline, outline[:1]])
    ax.plot(closed[:, 0], closed[:, 1], color="k", linewidth=1.0, linestyle="--" if packing.domain["periodic"] else "-")
    (x0, y0), (x1, y1) = packing.domain["bounds"]
    pad = 0.02 * max(x1 - x0, y1 - y0)
    ax.set_xlim(x0 - pad, x1 + pad)
    ax.set_ylim(y0 - pad, y1 + pad)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    if legend:
        ax.legend(handles=legend, loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize="small")
    elif values is not None and "facecolors" not in kw:
        label = {"r": "radius (mm)", "diameter": "diameter (mm)"}.get(key, key)
        ax.figure.colorbar(collection, ax=ax, label=label, shrink=0.8)
    return ax
