"""The package's dependencies point one way (the paper's Figure 2): perception is fed by the
simulator and feeds the programs; programs → value maps → planning → control; base modules
(errors, config range checks, geometry, the object catalog, the table layout, table places,
the robot protocol, PNG figures) import no stage; and no module imports, directly or through others, itself."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).resolve().parents[1] / "src" / "voxposer"
BASE = {"errors", "config_checks", "geometry", "catalog", "tabletop", "places", "robot", "plotting"}
#: subpackage → the subpackages and base modules it may import.
ALLOWED: dict[str, set[str]] = {
    "errors": set(),
    "config_checks": {"errors"},
    "robot": set(),
    "plotting": {"errors"},
    "geometry": {"errors"},
    "catalog": {"errors"},
    "tabletop": {"catalog"},
    "places": {"errors", "tabletop"},
    "valuemaps": BASE,
    "perception": BASE,
    "envs": BASE | {"perception"},
    "planning": BASE | {"valuemaps"},
    "lmp": BASE | {"valuemaps", "perception"},
    "control": BASE | {"valuemaps", "planning", "perception"},
    "pipeline": BASE | {"valuemaps", "planning", "perception", "lmp", "control"},
    "unet": BASE | {"valuemaps", "planning", "perception"},
    "bench": BASE | {"valuemaps", "planning", "perception", "lmp", "control", "envs", "pipeline",
                     "unet", "voxposer"},
    "learning": BASE | {"valuemaps", "planning", "perception", "lmp", "control", "pipeline"},
}
#: the only perception modules the simulator may import: the observation types it produces.
ENVS_MAY_USE = {"voxposer.perception.observation"}


def _module_name(path: Path) -> str:
    parts = path.relative_to(SRC.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules() -> dict[str, Path]:
    return {_module_name(p): p for p in SRC.rglob("*.py")}


def _imports(path: Path, known: set[str]) -> set[str]:
    """voxposer modules ``path`` imports anywhere (top level, functions, TYPE_CHECKING)."""
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text())):
        if isinstance(node, ast.Import):
            found |= {a.name for a in node.names if a.name.startswith("voxposer")}
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0 \
                and node.module.startswith("voxposer"):
            for alias in node.names:
                sub = f"{node.module}.{alias.name}"
                found.add(sub if sub in known else node.module)
    return {m for m in found if m in known}


def _stage(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "voxposer"


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    mods = _modules()
    return {m: _imports(p, set(mods)) for m, p in mods.items()}


def test_no_import_against_the_flow(graph: dict[str, set[str]]) -> None:
    wrong = []
    for module, targets in graph.items():
        stage = _stage(module)
        if stage not in ALLOWED:
            continue  # the CLI and the package root may import anything
        for target in targets:
            other = _stage(target)
            if other != stage and other not in ALLOWED[stage]:
                wrong.append(f"{module} imports {target}")
            if stage == "envs" and other == "perception" and target not in ENVS_MAY_USE:
                wrong.append(f"{module} imports {target} (the simulator knows no detection)")
    assert not wrong, "\n".join(sorted(wrong))


def test_no_module_imports_itself_through_others(graph: dict[str, set[str]]) -> None:
    # package __init__ files re-export their submodules: an edge into a package counts as an
    # edge into the submodules it re-exports, so it is followed, not treated as a cycle
    cycles: list[list[str]] = []
    state: dict[str, int] = {}
    stack: list[str] = []

    def visit(node: str) -> None:
        state[node] = 1
        stack.append(node)
        for nxt in sorted(graph.get(node, ())):
            if nxt.startswith(node + ".") or node.startswith(nxt + "."):
                continue  # a package and its own submodules
            if state.get(nxt) == 1:
                cycles.append(stack[stack.index(nxt):] + [nxt])
            elif nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = 2

    for module in sorted(graph):
        if module not in state:
            visit(module)
    assert not cycles, "\n".join(" → ".join(c) for c in cycles)
