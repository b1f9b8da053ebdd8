"""A benchmark run's outputs beside its episodes: the report (Markdown) and the success plot."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from voxposer.bench.config import Tolerances
from voxposer.bench.suites import MULTISTEP_SUITE


def write_outputs(records: list[dict[str, Any]], out: Path, plot: bool,
                  wall_rates: dict[str, float] | None = None, allow_mixed: bool = False) -> Path:
    """Write report.md (and success.png); returns the report's path (ConfigError when the
    records mix code versions and not ``allow_mixed``). Records of the multi-step suite get its
    own report (:mod:`voxposer.bench.report_multistep`)."""
    from voxposer.bench.report import main_records, markdown

    report = out / "report.md"
    if records and all(r.get("suite") == MULTISTEP_SUITE for r in records):
        from voxposer.bench.report_multistep import multistep_markdown

        report.write_text(multistep_markdown(records, allow_mixed), encoding="utf-8")
        return report  # (no success chart: it plots the 13 tasks)
    text = markdown(records, Tolerances(), wall_rates, allow_mixed=allow_mixed, out=out)
    report.write_text(text, encoding="utf-8")
    if plot and records:
        from voxposer.bench.plot import write_chart

        write_chart(main_records(records)[0], out / "success.png")
    return report
