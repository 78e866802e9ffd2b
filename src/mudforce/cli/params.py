"""Show the model's parameters: the paper's Table I, or one set for a water content, in SI.

Without --water-content: Table I of Chen, Yi & Shan (2024), all five water
contents, converted to SI (Pa/m, Pa s/m, Pa, rad/s, kg/m^3), with the RMSE
the paper reports on its own data, and the citation.

With --water-content W: the parameter set for W, exact on a Table I row and
interpolated log-linearly between rows (W within 15% to 35%).

--json prints JSON only: with --water-content, the flat object of the 11
keys in SI (the format --params of `mudforce simulate` reads); without it,
an object keyed by water content as a fraction ("0.15" ... "0.35"), each
value such a flat object.

examples:
  mudforce params
  mudforce params --water-content 25%
  mudforce params --water-content 22.5% --json > mud.json
"""

from __future__ import annotations

import argparse
import json

from mudforce.errors import InputError
from mudforce.io.units import parse_quantity

__all__ = ["HELP", "NAME", "add_arguments", "format_table_i", "parse_water_content", "run", "table_i_json"]

NAME = "params"
HELP = "print Table I, or the parameter set for one water content (SI, optionally JSON)"


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Declare the options of ``mudforce params``."""
    parser.formatter_class = argparse.RawDescriptionHelpFormatter  # keep the docstring's paragraphs
    parser.add_argument("--water-content", metavar="W", default=None,
                        help="water content within 15%%-35%%, e.g. 25%% (default: print all of Table I)")
    parser.add_argument("--json", action="store_true", help="print JSON (SI) and nothing else")


def format_table_i() -> str:
    """Table I of the paper in SI, one column per water content, with units and the citation.

    Returns
    -------
    str
        A plain-text table: one line per parameter (name, SI unit, the five
        values), the paper's RMSE [N], and a citation line.
    """
    from mudforce.model.parameters import (
        CITATION,
        PARAMETER_NAMES,
        PARAMETER_UNITS,
        TABLE_I,
        TABLE_I_RMSE_N,
        TABLE_I_WATER_CONTENTS,
    )

    cell = 10
    head = f"{'parameter':<9} {'unit':<7}" + "".join(f"{f'W = {w:.0%}':>{cell}}" for w in TABLE_I_WATER_CONTENTS)
    lines = ["Table I (SI units): the mud model's parameters per water content W", head, "-" * len(head)]
    for name in PARAMETER_NAMES:
        values = [TABLE_I[w].to_dict()[name] for w in TABLE_I_WATER_CONTENTS]
        lines.append(f"{name:<9} {PARAMETER_UNITS[name]:<7}" + "".join(f"{v:>{cell}.4g}" for v in values))
    lines.append(f"{'RMSE':<9} {'N':<7}" + "".join(f"{TABLE_I_RMSE_N[w]:>{cell}.3g}" for w in TABLE_I_WATER_CONTENTS))
    lines.append("-" * len(head))
    lines.append("RMSE: the fit error the paper reports on its own (unpublished) data; cited, not reproducible.")
    lines.append("rho_m and lambda are common to all rows. Between rows, `--water-content` interpolates log-linearly.")
    lines.append(f"Source: {CITATION}, Table I.")
    return "\n".join(lines)


def table_i_json() -> str:
    """Table I as JSON: an object keyed by water content (``"0.15"`` ... ``"0.35"``), each the 11 keys in SI."""
    from mudforce.model.parameters import TABLE_I, TABLE_I_WATER_CONTENTS

    return json.dumps({f"{w:.2f}": TABLE_I[w].to_dict() for w in TABLE_I_WATER_CONTENTS}, indent=2)


def parse_water_content(text: str, *, name: str = "--water-content") -> float:
    """Parse a water content (``"25%"`` or the fraction ``"0.25"``) within Table I's range.

    Returns
    -------
    float
        The volume fraction of water [-], within [0.15, 0.35].

    Raises
    ------
    InputError
        For a value without ``%`` above 1, a negative or zero value, or one
        outside Table I's range, with an example.
    """
    from mudforce.model.parameters import WATER_CONTENT_RANGE

    w = parse_quantity(text, "fraction", name=name)
    lo, hi = WATER_CONTENT_RANGE
    if not lo - 1e-12 <= w <= hi + 1e-12:
        shown = repr(text) if str(text).strip().endswith("%") else f"{text!r} ({w * 100:g}%)"
        raise InputError(
            f"{name}: {shown} is outside Table I's range {lo * 100:g}% to {hi * 100:g}%; "
            f"expected e.g. 25%"
        )
    return w


def run(args: argparse.Namespace) -> int:
    """Print Table I or one parameter set; see the module docstring."""
    if args.water_content is None:
        print(table_i_json() if args.json else format_table_i())
        return 0
    from mudforce.model.parameters import MudParameters

    params = MudParameters.from_water_content(parse_water_content(args.water_content))
    print(params.to_json() if args.json else params.describe())
    return 0
