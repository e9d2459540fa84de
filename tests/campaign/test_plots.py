"""The campaign picture: written whole, as a valid PNG or SVG, and binned honestly."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from atd.campaign.plots import approach_bins, draw_report
from atd.campaign.report import build_report
from tests.campaign.conftest import approach, preset_records, trial

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"


def test_trials_without_approach_error_fall_in_the_zero_bin() -> None:
    records = [trial(0), trial(1, grasp="robust"),
               trial(2, perturbation="approach", sampled=approach(0.02, 5.0), judged=False),
               trial(3, perturbation="approach", sampled=approach(0.10, 15.0))]
    bins = approach_bins(records, "translation", count=5)
    assert [(b.low, b.high) for b in bins] == [(0.0, 0.0), pytest.approx((0.0, 0.02)), pytest.approx((0.08, 0.10))]
    zero = {g.value("grasp"): g.n for g in bins[0].groups}
    assert zero == {"naive": 1, "robust": 1}
    assert [(g.n, g.successes) for g in bins[1].groups] == [(1, 0)]


def test_no_approach_error_anywhere_gives_only_the_zero_bin() -> None:
    assert [(b.low, b.high) for b in approach_bins([trial(0), trial(1)], "rotation")] == [(0.0, 0.0)]


def test_png_plot_is_a_valid_png(tmp_path: Path) -> None:
    records = preset_records()
    path = tmp_path / "campaign.png"
    path.write_bytes(draw_report(records, build_report(records).conditions, path.suffix.lstrip(".")))
    data = path.read_bytes()
    assert data.startswith(PNG_SIGNATURE) and b"IEND" in data[-16:]
    assert [p.name for p in tmp_path.iterdir()] == ["campaign.png"]  # no temporary file left


def test_svg_plot_is_valid_svg_and_shows_both_grasp_modes(tmp_path: Path) -> None:
    records = preset_records()
    path = tmp_path / "campaign.svg"
    path.write_bytes(draw_report(records, build_report(records).conditions, path.suffix.lstrip(".")))
    root = ET.parse(path).getroot()
    assert root.tag == "{http://www.w3.org/2000/svg}svg"
    text = path.read_text()
    for words in ("naive", "robust", "approach translation error (cm)", "approach rotation error (deg)"):
        assert words in text


def test_a_campaign_without_approach_error_draws_the_rates_alone(tmp_path: Path) -> None:
    records = [trial(i, judged=i % 2 == 0) for i in range(4)]
    path = tmp_path / "rates.svg"
    path.write_bytes(draw_report(records, build_report(records).groups, "svg"))
    assert "approach translation error" not in path.read_text()


def test_cells_of_all_or_no_successes_draw_their_interval(tmp_path: Path) -> None:
    # At 30/30 the Wilson high can round a hair below the rate: the bar must still draw.
    records = [trial(i, grasp=g, judged=g == "robust") for g in ("naive", "robust") for i in range(30)]
    picture = draw_report(records, build_report(records).conditions, "png")
    assert picture.startswith(b"\x89PNG")
