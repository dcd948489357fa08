"""The results table and README update that the example scripts share.

An example script runs its scenes, writes one row per scene as ``table.md`` and ``table.csv`` into
its output folder, and with ``--readme`` puts the Markdown table into its README between two
markers and copies its plots into ``images/``. The markers name the script:

    <!-- table: run_x.py --readme writes it -->
    ...
    <!-- end of table -->
"""

from __future__ import annotations

import csv
import re
import shutil
from pathlib import Path


def markers(script: str) -> tuple[str, str]:
    """The README's start and end markers around the table ``script`` writes."""
    return f"<!-- table: {script} --readme writes it -->", "<!-- end of table -->"


def table_markdown(columns, rows: list[dict], cell) -> str:
    """The table as Markdown: ``columns`` (header, key) pairs, one row per dict, each value as
    ``cell(key, value)`` gives it."""
    lines = ["| " + " | ".join(h for h, _ in columns) + " |", "|" + "---|" * len(columns)]
    for row in rows:
        lines.append("| " + " | ".join(cell(k, row[k]) for _, k in columns) + " |")
    return "\n".join(lines)


def write_table(columns, rows: list[dict], out: Path, cell) -> str:
    """Write ``table.md`` and ``table.csv`` (full precision) into ``out``; return the Markdown."""
    md = table_markdown(columns, rows, cell)
    (out / "table.md").write_text(md + "\n")
    with open(out / "table.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow([h for h, _ in columns])
        for row in rows:
            w.writerow([row[k] for _, k in columns])
    return md


def update_readme(folder: Path, script: str, md: str, plots: list[Path]) -> None:
    """Put the table ``md`` between the markers of ``script`` in ``folder``/README.md and copy the
    plots into ``folder``/images/."""
    start, end = markers(script)
    readme = folder / "README.md"
    text = readme.read_text()
    pattern = re.compile(re.escape(start) + ".*?" + re.escape(end), re.DOTALL)
    readme.write_text(pattern.sub(lambda _: f"{start}\n{md}\n{end}", text))
    (folder / "images").mkdir(exist_ok=True)
    for p in plots:
        shutil.copy(p, folder / "images" / p.name)
