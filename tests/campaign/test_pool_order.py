"""The order a campaign hands its trials out in: the costliest cells first, the same trials."""

from __future__ import annotations

from atd.campaign.cells import plans
from atd.campaign.spec import load_spec
from tests.conftest import EXAMPLES


def test_the_preset_runs_its_pybullet_cells_first_and_its_cheapest_last_with_the_same_trials() -> None:
    loaded, found = load_spec(EXAMPLES / "campaigns" / "table_3_3.toml")
    assert loaded is not None, found
    chosen = plans(loaded, trials=2)
    ordered = chosen.longest_first()
    kinds = [(c.engine, c.grasp, c.perturbation) for c, _ in ordered.cells]
    per_kind = len(kinds) // 8  # 4 robot arms x 10 objects in each of the 8 kinds
    assert [kinds[i] for i in range(0, len(kinds), per_kind)] == [
        ("pybullet", "robust", "approach"), ("pybullet", "naive", "approach"), ("pybullet", "robust", "none"),
        ("pybullet", "naive", "none"), ("mujoco", "robust", "approach"), ("mujoco", "naive", "approach"),
        ("mujoco", "robust", "none"), ("mujoco", "naive", "none")]
    assert all(len(set(kinds[i:i + per_kind])) == 1 for i in range(0, len(kinds), per_kind))
    # within a kind, the spec's order: robots, then objects
    assert [c for c, _ in ordered.cells[:per_kind]] == [
        c for c, _ in chosen.cells if (c.engine, c.grasp, c.perturbation) == kinds[0]]
    assert sorted(ordered, key=lambda p: (p.cell.key, p.index)) == sorted(chosen, key=lambda p: (p.cell.key, p.index))
    assert len(ordered) == len(chosen) == 640
