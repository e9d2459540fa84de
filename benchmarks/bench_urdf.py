"""Time `read_urdf` on generated URDFs: binary trees of boxes on revolute joints, each link
with its mass and inertia. Reading is linear in the links (issue 30: it was quadratic,
4,000 links 57 s); atd imports at most `MAX_LINKS` (1,000), so the cap is lifted here to
show the cost beyond it. Best of `--repeat` runs, in CPU and wall time.

    python benchmarks/bench_urdf.py [--links 1000 10000] [--repeat 3]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import factories.urdf_tree
from factories.urdf import read_urdf


def tree(links: int) -> str:
    """A URDF of `links` links, link k hanging from link (k - 1) // 2."""
    inertial = '<inertial><mass value="1"/><inertia ixx="0.01" iyy="0.01" izz="0.01"/></inertial>'
    box = '<collision><geometry><box size="0.04 0.04 0.04"/></geometry></collision>'
    lines = ['<robot name="tree">', *(f'<link name="l{k}">{inertial}{box}</link>' for k in range(links))]
    lines += [f'<joint name="j{k}" type="revolute"><parent link="l{(k - 1) // 2}"/><child link="l{k}"/>'
              '<origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit effort="50" velocity="2" lower="-1" upper="1"/>'
              "</joint>" for k in range(1, links)]
    return "\n".join([*lines, "</robot>"])


def seconds(path: Path, repeat: int) -> tuple[float, float]:
    """The best (CPU, wall) seconds of `repeat` reads of `path`."""
    best = (float("inf"), float("inf"))
    for _ in range(repeat):
        cpu, wall = time.process_time(), time.perf_counter()
        read_urdf(path)
        best = min(best, (time.process_time() - cpu, time.perf_counter() - wall))
    return best


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--links", type=int, nargs="+", default=[1000, 10000])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    factories.urdf_tree.MAX_LINKS = max(args.links)
    print(f"{'links':>8} {'CPU s':>8} {'wall s':>8}")
    with tempfile.TemporaryDirectory() as folder:
        for links in args.links:
            path = Path(folder) / f"tree{links}.urdf"
            path.write_text(tree(links))
            cpu, wall = seconds(path, args.repeat)
            print(f"{links:>8} {cpu:>8.2f} {wall:>8.2f}")


if __name__ == "__main__":
    main()
