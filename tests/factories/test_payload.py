"""Issue 12: an object over a robot's published payload is that robot's refusal (exit 4), not
a simulation that pretends to lift it."""

from __future__ import annotations

from pathlib import Path

from click.testing import CliRunner

from atd.cli import main

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "pick_and_place.xml"


def test_a_five_kg_object_is_refused_by_the_robots_that_cannot_carry_it(tmp_path: Path) -> None:
    heavy = tmp_path / "heavy.xml"
    heavy.write_text(EXAMPLE.read_text().replace("<weight>0.1</weight>", "<weight>5</weight>"))
    result = CliRunner().invoke(main, ["translate", str(heavy), "--robot", "melfa", "-q"])
    assert result.exit_code == 4
    assert "the object weighs 5 kg, over the 3 kg payload" in result.output
    assert not list(tmp_path.glob("*.estd.*"))
    assert CliRunner().invoke(main, ["translate", str(heavy), "--robot", "tombatossals", "-q"]).exit_code == 0
