"""The shape of the hil package: rooms, the direction of their imports, no cycles.

Every module's imports are read with `ast` (module level, inside functions and under
TYPE_CHECKING alike: each is a dependency), each module is mapped to its room (the package
right under hil), and the test fails on

* a module outside every room (hil.<room>.<...> only; hil/__init__.py aside),
* an import from a lower room into a higher one (ROOMS, lowest first; hil.<room>/__init__.py
  says what each owns and may import),
* any cycle between modules, inside a room too,
* a private name (``_x``) imported from another module,
* an import inside a function that is not one of the heavy optional packages (each command
  imports those only when it uses them),
* a module over MAX_LINES lines whose docstring does not say why it is long.
"""
from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

PKG = Path(__file__).resolve().parents[2] / "hil" / "src" / "hil"

#: the rooms, lowest first: a module may import its own room and the rooms before it
ROOMS = ("util", "io", "bus", "scenario", "sim", "targets", "apps", "rig", "results", "reference",
         "plots", "runs", "parallel", "bench", "verify", "cli")
#: what may be imported inside a function: slow to import (seconds in the UML guest) and
#: needed by few commands or late in a run -- and the hil modules that import these at load
HEAVY = {
    "matplotlib": "the figures only",
    "scipy": "the reference designs and the covariance study only",
    "dask": "--workers/--scheduler only", "distributed": "--workers/--scheduler only",
    "tqdm": "a progress bar on a terminal only",
    "control": "the LQG benchmark only",
    "cantools": "only when the DBC must be parsed (the digest spares it)",
    "can": "python-can: interfaces other than SocketCAN, ASC/BLF logs, live views only",
    "cryptography": "imported while the session listens to the bus, off the start-up path",
    "rich": "`hil live` only",
    "importlib.metadata": "`hil --version` only (0.1 s in the UML guest)",
    "numpy": "the simulator and the results: `hil run` imports them while its session listens "
             "to the bus (0.2 s in the UML guest)",
}


def heavy(target: str) -> bool:
    return any(target == h or target.startswith(h + ".") for h in HEAVY)
MAX_LINES = 400
LONG_REASON = "Why this module is long:"


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PKG.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {module_name(p): p for p in sorted(PKG.rglob("*.py"))}


def room(module: str) -> str | None:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 and parts[1] in ROOMS else None


def absolute(module: str, path: Path, node: ast.ImportFrom) -> str:
    if not node.level:
        return node.module or ""
    base = module.split(".")
    if path.name != "__init__.py":
        base = base[:-1]
    base = base[:len(base) - node.level + 1]
    return ".".join(base + ([node.module] if node.module else []))


def in_functions(tree: ast.AST) -> set[int]:
    """ids of the import nodes inside a function body."""
    inside: set[int] = set()
    for fn in ast.walk(tree):
        if isinstance(fn, (ast.FunctionDef, ast.AsyncFunctionDef)):
            inside |= {id(n) for n in ast.walk(fn) if isinstance(n, (ast.Import, ast.ImportFrom))}
    return inside


def for_typing(tree: ast.AST) -> set[int]:
    """ids of the import nodes under ``if TYPE_CHECKING:`` (never run)."""
    found: set[int] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
            found |= {id(n) for n in ast.walk(node) if isinstance(n, (ast.Import, ast.ImportFrom))}
    return found


def imports(module: str, run_only: bool = False) -> Iterator[tuple[int, str, str | None, bool]]:
    """(line, imported module, imported name or None, inside a function) of one module;
    run_only: not those under TYPE_CHECKING."""
    path = MODULES[module]
    tree = ast.parse(path.read_text(encoding="utf-8"))
    local = in_functions(tree)
    typing_only = for_typing(tree) if run_only else set()
    for node in ast.walk(tree):
        if id(node) in typing_only:
            continue
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield node.lineno, alias.name, None, id(node) in local
        elif isinstance(node, ast.ImportFrom):
            target = absolute(module, path, node)
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if sub in MODULES:  # `from package import submodule`
                    yield node.lineno, sub, None, id(node) in local
                else:
                    yield node.lineno, target, alias.name, id(node) in local


def graph() -> dict[str, set[str]]:
    return {m: {t for _, t, _, _ in imports(m) if t in MODULES and t != m} for m in MODULES}


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on_stack: set[str] = set()
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                found.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return found


def test_every_module_is_in_a_room() -> None:
    outside = [m for m in MODULES if m != "hil" and room(m) is None]
    assert not outside, f"modules outside the rooms {ROOMS}: {outside}"


def test_every_room_says_what_it_owns() -> None:
    for name in ROOMS:
        init = PKG / name / "__init__.py"
        assert init.is_file(), f"room {name} has no package"
        doc = ast.get_docstring(ast.parse(init.read_text(encoding="utf-8")))
        assert doc and "import" in doc, f"hil/{name}/__init__.py: a docstring that says what it " \
                                        f"owns and what it may import"


def test_imports_run_downward() -> None:
    upward = []
    for m in MODULES:
        src = room(m)
        for line, target, _, _ in imports(m):
            dst = room(target)
            if src and dst and ROOMS.index(dst) > ROOMS.index(src):
                upward.append(f"{MODULES[m].relative_to(PKG)}:{line}: {m} ({src}) imports "
                              f"{target} ({dst})")
    assert not upward, "imports from a lower room into a higher one:\n" + "\n".join(upward)


def test_no_import_cycles() -> None:
    found = cycles(graph())
    assert not found, "modules that import each other in a circle: " + "; ".join(
        " -> ".join(c) for c in found)


def test_no_private_name_crosses_a_module() -> None:
    crossing = [f"{MODULES[m].relative_to(PKG)}:{line}: {name} from {target}"
                for m in MODULES for line, target, name, _ in imports(m)
                if target.startswith("hil") and name and name.startswith("_") and target != m]
    assert not crossing, "private names imported from another module:\n" + "\n".join(crossing)


def loads_heavy(module: str, seen: set[str] | None = None) -> bool:
    """Whether importing a hil module imports a HEAVY package (at module level, transitively)."""
    seen = set() if seen is None else seen
    if module in seen or module not in MODULES:
        return False
    seen.add(module)
    for _, target, _, inside in imports(module, run_only=True):
        if inside:
            continue
        if heavy(target) or loads_heavy(target, seen):
            return True
    return False


def test_imports_inside_functions_are_heavy_ones_only() -> None:
    local = [f"{MODULES[m].relative_to(PKG)}:{line}: {target}"
             for m in MODULES for line, target, _, inside in imports(m)
             if inside and not heavy(target) and not loads_heavy(target)]
    assert not local, f"imports inside functions (only {', '.join(HEAVY)}, or hil modules that " \
                      f"import them, may be):\n" + "\n".join(local)


def test_long_modules_say_why() -> None:
    unexplained = []
    for m, path in MODULES.items():
        text = path.read_text(encoding="utf-8")
        lines = text.count("\n")
        if lines > MAX_LINES and LONG_REASON not in (ast.get_docstring(ast.parse(text)) or ""):
            unexplained.append(f"{m}: {lines} lines")
    assert not unexplained, f"split these, or say '{LONG_REASON} ...' in the docstring:\n" + \
        "\n".join(unexplained)


def test_the_test_sees_a_cycle() -> None:
    assert cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []
