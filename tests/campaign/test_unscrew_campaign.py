"""Issue 32: unscrew campaigns (thesis 3.4.2, Tables 3.4 and 3.5). The cap judge reads the
simulator's cap (free? resting where?), the Table 3.5 noise is a perturbation model of its
own, a perturbation may be tried on some objects with trials of its own, the naive grasp
mode unscrews without the alignment, and the report sets Tables 3.4 and 3.5 beside ours."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from atd.campaign.cells import plans
from atd.campaign.formats import render
from atd.campaign.judge import CapJudge
from atd.campaign.perturbation import CapApproach, Truth, approach_states
from atd.campaign.record import Cell, TrialRecord
from atd.campaign.report import build_report
from atd.campaign.spec import load_spec
from atd.campaign.unscrew import unscrew_measures
from atd.model import load_task
from atd.model.vocabulary import StateType
from atd.runtime.session import belief_scene
from atd.sim.thread import CapState
from factories.registry import create
from tests.conftest import EXAMPLES
from translator import translate

TASK = EXAMPLES / "unscrew_fixture.xml"
PRESET = EXAMPLES / "campaigns" / "unscrew.toml"


class Caps:
    """What the cap judge may read of a simulated robot: the cap, as the simulator has it now."""

    def __init__(self, free: bool, rests: str, turned: float = 1.6) -> None:
        self.cap = CapState(turned, free, np.eye(4), rests)  # type: ignore[arg-type]

    def caps(self) -> dict[str, CapState]:
        return {"jar": self.cap}

    def hold_still(self, seconds: float) -> None:
        pass


def _judged(robot: Caps, task_succeeded: bool):
    judge = CapJudge(robot)  # type: ignore[arg-type]
    judge(robot)  # type: ignore[arg-type]
    return judge.verdict(task_succeeded)


def test_a_cap_free_on_the_table_after_the_task_said_so_is_a_success() -> None:
    verdict = _judged(Caps(True, "table"), task_succeeded=True)
    assert verdict.succeeded and verdict.reason == "the cap of 'jar' is off its thread, on the table"
    assert verdict.measurements["cap_free"] == 1.0 and verdict.measurements["cap_on_table"] == 1.0


def test_a_cap_still_on_its_bottle_is_neither_a_success_nor_unscrewed() -> None:
    verdict = _judged(Caps(False, "bottle", turned=0.5), task_succeeded=False)
    assert not verdict.succeeded and verdict.measurements["cap_free"] == 0.0
    assert verdict.reason == "the cap of 'jar' is still on its thread, turned 0.08 turns"


@pytest.mark.parametrize(("free", "rests"), [(False, "bottle"), (True, "held"), (True, "bottle")])
def test_a_task_that_says_the_cap_is_on_the_table_when_it_is_not_made_a_false_success(free: bool, rests: str) -> None:
    verdict = _judged(Caps(free, rests), task_succeeded=True)
    record = TrialRecord(cell=Cell("unscrew_fixture", "tombatossals", "left", "mujoco", "robust", "jam_jar", "none"),
                         index=0, seed=1, task_succeeded=True, judged_succeeded=verdict.succeeded)
    assert not verdict.succeeded and record.false_success
    assert verdict.measurements["cap_free"] == float(free)


def test_a_cap_unscrewed_and_on_the_table_while_the_task_said_failure_is_unscrewed_but_no_success() -> None:
    verdict = _judged(Caps(True, "table"), task_succeeded=False)
    assert not verdict.succeeded and verdict.measurements["cap_free"] == 1.0
    assert verdict.reason.endswith("but the task did not say it put it there")


def test_the_unscrews_time_and_twists_come_from_the_trace_the_count_as_a_number_not_read_from_words() -> None:
    belief = translate(load_task(TASK)[0], create("tombatossals", "left")).estd
    records = [{"t": 3.0, "type": "enter", "state": "unscrew_cap"},
               {"t": 15.0, "type": "event", "state": "unscrew_cap", "conditions": [
                   {"arm": "done", "reason": "cap off after 3 twists, pulled 4.0 cm with the pads on it", "twists": 4},
                   {"reason": "holding the cap"}]},
               {"t": 15.0, "type": "exit", "state": "unscrew_cap"}]
    assert unscrew_measures(belief, records, 24.0) == {"unscrew_time": 12.0, "twists": 4.0}
    assert unscrew_measures(belief, records[:1], 153.0) == {"unscrew_time": 150.0}  # a timeout said no count


def test_the_cap_approach_noise_shifts_the_moves_to_the_unscrew_only() -> None:
    belief = translate(load_task(TASK)[0], create("tombatossals", "left")).estd
    model = CapApproach(model="cap_approach", across=0.015)
    values = model.draw(np.random.default_rng(5))
    assert abs(values["cap_dx"]) <= 0.015 and abs(values["cap_dy"]) <= 0.015 and values["cap_dz"] == 0.0
    truth = model.apply(Truth(belief, belief_scene(belief), create("tombatossals", "left").robot), values)
    assert approach_states(belief, StateType.UNSCREW) == {"above_cap", "around_cap"}
    for before, after in zip(belief.states, truth.estd.states):
        if before.name in ("above_cap", "around_cap"):
            moved = np.subtract(after.arm.params["target"], before.arm.params["target"])
            assert np.allclose(moved, (values["cap_dx"], values["cap_dy"], 0.0))
        else:
            assert after == before, before.name


def test_on_the_touch_task_the_cap_approach_noise_moves_the_hand_over_the_cap_and_the_touch_carries_it() -> None:
    """examples/unscrew_by_touch.xml: only the move over the believed object has a target to
    shift; the explore starts where it ended and every later move is read from its contact."""
    belief = translate(load_task(EXAMPLES / "unscrew_by_touch.xml")[0], create("tombatossals", "left")).estd
    assert approach_states(belief, StateType.UNSCREW) == {"above_cap"}
    assert {s.name for s in belief.states if s.target_from == "cap_top"} == {
        "off_cap", "open_over_cap", "around_cap", "carry_cap"}


def test_the_naive_grasp_mode_unscrews_without_the_alignment() -> None:
    task, _ = load_task(TASK)
    for mode, aligned in (("naive", False), ("robust", True)):
        estd = translate(task, create("tombatossals", "left", grasp=mode)).estd
        assert estd.states_by_name["unscrew_cap"].arm.params["alignment"] is aligned, mode


def _spec(tmp_path: Path, extra: str) -> Path:
    spec = tmp_path / "s.toml"
    spec.write_text(f'name = "s"\ntasks = [{{ file = "{TASK}", judge = "cap", fixture = true }}]\n'
                    f'robots = ["melfa"]\nobjects = ["jam_jar", "spice_jar"]\n{extra}\n')
    return spec


def test_a_parameter_the_cap_approach_lacks_is_a_located_spec_error(tmp_path: Path) -> None:
    spec = _spec(tmp_path, '[perturbations.noise]\nmodel = "cap_approach"\nacross = 0.015\ntranslation = 0.02')
    loaded, found = load_spec(spec)
    assert loaded is None and [(d.code, d.loc.line) for d in found] == [("CMP010", 8)]
    assert found[0].hint == "the 'cap_approach' model's parameters: across, along ('translation' belongs to 'approach')"


def test_a_perturbation_on_an_unlisted_object_and_a_fixture_for_an_object_without_a_cap_are_spec_errors(
        tmp_path: Path) -> None:
    spec = _spec(tmp_path, '[perturbations.noise]\nmodel = "cap_approach"\nobjects = ["jam_jr"]')
    _, found = load_spec(spec)
    assert [(d.code, d.hint) for d in found] == [("CMP023", "did you mean 'jam_jar'?")]
    spec.write_text(spec.read_text().replace('"spice_jar"', '"mug"'))
    _, found = load_spec(spec)
    assert [(d.code, d.loc.line) for d in found] == [("CMP023", 7), ("CMP028", 2)]


def test_the_preset_makes_table_3_4s_cells_of_ten_and_table_3_5s_of_fifteen_on_one_object() -> None:
    loaded, found = load_spec(PRESET)
    assert loaded is not None, found
    chosen = plans(loaded, {"robot": {"tombatossals"}, "arm": {"left"}, "engine": {"mujoco"}})
    counts = {(c.object, c.perturbation, c.grasp): chosen.count(c) for c, _ in chosen.cells}
    assert len(counts) == 8 * 2 + 2 and len(chosen) == 8 * 2 * 10 + 2 * 15
    assert counts[("jam_jar", "cap_noise", "naive")] == 15 and counts[("spice_jar", "none", "robust")] == 10
    assert plans(loaded, {"robot": {"tombatossals"}, "arm": {"left"}, "engine": {"mujoco"}}, trials=2).__len__() == 36


def _record(grasp: str, perturbation: str, index: int, ok: bool, free: bool, twists: float | None,
            robot: str = "tombatossals", error: str = "") -> TrialRecord:
    cell = Cell("unscrew_fixture", robot, "left" if robot == "tombatossals" else "main", "mujoco", grasp, "jam_jar",
                perturbation)
    if error:
        return TrialRecord(cell=cell, index=index, seed=index, status="error", error=error)
    m = {"cap_free": float(free), "cap_on_table": float(ok), "cap_turns": 0.25, "unscrew_time": 12.0 + index}
    return TrialRecord(cell=cell, index=index, seed=index, task_succeeded=ok, judged_succeeded=ok,
                       perturbation={"cap_dx": 0.01, "cap_dy": 0.0, "cap_dz": 0.0, "cap_offset": 0.01}
                       if perturbation == "cap_noise" else {},
                       measurements={**m, **({"twists": twists} if twists is not None else {})})


def test_the_report_sets_tables_3_4_and_3_5_beside_the_thesis_and_names_refused_robots() -> None:
    refusal = ("melfa (main) cannot do unscrew_fixture.xml with object 'jam_jar':\n/x.xml:35:3: error[TRN001]: melfa: "
               "cannot map unscrew state 'unscrew_cap': the melfa has no unscrew primitive\n  hint: ...")
    records = [_record("naive", "none", 0, True, True, 4.0), _record("naive", "none", 1, False, True, None),
               _record("robust", "none", 0, True, True, 5.0), _record("robust", "cap_noise", 0, True, True, 6.0),
               _record("naive", "cap_noise", 0, False, False, 40.0),
               _record("robust", "none", 0, False, False, None, robot="melfa", error=refusal)]
    report = build_report(records)
    rows = {(r.ours.value("robot"), r.table, r.alignment): r for r in report.unscrews}
    assert sorted(rows) == [("melfa", "3.4", "yes"), ("tombatossals", "3.4", "no"), ("tombatossals", "3.4", "yes"),
                            ("tombatossals", "3.5", "no"), ("tombatossals", "3.5", "yes")]
    naive = rows[("tombatossals", "3.4", "no")]
    assert (naive.ours.successes, naive.ours.n, naive.unscrewed, naive.time, naive.moves, naive.counted) == \
        (1, 2, 2, 12.5, 4.0, 1)
    assert rows[("melfa", "3.4", "yes")].refused == \
        "melfa: cannot map unscrew state 'unscrew_cap': the melfa has no unscrew primitive"
    assert report.thesis == []  # no Table 3.3 for an unscrew campaign
    text = render(report, "table")
    assert "70/80 (87.5%)" in text and "71/80 (88.6%)" in text and "78/80 (97.5%)" in text  # Table 3.4
    assert "9/15 (60.0%)" in text and "12/15 (80.0%)" in text  # Table 3.5
    assert "1/2 (50.0%)" in text and "2/2 (100.0%)" in text and "4.00 (of 1)" in text
    assert "refused:\n  unscrew_fixture / melfa / main / mujoco / robust: melfa: cannot map unscrew state" in text
    header = next(line for line in text.splitlines() if line.startswith("task") and "success thesis" in line)
    assert header.split() == ["task", "robot", "arm", "engine", "table", "reactive", "success", "thesis", "ours",
                              "ours", "95%", "unscrewed", "thesis", "ours", "time", "thesis", "ours", "moves",
                              "thesis", "ours", "n", "false", "successes", "errors"]


def test_the_plot_draws_the_unscrew_rates_beside_the_thesis() -> None:
    from atd.campaign.plots import draw_report
    from atd.campaign.report import group

    records = [_record("naive", "none", 0, True, True, 4.0), _record("robust", "cap_noise", 0, False, True, 6.0)]
    svg = draw_report(records, group(records), "svg").decode()
    assert "thesis Tables 3.4, 3.5" in svg and "T3.5 reactive yes" in svg and "thesis: cap unscrewed" in svg
