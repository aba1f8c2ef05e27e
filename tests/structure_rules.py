"""Static reading of the sources for ``tests/test_structure.py``.

Every function here works on source text, so each rule can be shown to fail on a made-up
module as well as checked on the real ones.

Notes
-----
An *import* is anything that runs a module of ours: ``import`` and ``from ... import`` at
any depth (module level, in functions, methods, ``try``, ``if``), relative ones resolved,
but not under ``if TYPE_CHECKING:``; ``importlib.import_module`` / ``__import__`` calls
with a constant (or an f-string whose constant head names a package); and a string
constant that is the dotted name of one of our modules (the lazy-name tables of
``__init__`` files import it on first use; a fork server preloads it). Importing
``a.b.c`` also runs the packages ``a.b`` and ``a`` (their ``__init__``): :func:`executed`
adds them, except the ones that contain the importer, which are already running.
"""

from __future__ import annotations

import ast
import functools
import io
import re
import tokenize
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path

_IMPORTERS = {"import_module", "__import__"}
_MARKER = re.compile(r"#\s*long:")


@dataclass(frozen=True)
class Source:
    """One module: its dotted name, whether it is a package ``__init__``, its text."""

    name: str
    text: str
    is_package: bool = False
    path: str = ""

    @property
    def package(self) -> str:
        """The package a relative import is resolved from."""
        return self.name if self.is_package else self.name.rpartition(".")[0]

    @property
    def where(self) -> str:
        return self.path or self.name


@dataclass(frozen=True)
class Import:
    """``source`` runs ``target`` at ``line``; ``name`` is the name taken from it, if any."""

    source: str
    target: str
    line: int
    name: str | None = None
    how: str = "import"  # "import", "dynamic" or "string"


@dataclass(frozen=True)
class Use:
    """``source`` reaches ``name`` of module ``target`` (by import or attribute) at ``line``."""

    source: str
    target: str
    name: str | None
    line: int


def read_sources(root: Path, paths: Iterable[Path]) -> list[Source]:
    """:class:`Source` of each file, named as Python would import it from ``root``."""
    out = []
    for path in sorted(paths):
        parts = list(path.relative_to(root).with_suffix("").parts)
        is_package = parts[-1] == "__init__"
        name = ".".join(parts[:-1] if is_package else parts)
        rel = str(path.relative_to(root))
        out.append(Source(name, path.read_text(encoding="utf-8"), is_package, rel))
    return out


def by_place(problems: Iterable[str]) -> list[str]:
    """``path:line ...`` messages, unique, in file then line order."""

    def key(p: str) -> tuple[str, int, str]:
        path, _, rest = p.partition(":")
        line, _, tail = rest.partition(" ")
        return (path, int(line.rstrip(":")) if line.rstrip(":").isdigit() else 0, tail)

    return sorted(set(problems), key=key)


@functools.lru_cache(maxsize=1024)
def parse(text: str) -> ast.Module:
    """The tree of ``text``, parsed once (callers must not change it)."""
    return ast.parse(text)


def private(name: str) -> bool:
    """``_x`` but not ``__x__``."""
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _is_type_checking(test: ast.expr) -> bool:
    return ast.unparse(test) in {"TYPE_CHECKING", "typing.TYPE_CHECKING"}


def _docstrings(tree: ast.AST) -> set[int]:
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Module | ast.ClassDef | ast.FunctionDef | ast.AsyncFunctionDef):
            body = node.body
            if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
                out.add(id(body[0].value))
    return out


def executed_nodes(tree: ast.AST) -> Iterator[ast.AST]:
    """Every node of ``tree`` except those under ``if TYPE_CHECKING:`` (its ``else`` runs)."""
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, ast.If) and _is_type_checking(node.test):
            stack.extend(reversed(node.orelse))
            stack.append(node.test)
            continue
        stack.extend(reversed(list(ast.iter_child_nodes(node))))


def _absolute(src: Source, module: str | None, level: int) -> str:
    if level == 0:
        return module or ""
    base = src.package.split(".")
    base = base[: len(base) - (level - 1)] if level > 1 else base
    return ".".join([*base, module] if module else base)


def _ours(name: str, modules: set[str]) -> bool:
    """``name`` is in one of the packages of ``modules``."""
    top = name.split(".")[0]
    return top in modules or any(m.startswith(top + ".") for m in modules)


def _dynamic_target(src: Source, node: ast.Call) -> str | None:
    """Module named by ``import_module(...)`` / ``__import__(...)``, or None."""
    func = node.func
    called = func.attr if isinstance(func, ast.Attribute) else getattr(func, "id", None)
    if called not in _IMPORTERS or not node.args:
        return None
    arg = node.args[0]
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        return arg.value
    if isinstance(arg, ast.JoinedStr):
        head = ""
        for part in arg.values:
            if isinstance(part, ast.Constant):
                head += str(part.value)
            elif ast.unparse(part.value) == "__name__":
                head += src.name
            else:
                break
        return head.rpartition(".")[0] if "." in head else None
    return None


def imports(src: Source, modules: set[str]) -> list[Import]:
    """Every import of our modules that ``src`` executes (see the module Notes)."""
    tree = parse(src.text)
    docs = _docstrings(tree)
    out: list[Import] = []
    for node in executed_nodes(tree):
        if isinstance(node, ast.Import):
            out += [
                Import(src.name, a.name, node.lineno) for a in node.names if _ours(a.name, modules)
            ]
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(src, node.module, node.level)
            if not _ours(base, modules):
                continue
            for alias in node.names:
                sub = f"{base}.{alias.name}"
                if sub in modules:
                    out.append(Import(src.name, sub, node.lineno))
                else:
                    out.append(Import(src.name, base, node.lineno, alias.name))
        elif isinstance(node, ast.Call) and (target := _dynamic_target(src, node)):
            if _ours(target, modules):
                out.append(Import(src.name, target, node.lineno, how="dynamic"))
        elif (
            isinstance(node, ast.Constant)
            and node.value in modules
            and "." in node.value
            and id(node) not in docs
        ):
            out.append(Import(src.name, node.value, node.lineno, how="string"))
    return out


def executed(imp: Import) -> list[str]:
    """The modules ``imp`` runs: its target, and the packages above it that are not above the
    importer (those are running already)."""
    parts = imp.target.split(".")
    above = [".".join(parts[:k]) for k in range(len(parts) - 1, 0, -1)]
    src = imp.source.split(".")
    running = {".".join(src[:k]) for k in range(1, len(src) + 1)}
    return [imp.target, *(m for m in above if m not in running)]


def graph(sources: Iterable[Source], modules: set[str]) -> dict[str, set[str]]:
    """Module -> modules it executes (existing ones; no self-edge)."""
    out: dict[str, set[str]] = {}
    for src in sources:
        edges = out.setdefault(src.name, set())
        for imp in imports(src, modules):
            edges.update(m for m in executed(imp) if m in modules and m != src.name)
    return out


def tangles(edges: dict[str, set[str]]) -> list[list[str]]:
    """Groups of modules that import each other, directly or not (Tarjan), sorted."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    groups: list[list[str]] = []

    def connect(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in index:
                connect(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            group = []
            while True:
                w = stack.pop()
                on.discard(w)
                group.append(w)
                if w == v:
                    break
            if len(group) > 1:
                groups.append(sorted(group))

    for v in sorted(edges):
        if v not in index:
            connect(v)
    return sorted(groups)


def cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """A shortest cycle through the first module of each :func:`tangles` group."""
    return [_one_cycle(edges, set(g)) for g in tangles(edges)]


def _one_cycle(edges: dict[str, set[str]], group: set[str]) -> list[str]:
    """A shortest cycle through the group's first module (breadth-first)."""
    start = min(group)
    seen = {start: [start]}
    frontier = [start]
    while frontier:
        nxt = []
        for v in frontier:
            for w in sorted(edges.get(v, ()) & group):
                if w == start:
                    return [*seen[v], start]
                if w not in seen:
                    seen[w] = [*seen[v], w]
                    nxt.append(w)
        frontier = nxt
    return sorted(group)


def uses(src: Source, modules: set[str]) -> list[Use]:
    """Names ``src`` takes from our modules: imported modules and names, and attributes of a
    module bound by an import (``auto._fir`` after ``from noisevar.estimators import auto``).

    A name bound by an import anywhere in the file counts in the whole file.
    """
    found = imports(src, modules)
    out = [Use(src.name, i.target, i.name, i.line) for i in found]
    tree = parse(src.text)
    bound: dict[str, str] = {}
    for node in executed_nodes(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if _ours(a.name, modules):
                    top = a.name.split(".")[0]
                    bound[a.asname or top] = a.name if a.asname else top
        elif isinstance(node, ast.ImportFrom):
            base = _absolute(src, node.module, node.level)
            for a in node.names:
                if f"{base}.{a.name}" in modules:
                    bound[a.asname or a.name] = f"{base}.{a.name}"

    def module_of(expr: ast.expr) -> str | None:
        if isinstance(expr, ast.Name):
            return bound.get(expr.id)
        if isinstance(expr, ast.Attribute) and (base := module_of(expr.value)):
            sub = f"{base}.{expr.attr}"
            return sub if sub in modules else None
        return None

    for node in executed_nodes(tree):
        if isinstance(node, ast.Attribute) and (base := module_of(node.value)):
            sub = f"{base}.{node.attr}"
            if sub in modules:
                out.append(Use(src.name, sub, None, node.lineno))
            else:
                out.append(Use(src.name, base, node.attr, node.lineno))
    return out


def private_part(use: Use, helpers_ok: bool) -> str | None:
    """The private module or name ``use`` reaches, or None.

    ``helpers_ok``: the package's top-level private helpers (``noisevar._arrays``) count as
    public.
    """
    parts = use.target.split(".")
    for k, part in enumerate(parts[1:], start=2):
        if private(part) and not (helpers_ok and k == 2 and len(parts) == 2):
            return ".".join(parts[:k])
    if use.name is not None and private(use.name):
        return f"{use.target}.{use.name}"
    return None


def name_literals(src: Source, names: Iterable[str]) -> list[tuple[int, str]]:
    """(line, value) of every string constant equal to one of ``names``, docstrings aside."""
    wanted = set(names)
    tree = parse(src.text)
    docs = _docstrings(tree)
    return sorted(
        (node.lineno, node.value)
        for node in ast.walk(tree)
        if isinstance(node, ast.Constant)
        and isinstance(node.value, str)
        and node.value in wanted
        and id(node) not in docs
    )


def code_lines(node: ast.FunctionDef | ast.AsyncFunctionDef, lines: list[str]) -> int:
    """Lines of code in a function body: no docstring, blank or comment-only line."""
    body = node.body
    if body and isinstance(body[0], ast.Expr) and isinstance(body[0].value, ast.Constant):
        body = body[1:]
    if not body:
        return 0
    text = lines[body[0].lineno - 1 : node.end_lineno]
    return sum(1 for ln in text if ln.strip() and not ln.strip().startswith("#"))


def long_marker_problems(src: Source, limit: int) -> list[str]:
    """Functions over ``limit`` lines without a ``# long:`` on their ``def`` line, markers on
    functions of ``limit`` lines or fewer, and markers on a line that is no ``def`` line."""
    tree = parse(src.text)
    lines = src.text.splitlines()
    tokens = tokenize.generate_tokens(io.StringIO(src.text).readline)
    markers = {t.start[0] for t in tokens if t.type == tokenize.COMMENT and _MARKER.match(t.string)}
    out = []
    defs = set()
    for node in ast.walk(tree):
        if not isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            continue
        defs.add(node.lineno)
        n = code_lines(node, lines)
        marked = node.lineno in markers
        if n > limit and not marked:
            out.append(f"{src.where}:{node.lineno} {node.name}: {n} lines, no '# long:' on its def")
        elif n <= limit and marked:
            out.append(f"{src.where}:{node.lineno} {node.name}: marked long but {n} lines")
    out += [f"{src.where}:{ln}: '# long:' not on a def line" for ln in sorted(markers - defs)]
    return out
