"""The import graph goes one way (README, *Layout*): the language at the bottom, the robots and
their primitives on it, the translator on those, the engines and the executor on that, campaigns
on the executor, the command line on top. A cycle would make a layer unusable without the one
above it (a factory that needs the executor to import, say), so each new import is checked here."""

from __future__ import annotations

import ast
from pathlib import Path

import networkx as nx

REPO = Path(__file__).resolve().parents[1]
SOURCES = ("atd", "factories", "primitives", "translator")

# The README's layers, bottom first: a module may import its own layer's packages and those below.
LAYER = {"atd.model": 0, "factories": 1, "primitives": 1, "translator": 2,
         "atd.sim": 3, "atd.runtime": 3, "atd.campaign": 4, "atd.cli": 5}


def module_name(path: Path) -> str:
    parts = path.relative_to(REPO).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def imported(path: Path) -> set[str]:
    """The project's modules and names that a file imports, at any depth of its code."""
    names: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(), str(path))):
        if isinstance(node, ast.Import):
            names.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names.add(node.module)
            names.update(f"{node.module}.{alias.name}" for alias in node.names)
    return {name for name in names if name.split(".")[0] in SOURCES}


def module_graph() -> nx.DiGraph:
    """An edge from each project module to each project module it imports (`from atd import api`
    inside atd names atd's submodule, not atd itself)."""
    files = {module_name(path): path for top in SOURCES for path in (REPO / top).rglob("*.py")}
    graph = nx.DiGraph()
    graph.add_nodes_from(files)
    for module, path in files.items():
        graph.add_edges_from((module, name) for name in imported(path) if name in files and name != module)
    return graph


def package(module: str) -> str:
    """The README's package a module belongs to (the longest prefix that names one), else its own name."""
    return max((name for name in LAYER if module == name or module.startswith(name + ".")), key=len, default=module)


def test_no_module_imports_one_that_imports_it_back():
    cycles = list(nx.simple_cycles(module_graph()))
    assert not cycles, f"import cycles: {cycles[:5]}"


def test_no_layer_imports_a_layer_above_it_and_packages_form_no_cycle():
    modules = module_graph()
    packages = nx.DiGraph((package(a), package(b)) for a, b in modules.edges if package(a) != package(b))
    upward = [(a, b) for a, b in modules.edges
              if package(a) in LAYER and package(b) in LAYER and LAYER[package(a)] < LAYER[package(b)]]
    assert not upward, f"imports from a lower layer into a higher one: {upward[:5]}"
    assert nx.is_directed_acyclic_graph(packages), f"package cycles: {list(nx.simple_cycles(packages))[:5]}"
