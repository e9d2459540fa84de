"""The reference half of docs/estd.md (every controller and condition with its parameters),
written from the vocabulary in atd/model/controllers.py: parameters are declared there once,
so the reference a factory author reads cannot fall behind the code.

    python -m atd.model.estd_doc docs/estd.md    # rewrite the reference in place
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Iterable, Mapping

from atd.model.controllers import (ARM_CONTROLLERS, CONDITIONS, HAND_CONTROLLERS, ConditionSpec, ControllerSpec,
                                   ParamSpec, format_value)

#: Where the generated reference starts; everything above it is written by hand.
START = "## Arm controllers"


def reference() -> str:
    """The generated part of docs/estd.md, from `START` to the end of the file."""
    sections = [("Arm controllers", ARM_CONTROLLERS.values()), ("Hand controllers", HAND_CONTROLLERS.values()),
                ("Conditions", CONDITIONS.values())]
    blocks = [block for title, specs in sections for block in (f"## {title}", *map(_entry, specs))]
    return "\n\n".join(blocks) + "\n"


def rewrite(path: Path) -> None:
    """Replace `path`'s reference (from `START` on) with the generated one."""
    text = path.read_text()
    head, found, _ = text.partition(START)
    if not found:
        raise SystemExit(f"{path}: no '{START}' heading to put the reference under")
    path.write_text(head + reference())


def _entry(spec: ControllerSpec | ConditionSpec) -> str:
    if isinstance(spec, ControllerSpec):
        title, about = f"### `{spec.name}` ({spec.source})", spec.doc
    else:
        reads = f" Reads sensors of kind `{spec.reads.value}`." if spec.reads else ""
        title, about = f"### `{spec.kind}`", spec.doc + reads
    return "\n\n".join([title, about, *_table(spec.params)])


def _table(params: Mapping[str, ParamSpec]) -> Iterable[str]:
    if not params:
        return []
    rows = ["| parameter | type | default | unit | meaning |", "|---|---|---|---|---|"]
    rows += [f"| `{name}` | {p.type.value} | {_default(p)} | {p.unit} | {p.doc} |" for name, p in params.items()]
    return ["\n".join(rows)]


def _default(p: ParamSpec) -> str:
    if p.required:
        return "required"
    if p.default is None or p.default == ():
        return "unset"
    return format_value(p.default)


if __name__ == "__main__":
    rewrite(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/estd.md"))
