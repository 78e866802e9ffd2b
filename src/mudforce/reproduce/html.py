"""``report.html`` of :mod:`mudforce.reproduce`: the template ``templates/report.html`` filled from the summary.

The page's text and layout live in the template (read with
:mod:`importlib.resources`, filled with :class:`string.Template`); this
module makes only the parts that depend on the run: the table rows, the
figure list, and the numbers in the prose. Values are shown in the
paper's units (:data:`mudforce.reproduce.summary.PAPER_UNITS`); every text
from the data is HTML-escaped.
"""

from __future__ import annotations

import html
import math
from collections.abc import Mapping, Sequence
from importlib import resources
from pathlib import Path
from string import Template
from typing import Any

from mudforce.model.parameters import CITATION
from mudforce.reproduce.experiments import SCATTERED, ReproduceConfig
from mudforce.reproduce.summary import MODEL_LABELS, NINE, PAPER_UNITS, POORLY_DETERMINED, in_paper_units

__all__ = ["TEMPLATE", "render_html"]

#: The page's template, a resource of this package.
TEMPLATE = "templates/report.html"

_DAGGER = "<sup>&dagger;</sup>"


def _template() -> Template:
    text = resources.files("mudforce.reproduce").joinpath(TEMPLATE).read_text(encoding="utf-8")
    return Template(text)


def _fmt(x: float | None, digits: int = 3) -> str:
    """``x`` to ``digits`` significant digits; a dash for a missing or non-finite value."""
    if x is None or not math.isfinite(x):
        return "&mdash;"
    return f"{x:.{digits}g}"


def _table_i_rows(rows: Sequence[Mapping[str, Any]]) -> list[str]:
    """Two rows per water content: the fit (value ± standard error, † if not determined), then the paper."""
    out = []
    for row in rows:
        cells = []
        for n in NINE:
            se = row["stderr"].get(n)
            mark = "" if row["determined"][n] else _DAGGER
            cells.append(f"<td>{_fmt(in_paper_units(n, row['fitted'][n]))}"
                         + (f" &plusmn; {_fmt(in_paper_units(n, se), 2)}" if se is not None else "") + f"{mark}</td>")
        out.append(f"<tr><td>{row['water_content']:.0%} fitted</td>{''.join(cells)}"
                   f"<td>{_fmt(row['rmse_N'])}</td></tr>")
        paper = "".join(f"<td>{_fmt(in_paper_units(n, row['paper'][n]))}</td>" for n in NINE)
        out.append(f"<tr class=\"paper\"><td>{row['water_content']:.0%} paper</td>{paper}"
                   f"<td>{_fmt(row['paper_reported_rmse_N'])}</td></tr>")
    return out


def _fit_warnings(rows: Sequence[Mapping[str, Any]]) -> str:
    warned = [(row["water_content"], w) for row in rows for w in row["warnings"]]
    if not warned:
        return ""
    items = "".join(f"<li>W = {w:.0%}: {html.escape(text)}</li>" for w, text in warned)
    return f"\n<details><summary>Fit warnings</summary><ul>{items}</ul></details>"


def _critical_rows(config: ReproduceConfig, rows: Sequence[Mapping[str, Any]]) -> list[str]:
    out = []
    for row in rows:
        necks = "".join(f"<td>{'yes' if row['necks_at_m_s'][f'{v:g}'] else 'no'}</td>" for v in config.velocities)
        fitted = row["fitted_m_s"]
        mark = "" if row["fitted_determined"] else _DAGGER
        out.append(f"<tr><td>{row['water_content']:.0%}</td><td>{_fmt(None if fitted is None else fitted * 1e3)}"
                   f"{mark}</td><td>{_fmt(row['paper_m_s'] * 1e3)}</td>{necks}</tr>")
    return out


def _baseline_rows(config: ReproduceConfig, baselines: Mapping[str, Mapping[str, Any]]) -> list[str]:
    e = html.escape
    out = []
    for name, entry in baselines.items():
        per = "".join(f"<td>{_fmt(entry['rmse_N_by_water_content'].get(f'{w:g}'))}</td>"
                      for w in config.water_contents)
        out.append(f"<tr><td>{e(MODEL_LABELS.get(name, name))} (<code>{e(name)}</code>)</td>"
                   f"<td>{_fmt(entry['rmse_N'])}</td>{per}</tr>")
    return out


def _figures(figures: Sequence[tuple[str, str, str]]) -> list[str]:
    e = html.escape
    return [f'<figure id="{e(Path(file).stem)}"><img src="{e(file)}" alt="{e(paper_fig)}">'
            f"<figcaption><b>{e(paper_fig)}.</b> {e(caption)}</figcaption></figure>"
            for file, paper_fig, caption in figures]


def render_html(config: ReproduceConfig, summary: Mapping[str, Any], figures: Sequence[tuple[str, str, str]]) -> str:
    """The text of ``report.html``.

    Parameters
    ----------
    config : ReproduceConfig
        The run's configuration (speeds, noise, seed).
    summary : mapping
        The content of ``summary.json`` (:func:`mudforce.reproduce.summary.make_summary`).
    figures : sequence of (file, paper figure, caption)
        The figures, in the order shown.
    """
    e = html.escape
    rows = summary["table_i"]
    return _template().substitute(
        paper=e(CITATION),
        version=e(str(summary["mudforce_version"])),
        mode="--quick" if config.quick else "full",
        seed=config.seed,
        n_water_contents=len(config.water_contents),
        n_speeds=len(config.velocities),
        speeds_mm_s=", ".join(f"{v * 1e3:g}" for v in config.velocities),
        repeats=config.repeats,
        force_noise_N=f"{config.force_noise:g}",
        depth_noise_mm=f"{config.depth_noise * 1e3:g}",
        bias_N=f"{config.bias:g}",
        repeat_scatter=f"{config.repeat_scatter:.0%}",
        scattered=", ".join(SCATTERED),
        table_i_header="".join(f"<th>{e(n)} [{e(PAPER_UNITS[n][1])}]</th>" for n in NINE),
        table_i_rows="\n".join(_table_i_rows(rows)),
        poorly_determined=f"{POORLY_DETERMINED:.0%}",
        paper_parameters_rmse=", ".join(f"{row['water_content']:.0%}: {_fmt(row['paper_parameters_rmse_N'])} N"
                                        for row in rows),
        fit_warnings=_fit_warnings(rows),
        critical_header="".join(f"<th>necks at {float(v) * 1e3:g} mm/s (Table I)</th>" for v in config.velocities),
        critical_rows="\n".join(_critical_rows(config, summary["critical_withdrawal_velocity"])),
        baseline_header="".join(f"<th>W = {w:.0%}</th>" for w in config.water_contents),
        baseline_rows="\n".join(_baseline_rows(config, summary["baselines"])),
        figures="\n".join(_figures(figures)),
    )
