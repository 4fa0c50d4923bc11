"""The plots of a diagnosis report's before/after section (`damper diagnose` with an effect named) as one
SVG file: docs/effects.md shows the worked example's, which tests/python/test_transcripts.py compares
with the report it makes (UPDATE_DOCS=1 rewrites the file).

    .venv/bin/python -m damper_tools.report_figure after/report.html --out docs/figures/diagnose_before_after.svg
"""

import argparse
import re
from pathlib import Path

from damper_tools import REPO

# docs/effects.md's figure of the worked example
DOCS_FIGURE = REPO / "docs" / "figures" / "diagnose_before_after.svg"
SECTION = "<h2>Before and after adding"
SVG = re.compile(r"<svg (.*?)>(.*?)</svg>", re.S)
HEIGHT = re.compile(r'\bheight="(\d+(?:\.\d+)?)"')
WIDTH = re.compile(r'\bwidth="(\d+(?:\.\d+)?)"')


def before_after_svg(report_html: str) -> str:
    """The before/after section's plots of `report_html`, stacked top to bottom in one SVG document
    (each keeps its own size and clip ids, which the report already makes unique)."""
    start = report_html.find(SECTION)
    if start < 0:
        raise ValueError("the report has no before/after section (the diagnosis named no effect)")
    plots = SVG.findall(report_html[start:])
    if not plots:
        raise ValueError("the report's before/after section has no plot")
    parts, top, width = [], 0.0, 0.0
    for attributes, body in plots:
        height, plot_width = HEIGHT.search(attributes), WIDTH.search(attributes)
        if height is None or plot_width is None:
            raise ValueError(f"a plot of the report has no size: <svg {attributes[:80]}>")
        parts.append(f'<svg y="{top:g}" {attributes}>{body}</svg>')
        top += float(height.group(1))
        width = max(width, float(plot_width.group(1)))
    return (f'<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {width:g} {top:g}" width="{width:g}" '
            f'height="{top:g}">\n' + "\n".join(parts) + "\n</svg>\n")


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("report", type=Path, help="a diagnosis's report.html")
    parser.add_argument("--out", type=Path, required=True, help="the SVG file to write")
    args = parser.parse_args(argv)
    args.out.write_text(before_after_svg(args.report.read_text(encoding="utf-8")), encoding="utf-8")
    print(f"report_figure: wrote {args.out}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
