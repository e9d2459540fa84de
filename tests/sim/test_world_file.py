"""World files: what is true on the table, read with located errors, built into a scene
(no engine needed: the scene is made before the engine starts)."""

from __future__ import annotations

import itertools
import textwrap
from pathlib import Path
from typing import Callable

import numpy as np
import pytest

from atd.sim.scene import Body, Container, Scene, bounding_box, half_extent
from atd.sim.library import library
from atd.sim.world import World, WorldError, load_world

BOX = """
    [[container]]
    name = "box"
    position = [0.3, 0.15]
    size = [0.30, 0.25, 0.10]
"""


@pytest.fixture
def world_file(tmp_path: Path) -> Callable[[str], Path]:
    def write(text: str) -> Path:
        path = tmp_path / "world.toml"
        path.write_text(textwrap.dedent(text).lstrip())
        return path

    return write


def _loaded(path: Path) -> World:
    world, found = load_world(path)
    assert world is not None, [d.render() for d in found]
    return world


def _problems(path: Path) -> list[tuple[str, int, str, str | None]]:
    world, found = load_world(path)
    assert world is None
    return [(d.code, d.loc.line, d.message, d.hint) for d in found]


def _scene_problems(path: Path, belief: Scene = Scene()) -> list[tuple[str, int, str, str | None]]:
    with pytest.raises(WorldError) as caught:
        _loaded(path).scene(belief, 0)
    return [(d.code, d.loc.line, d.message, d.hint) for d in caught.value.diagnostics]


def test_a_misspelt_library_object_is_located_with_the_name_it_meant(world_file):
    path = world_file("""
        [[object]]
        library = "duk"
        position = [0.1, 0.3]
    """)
    assert _problems(path) == [("WLD020", 2, "no object 'duk' in the library", "did you mean 'duck'?")]
    assert _problems(world_file('[[drop]]\ninto = "box"\nobjects = ["mug", "stapeler"]\n'))[0][:2] == ("WLD020", 3)


def test_an_object_off_the_table_is_located_with_the_table_s_extent(world_file):
    path = world_file("""
        [[object]]
        shape = "box"
        size = [0.05, 0.05, 0.05]
        position = [0.9, 0.0]
    """)
    [(code, line, message, hint)] = _problems(path)
    assert (code, line, message) == ("WLD021", 4, "(0.9, 0) is not over the table")
    assert hint == "the table top spans x -0.12 to 0.52 and y -0.6 to 0.6 m"


def test_bad_numbers_are_located_and_say_what_is_allowed(world_file):
    path = world_file("""
        [[object]]
        shape = "cylinder"
        size = [0.05, -1]
        position = [0.1, 0.0, nan]
        mass = "heavy"
        rpy = [0, 0]
    """)
    assert {(code, line, message) for code, line, message, _ in _problems(path)} == {
        ("WLD012", 3, "'size': -1 is outside [0.001, 10] m"),
        ("WLD012", 4, "'position': nan is not a finite number; give one in [-10, 10] m"),
        ("WLD012", 5, "'mass' must be a number, not 'heavy'"),
        ("WLD012", 6, "'rpy' must be a list of 3 numbers, not [0, 0]"),
    }


def test_unknown_keys_and_tables_are_located_with_what_was_meant(world_file):
    path = world_file(BOX + """
        wal = 0.02

        [objects]
        library = "duck"
    """)
    assert [(c, line, m, h) for c, line, m, h in _problems(path)] == [
        ("WLD010", 6, "unknown key 'wal' in [[container]]", "did you mean 'wall'?"),
        ("WLD010", 8, "unknown table 'objects'", "did you mean 'object'?"),
    ]


def test_missing_keys_wrong_shapes_and_clashing_names_are_located(world_file):
    path = world_file("""
        [[object]]
        library = "duck"

        [[object]]
        shape = "cone"
        position = [0.1, 0.1]

        [[object]]
        library = "mug"
        shape = "box"
        position = [0.1, 0.1]

        [[container]]
        name = "box"
        position = [0.3, 0.15]
        size = [0.1, 0.1, 0.05]
        wall = 0.06

        [[object]]
        library = "ball"
        name = "my ball"
        position = [0.1, 0.1]
    """)
    assert [(c, line, m) for c, line, m, _ in _problems(path)] == [
        ("WLD011", 1, "[[object]] needs 'position'"),
        ("WLD012", 5, "no shape 'cone'"),
        ("WLD012", 8, "an object is a library object or a described shape, not both"),
        ("WLD025", 17, "walls 0.06 m thick leave no room inside a 0.1 x 0.1 x 0.05 m box"),
        ("WLD023", 21, "'my ball' cannot name an object or container"),
    ]


def test_a_name_given_twice_is_an_error_and_nameless_objects_get_names_of_their_own(world_file):
    twice = world_file(BOX + """
        [[object]]
        library = "duck"
        name = "box"
        position = [0.0, 0.3]
    """)
    assert _problems(twice) == [("WLD023", 6, "'box' names two things",
                                 "give each object and container a name of its own")]
    world = _loaded(world_file(BOX + """
        [[object]]
        library = "duck"
        position = [0.0, 0.3]

        [[object]]
        library = "mug"
        name = "duck_2"
        position = [0.0, -0.3]

        [[drop]]
        objects = ["duck", "mug"]
        into = "box"
    """))
    assert [o.name for o in world.scene(Scene(), 0).objects] == ["duck", "duck_2", "duck_3", "mug"]


def test_a_drop_into_a_container_neither_file_names_is_located(world_file):
    path = world_file(BOX + """
        [[drop]]
        objects = ["mug"]
        into = "bx"
    """)
    assert _scene_problems(path) == [("WLD024", 6, "no container 'bx' to drop into", "did you mean 'box'?")]


def test_an_object_named_like_a_container_of_the_task_is_located(world_file):
    path = world_file("""
        [[object]]
        library = "mug"
        name = "tray"
        position = [0.0, 0.3]
    """)
    tray = Container("tray", np.eye(4), (0.2, 0.2, 0.05))
    assert _scene_problems(path, Scene(containers=(tray,))) == [
        ("WLD023", 1, "'tray' names an object here and a container of the task", "give the object another name")]


def test_a_drop_goes_into_the_task_s_own_container_when_the_file_has_none(world_file):
    path = world_file("""
        [[drop]]
        objects = ["ball"]
        into = "tray"
    """)
    tray = Container("tray", np.eye(4), (0.2, 0.2, 0.05))
    scene = _loaded(path).scene(Scene(containers=(tray,)), 0)
    assert scene.containers == (tray,) and tray.holds(scene.objects[0].pose[:3, 3])


def test_placed_objects_that_cut_into_each_other_or_the_table_are_located(world_file):
    path = world_file("""
        [[object]]
        library = "duck"
        position = [0.1, 0.3, 0.1]

        [[object]]
        library = "mug"
        position = [0.1, 0.3, 0.12]

        [[object]]
        library = "stapler"
        position = [0.1, -0.3, 0.0]
    """)
    assert [(c, line, m) for c, line, m, _ in _scene_problems(path)] == [
        ("WLD022", 5, "'mug' cuts into 'duck'"),
        ("WLD022", 9, "'stapler' reaches 0.025 m into the table"),
    ]


def test_an_object_without_z_rests_on_whatever_is_below_it(world_file):
    world = _loaded(world_file(BOX + """
        [[object]]
        library = "stapler"
        position = [0.3, 0.15]

        [[object]]
        shape = "box"
        size = [0.04, 0.04, 0.02]
        position = [0.3, 0.15]

        [[object]]
        shape = "sphere"
        size = [0.02]
        position = [0.0, -0.2]
    """))
    stapler, block, ball = world.scene(Scene(), 0).objects
    assert stapler.pose[2, 3] == pytest.approx(0.01 + 0.025)  # on the box's floor, 1 cm thick
    assert block.pose[2, 3] == pytest.approx(0.01 + 0.05 + 0.01)  # on the stapler
    assert ball.pose[2, 3] == pytest.approx(0.02)  # on the table


def test_the_world_s_objects_replace_the_task_s_and_its_obstacles_stay(world_file):
    believed = Body("object", "box", (0.05, 0.05, 0.05), np.eye(4), 0.2, 1.0)
    wall = Body("obstacle0", "box", (0.1, 0.1, 0.1), np.eye(4), 1.0, 1.0)
    belief = Scene(believed, (wall,))
    dropped = _loaded(world_file(BOX + '[[drop]]\nobjects = ["ball"]\ninto = "box"\n')).scene(belief, 0)
    assert [o.name for o in dropped.objects] == ["ball"] and dropped.obstacles == (wall,) and dropped.settle
    boxed = _loaded(world_file(BOX)).scene(belief, 0)
    assert boxed.objects == (believed,) and [c.name for c in boxed.containers] == ["box"] and not boxed.settle


def test_drops_are_drawn_from_the_seed_inside_the_box_and_clear_of_each_other(world_file):
    world = _loaded(world_file(BOX + """
        [[drop]]
        objects = ["duck", "mug", "ball", "stapler", "tape"]
        into = "box"
    """))
    first, again, other = (world.scene(Scene(), seed).objects for seed in (4, 4, 5))
    assert all(np.array_equal(a.pose, b.pose) for a, b in zip(first, again))
    assert not any(np.allclose(a.pose, b.pose) for a, b in zip(first, other))
    box = world.scene(Scene(), 4).containers[0]
    low, high = box.inner_bounds()
    centres = np.array([o.pose[:3, 3] for o in first])
    assert (centres[:, :2] > low[:2]).all() and (centres[:, :2] < high[:2]).all()
    radius = [np.linalg.norm(bounding_box(o.kind, o.size)) / 2 for o in first]
    for i, j in itertools.combinations(range(len(first)), 2):  # nothing starts inside anything
        assert np.linalg.norm(centres[i] - centres[j]) >= radius[i] + radius[j]


def test_a_box_too_small_for_what_is_dropped_into_it_is_located(world_file):
    path = world_file("""
        [[container]]
        name = "cup"
        position = [0.3, 0.15]
        size = [0.06, 0.06, 0.05]

        [[drop]]
        objects = ["duck"]
        into = "cup"
    """)
    [(code, line, message, _)] = _scene_problems(path)
    assert (code, line) == ("WLD025", 6) and message.startswith("'duck' (0.")


def test_a_drop_with_a_clearance_lays_its_objects_resting_that_far_from_the_walls_and_apart(world_file):
    world = _loaded(world_file(BOX + """
        [[drop]]
        objects = ["duck", "mug", "ball", "stapler", "tape"]
        into = "box"
        clearance = 0.03
    """))
    for seed in range(20):
        scene = world.scene(Scene(), seed)
        box = scene.containers[0]
        low, high = box.inner_corners()
        footprints = []
        for body in scene.objects:
            local = np.linalg.solve(box.pose, body.pose)
            shape = library()[body.name]  # as laid: a mesh by the shape the library gives it
            reach = np.array([half_extent(shape.shape.value, shape.size, local[:3, :3], axis) for axis in np.eye(3)])
            assert (local[:2, 3] - reach[:2] >= low[:2] + 0.03 - 1e-9).all(), (seed, body.name)
            assert (local[:2, 3] + reach[:2] <= high[:2] - 0.03 + 1e-9).all(), (seed, body.name)
            assert local[2, 3] - reach[2] == pytest.approx(low[2], abs=2e-3)  # resting on the floor, not dropped
            footprints.append((local[:2, 3] - reach[:2], local[:2, 3] + reach[:2]))
        for (lo, hi), (lo2, hi2) in itertools.combinations(footprints, 2):
            assert (np.minimum(hi, hi2) - np.maximum(lo, lo2) <= 1e-3).any(), seed


def test_a_clearance_the_box_cannot_give_is_located(world_file):
    too_much = world_file(BOX + """
        [[drop]]
        objects = ["duck", "mug", "ball", "stapler", "tape"]
        into = "box"
        clearance = 0.09
    """)
    [(code, line, message, hint)] = _scene_problems(too_much)
    assert (code, line) == ("WLD025", 6) and "no room to lay 5 objects 0.09 m from the walls of 'box'" in message
    negative = world_file(BOX + """
        [[drop]]
        objects = ["duck"]
        into = "box"
        clearance = -0.01
    """)
    [(code, line, message, _)] = _problems(negative)
    assert (code, line, message) == ("WLD012", 9, "'clearance': -0.01 is outside [0, 0.1] m")
