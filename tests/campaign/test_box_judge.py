"""Issue 31: the box judge counts what is left in the box from the ground truth, a false
"empty" is a task's success with an object left, and a world is drawn per trial."""

from __future__ import annotations

from pathlib import Path

from atd.campaign.cells import TrialPlan, plans
from atd.campaign.formats import render
from atd.campaign.judge import BoxJudge
from atd.campaign.plots import attempts_by_remaining, draw_report
from atd.campaign.record import Cell, TrialRecord
from atd.campaign.report import build_report
from atd.campaign.spec import load_spec
from atd.campaign.trial import believed, drawn_world
from tests.conftest import EXAMPLES


class Truth:
    """What the judge may read of a simulated robot: the box's contents, now."""

    def __init__(self, *contents: list[str]) -> None:
        self.contents = list(contents)
        self.held = 0.0

    def objects_inside(self, container: str) -> list[str]:
        return self.contents[0] if len(self.contents) == 1 else self.contents.pop(0)

    def hold_still(self, seconds: float) -> None:
        self.held += seconds


def test_an_object_left_in_the_box_fails_the_trial_and_a_task_that_said_empty_made_a_false_empty():
    truth = Truth(["duck", "mug"], ["mug"])
    judge = BoxJudge(truth, "box")  # type: ignore[arg-type]
    judge(truth)  # type: ignore[arg-type]
    assert judge.verdict.succeeded is False and judge.verdict.reason == "1 of 2 objects left in 'box': mug"
    assert judge.verdict.measurements == {"objects": 2.0, "remaining": 1.0} and truth.held > 0
    record = TrialRecord(cell=Cell("empty_the_box_vision", "melfa", "main", "mujoco", "robust", "task", "none"),
                         index=0, seed=1, task_succeeded=True, judged_succeeded=judge.verdict.succeeded)
    assert record.false_success


def test_the_judge_stops_a_run_once_the_box_is_empty_looking_once_a_second():
    truth = Truth(["ball"], ["ball"], [], [])
    stopped: list[str] = []
    judge = BoxJudge(truth, "box", stopped.append)  # type: ignore[arg-type]
    for tick in range(1, 400):
        judge.watch(tick * 0.005)
    assert stopped == []  # one look, at 1 s: the ball is still there
    judge.watch(2.0)
    assert stopped == ["the judge sees 'box' empty"]
    # Two attempts while the ball was in the box (the run began with it), none after.
    assert judge.by_remaining([0.4, 1.5]) == {"attempts_with_1_left": 2.0}


SPEC = """name = "box"
tasks = [{{ file = "{task}", judge = "box" }}]
robots = ["melfa"]
world = {{ objects = 3, into = "box", from = {pool} }}
"""


def test_a_world_is_drawn_per_trial_from_its_seed_alone(tmp_path: Path):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(task=EXAMPLES / "empty_the_box_vision.xml", pool='["ball", "tape", "duck", "mug"]'))
    loaded, found = load_spec(spec)
    assert found == [] and loaded is not None
    first, second = list(plans(loaded, trials=2))
    belief, _ = believed(first.task_file, "melfa", "main", "robust", "task")

    def world(plan: TrialPlan) -> dict[str, tuple]:
        return {o.name: tuple(o.pose[:3, 3].round(6)) for o in drawn_world(plan, belief).objects}

    assert world(first) == world(first) and world(first) != world(second)
    assert len(world(first)) == 3 and set(world(first)) <= {"ball", "tape", "duck", "mug"}


def test_a_world_of_an_unknown_library_object_is_refused_located(tmp_path: Path):
    spec = tmp_path / "s.toml"
    spec.write_text(SPEC.format(task=EXAMPLES / "empty_the_box_vision.xml", pool='["ball", "duk"]'))
    loaded, found = load_spec(spec)
    assert loaded is None and [(d.code, d.loc.line) for d in found] == [("CMP012", 4)]
    assert "no object 'duk' in the library" in found[0].message


def test_a_world_with_a_clearance_lays_its_objects_and_one_out_of_range_is_refused_located(tmp_path: Path):
    spec = tmp_path / "s.toml"
    pool = '["ball", "tape", "duck", "mug"]'
    spec.write_text(SPEC.format(task=EXAMPLES / "empty_the_box_vision.xml", pool=pool + ", clearance = 0.03"))
    loaded, found = load_spec(spec)
    assert found == [] and loaded is not None
    plan = next(iter(plans(loaded, trials=1)))
    belief, _ = believed(plan.task_file, "melfa", "main", "robust", "task")
    scene = drawn_world(plan, belief)
    floor = scene.containers[0].inner_bounds()[0][2]
    assert all(o.pose[2, 3] < floor + 0.05 for o in scene.objects)  # laid on the floor, none dropped onto another
    spec.write_text(SPEC.format(task=EXAMPLES / "empty_the_box_vision.xml", pool=pool + ", clearance = 0.5"))
    loaded, found = load_spec(spec)
    assert loaded is None and [(d.code, d.loc.line) for d in found] == [("CMP012", 4)]
    assert "0.5" in found[0].message and "[0, 0.1] m" in found[0].message


def box_trial(task: str, index: int, attempts: dict[int, float], left: int, said_empty: bool) -> TrialRecord:
    measured = {f"attempts_with_{k}_left": n for k, n in attempts.items()}
    return TrialRecord(cell=Cell(task, "melfa", "main", "mujoco", "robust", "task", "none"), index=index, seed=index,
                       task_succeeded=said_empty, judged_succeeded=not left, sim_time=100.0 + 20 * index,
                       measurements={"objects": 2.0, "remaining": float(left),
                                     "attempts": sum(attempts.values()), **measured})


def test_the_report_puts_table_3_6_beside_ours_and_counts_false_empties():
    records = [box_trial("empty_the_box_vision", 0, {2: 1.0, 1: 1.0}, 0, True),
               box_trial("empty_the_box_vision", 1, {2: 3.0, 1: 1.0}, 1, True),
               box_trial("empty_the_box_random", 0, {2: 4.0, 1: 6.0}, 0, False)]
    report = build_report(records)
    assert report.thesis == []  # not Table 3.3's shape
    text = render(report, "table")
    assert "thesis Table 3.6" in text
    vision = next(line for line in text.splitlines() if " vision " in line)
    # thesis 7.1 attempts, ours 3.0; 101 s, ours 110 s; 100%, ours 50% of 2; one false "empty"
    assert vision.split()[4:9] == ["vision", "7.1", "3.0", "101", "s"] and vision.split()[-1] == "1"
    assert "50.0%" in vision and " 110 s " in vision
    assert attempts_by_remaining(records) == {"empty_the_box_random": {2: 4.0, 1: 6.0},
                                              "empty_the_box_vision": {2: 2.0, 1: 1.0}}
    assert draw_report(records, report.groups, "svg").startswith(b"<?xml")
