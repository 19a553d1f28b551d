"""The import graph of python/brushwork, read from the source with `ast`: imports run one way
(no circles), the data layer (glyphs/) leans on nothing above it, font/ and bench/ go to the pool
and the writing rather than the batch module, and cli.py stays a table of commands."""
from __future__ import annotations

import ast
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1] / "python"
PACKAGE = ROOT / "brushwork"
CLI_MAX_LINES = 200


def module_name(path: Path) -> str:
    """brushwork.a.b for python/brushwork/a/b.py; brushwork.a for python/brushwork/a/__init__.py."""
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def extension_modules() -> set[str]:
    """The compiled modules CMakeLists.txt builds into the package (python_add_library NAME MODULE)."""
    cmake = (ROOT.parent / "CMakeLists.txt").read_text(encoding="utf-8")
    return {f"brushwork.{m}" for m in re.findall(r"python_add_library\(\s*(\w+)\s+MODULE", cmake)}


def all_modules() -> dict[str, Path | None]:
    """Every module of the package: its source file, or None for a compiled one."""
    found: dict[str, Path | None] = {m: None for m in extension_modules()}
    found.update({module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))})
    return found


def _base(name: str, path: Path, level: int) -> str:
    """The package a relative import of `level` dots in module `name` starts from."""
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    for _ in range(level - 1):
        package = package.rpartition(".")[0]
    return package


def _targets(node: ast.AST, name: str, path: Path, modules: dict) -> list[str]:
    """The brushwork modules one import statement reaches: a name that is a submodule counts as
    that module, any other name as the module it is taken from."""
    if isinstance(node, ast.Import):
        return [a.name for a in node.names if a.name in modules]
    if not isinstance(node, ast.ImportFrom):
        return []
    source = node.module or ""
    if node.level:
        source = _base(name, path, node.level) + ("." + source if source else "")
    found = []
    for alias in node.names:
        sub = f"{source}.{alias.name}"
        found.append(sub if sub in modules else source)
    return [m for m in found if m in modules]


def import_graph() -> dict[str, set[str]]:
    """module -> the brushwork modules it imports, at the top or inside a function."""
    modules = all_modules()
    graph: dict[str, set[str]] = {}
    for name, path in modules.items():
        if path is None:
            graph[name] = set()
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        edges = {t for node in ast.walk(tree) for t in _targets(node, name, path, modules)}
        graph[name] = edges - {name}
    return graph


def cycles(graph: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    found: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in sorted(graph[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return found


def _inside(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


def reaching(graph: dict[str, set[str]], sources: str, target: str) -> list[str]:
    """Edges 'a -> b' from a module in package `sources` to one in package `target`."""
    return sorted(f"{a} -> {b}" for a, edges in graph.items() if _inside(a, sources)
                  for b in edges if _inside(b, target))


@pytest.fixture(scope="module")
def graph() -> dict[str, set[str]]:
    return import_graph()


def test_the_graph_is_read_whole(graph):
    # the walk sees the modules and the imports between them, relative and nested ones included
    assert "brushwork._core" in graph["brushwork.brush"]
    assert {"brushwork.cli", "brushwork.batch", "brushwork.writing.driver", "brushwork.glyphs.score"} <= set(graph)
    assert "brushwork.writing.style" in graph["brushwork.writing.driver"]
    assert "brushwork.bench.report" in graph["brushwork.commands.render"]     # imported inside a function


def test_cycles_are_found():
    made_up = {"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}, "e": set()}
    assert cycles(made_up) == [["a", "b", "c"]]
    assert cycles({"a": {"b"}, "b": set()}) == []


def test_no_import_circles(graph):
    assert cycles(graph) == []


def test_glyphs_import_nothing_from_writing(graph):
    assert reaching(graph, "brushwork.glyphs", "brushwork.writing") == []


@pytest.mark.parametrize("package", ["brushwork.font", "brushwork.bench"])
def test_font_and_bench_import_nothing_from_batch(graph, package):
    assert reaching(graph, package, "brushwork.batch") == []


def test_cli_is_a_table_of_commands():
    lines = (PACKAGE / "cli.py").read_text(encoding="utf-8").count("\n")
    assert lines <= CLI_MAX_LINES, f"cli.py has {lines} lines"
