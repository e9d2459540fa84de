"""Issue 12: a mesh is checked before any engine sees it; what the validator accepts loads
in both engines (tests/sim/test_scene.py runs a checked mesh in each)."""

from __future__ import annotations

import re
import struct
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from atd.cli import main
from atd.model import load_task
from atd.model.meshcheck import MeshError, check_mesh

CUBE = np.array([[x, y, z] for x in (0, 0.04) for y in (0, 0.04) for z in (0, 0.04)])
CUBE_FACES = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
              (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]


def obj_text(vertices=CUBE, faces=CUBE_FACES) -> str:
    return "".join(f"v {x} {y} {z}\n" for x, y, z in vertices) + "".join(
        "f " + " ".join(str(i + 1) for i in face) + "\n" for face in faces)


def binary_stl(vertices=CUBE, faces=CUBE_FACES) -> bytes:
    body = b"".join(struct.pack("<12fH", 0, 0, 0, *[c for i in face for c in vertices[i]], 0) for face in faces)
    return b"\0" * 80 + struct.pack("<I", len(faces)) + body


def ascii_stl(vertices=CUBE, faces=CUBE_FACES) -> str:
    facets = "".join("facet normal 0 0 0\n outer loop\n" + "".join(
        f"  vertex {x} {y} {z}\n" for x, y, z in (vertices[i] for i in face)) + " endloop\nendfacet\n"
        for face in faces)
    return f"solid cube\n{facets}endsolid cube\n"


@pytest.mark.parametrize("name, content", [("c.obj", obj_text()), ("c.stl", binary_stl()), ("a.stl", ascii_stl())])
def test_a_good_mesh_passes_in_every_format(tmp_path: Path, name: str, content) -> None:
    path = tmp_path / name
    path.write_bytes(content if isinstance(content, bytes) else content.encode())
    assert check_mesh(path).shape == (12, 3, 3)


BAD = {
    "text named .stl": ("m.stl", b"hello, this is not a mesh\n", "not an STL file"),
    "garbage .obj": ("m.obj", bytes(range(256)) * 8, "is not an OBJ statement"),
    "NaN vertex": ("m.obj", obj_text(np.where(CUBE == 0.04, np.nan, CUBE)).encode(), "not a finite number"),
    "flat": ("m.obj", obj_text(CUBE * [1, 1, 0]).encode(), "degenerate"),
    "faces with no area": ("m.obj", obj_text(faces=[(0, 0, 0), (1, 1, 1)]).encode(), "degenerate"),
    "index out of range": ("m.obj", obj_text(faces=[(0, 1, 99)]).encode(), "does not exist"),
    "index not a number": ("m.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 inf\n", "not a vertex number"),
    "no faces": ("m.obj", obj_text(faces=[]).encode(), "no faces"),
    "truncated binary stl": ("m.stl", binary_stl()[:-7], "not an STL file"),
    "in millimetres": ("m.stl", binary_stl(CUBE * 1000), "outside [0.001, 10] m"),
    "unsupported format": ("m.dae", b"<COLLADA/>", "use an STL or OBJ file"),
    "NaN vertex in binary STL": ("m.stl", binary_stl(np.where(CUBE == 0.04, np.nan, CUBE)), "not a finite number"),
    "zero-area binary STL": ("m.stl", binary_stl(faces=[(0, 0, 0), (1, 1, 1)]), "degenerate"),
    # float() and int() read '1_0' as 10; no engine's mesh loader does
    "underscore in an OBJ coordinate": ("m.obj", obj_text().replace("0.04", "0_04", 1).encode(),
                                        "line 2: '0_04' is not a number"),
    "underscore in a vertex number": ("m.obj", obj_text().replace("f 1 2 4", "f 1 2 0_4").encode(),
                                      "line 9: '0_4' is not a vertex number"),
    "underscore in an ASCII STL": ("m.stl", ascii_stl().replace("0.04", "0_04", 1).encode(),
                                   "line 5: '0_04' is not a number"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_bad_mesh_is_refused_with_the_reason(tmp_path: Path, case: str) -> None:
    name, content, reason = BAD[case]
    (tmp_path / name).write_bytes(content)
    with pytest.raises(MeshError, match=re.escape(reason)):
        check_mesh(tmp_path / name)


def test_a_fifo_as_a_mesh_is_refused_at_once(tmp_path: Path) -> None:
    import os
    os.mkfifo(tmp_path / "m.stl")
    with pytest.raises(MeshError, match="not a regular file"):
        check_mesh(tmp_path / "m.stl")


TASK = """<statemachine>
  <object><shape>m.stl</shape><class>box</class><size>0.04 0.04 0.04</size>
    <pose>1 0 0 0.1 0 1 0 0 0 0 1 0.02 0 0 0 1</pose></object>
  <state name="wait" type="move"><path><position>0.1 0 0.2</position></path></state>
  <state name="done" type="success"/>
  <transition origin="wait" destination="done"><timeout>0.01</timeout></transition>
</statemachine>"""


def test_validate_locates_a_broken_mesh_and_run_refuses_it_before_any_engine(tmp_path: Path) -> None:
    (tmp_path / "m.stl").write_text("solid x\nfacet\n vertex 0 0 nan\nendsolid\n")
    (tmp_path / "t.xml").write_text(TASK)
    _, found = load_task(tmp_path / "t.xml")
    assert [(d.code, d.loc.line) for d in found] == [("ATD216", 2)]
    for engine in ("mujoco", "pybullet"):
        result = CliRunner().invoke(main, ["run", str(tmp_path / "t.xml"), "--robot", "melfa", "--engine", engine])
        assert result.exit_code == 1 and "ATD216" in result.output


def test_a_mesh_missing_at_run_time_is_invalid_input(tmp_path: Path) -> None:
    (tmp_path / "t.xml").write_text(TASK)
    estd = tmp_path / "t.melfa.estd.xml"
    assert CliRunner().invoke(main, ["translate", str(tmp_path / "t.xml"), "-r", "melfa", "-q"]).exit_code == 0
    result = CliRunner().invoke(main, ["run", str(estd)])
    assert result.exit_code == 1 and "no such file" in result.output
