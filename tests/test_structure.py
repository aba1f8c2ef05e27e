"""The code's shape: layers, no import cycle, no private name across a boundary, one home per
name, short functions, modules of readable size, no Streamlit (issues 12 and 25).

Every rule reads the sources (``tests/structure_rules.py``) and has a self-test on made-up
modules showing that it can fail.
"""

from __future__ import annotations

import ast
import functools
import subprocess
import sys
from collections.abc import Iterable
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest
import structure_rules as sr

#: The layers below the tools (batch, figures, cli), which may import any of them.
_BELOW_TOOLS = frozenset(
    {"numeric", "filters", "diagnostics", "io", "signals", "estimators", "stream", "kalman"}
    | {"noise_model", "systems", "experiments", "config"}
)
#: Who may import whom: a layer -> the layers it may import directly (the table is of direct
#: edges: nothing is implied). A layer is a subpackage of noisevar, or the layer TOP_LEVEL
#: gives a top-level module. Any layer may also import itself and "core" (``_may_import``).
#: "noisevar" is the package's facade (``noisevar/__init__.py``, ``__main__.py``): it may
#: import every layer, and nothing in the package imports it. The dashboard (dashboard/,
#: app_pages/, app.py) may import any public module or name of noisevar and nothing private
#: (``test_the_dashboard_imports_only_public_names``).
ALLOWED: dict[str, frozenset[str]] = {
    "core": frozenset(),
    "numeric": frozenset(),
    "io": frozenset(),
    "filters": frozenset({"numeric"}),
    "diagnostics": frozenset({"filters", "numeric"}),
    "signals": frozenset({"io"}),
    "estimators": frozenset({"diagnostics", "filters", "numeric", "io", "signals"}),
    "stream": frozenset({"estimators", "io"}),
    "kalman": frozenset({"estimators", "numeric"}),
    # estimators: a noise model fitted on the still regimes needs the record's regimes,
    # which the estimate finds (issue 26); kalman already imports estimators, so no new layer
    "noise_model": frozenset({"kalman", "numeric", "estimators"}),
    "systems": frozenset({"kalman"}),
    "experiments": frozenset({"systems", "kalman", "estimators", "signals"}),
    "config": frozenset({"estimators", "io", "noise_model"}),
    "batch": _BELOW_TOOLS,
    "figures": _BELOW_TOOLS | {"batch"},  # figures draw batch's fleet results
    "cli": _BELOW_TOOLS | {"batch", "figures"},
    "noisevar": _BELOW_TOOLS | {"batch", "figures", "cli"},
}
#: Top-level modules of noisevar and their layer. "core" is the floor every layer may use:
#: errors, parameter specs, number formatting and the synthetic-noise generators import no
#: subpackage (read them). signals reads io's sample-period range, so it sits above io;
#: config reads the estimators, io and noise_model, so it sits with the upper layers. A
#: private top-level helper (noisevar/_arrays.py, _lazy.py, _distributions.py) is core.
TOP_LEVEL = {
    "errors": "core",
    "params": "core",
    "format": "core",
    "synth": "core",
    "units": "core",
    "report": "core",  # the HTML page every report shares (escaping, style): no imports
    "signals": "signals",
    "config": "config",
    "__main__": "noisevar",
}
MAX_FUNCTION_LINES = 60
MAX_MODULE_LINES = 600

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = ROOT / "noisevar"
APP_FILES = sorted(
    [*(ROOT / "dashboard").rglob("*.py"), *(ROOT / "app_pages").glob("*.py"), ROOT / "app.py"]
)
#: Every Python file of the package, the dashboard and the page scripts (app_pages/).
SOURCES = sorted([*PACKAGE.rglob("*.py"), *APP_FILES])
ALL = sr.read_sources(ROOT, SOURCES)
MODULES = {s.name for s in ALL}


def _layer(module: str) -> str | None:
    """The layer of a module of noisevar (None: not in the table)."""
    parts = module.split(".")
    if len(parts) == 1:
        return "noisevar"
    if len(parts) == 2 and (parts[1] in TOP_LEVEL or sr.private(parts[1])):
        return TOP_LEVEL.get(parts[1], "core")
    return parts[1] if parts[1] in ALLOWED else None


def _may_import(src: str, dst: str) -> bool:
    return src == dst or dst == "core" or dst in ALLOWED[src]


def _ours(module: str) -> bool:
    return module == "noisevar" or module.startswith("noisevar.")


def _in_app(module: str) -> bool:
    return module.split(".")[0] in ("dashboard", "app_pages", "app")


def _show(problems: list[str], what: str) -> str:
    return f"{len(problems)} {what}:\n" + "\n".join(problems)


# ----------------------------------------------------------------- (a) layers


def edge_violations(sources: Iterable[sr.Source], modules: set[str]) -> list[str]:
    """Imports of noisevar's modules that the table does not allow."""
    out = []
    for src in sources:
        if not _ours(src.name):
            continue
        here = _layer(src.name)
        for imp in sr.imports(src, modules):
            for dst in sr.executed(imp):
                there = _layer(dst) if _ours(dst) else "dashboard"
                if here is None or there is None or not _may_import(here, there):
                    out.append(f"{src.where}:{imp.line} {here} -> {there}: {dst}")
    return sr.by_place(out)


def app_violations(sources: Iterable[sr.Source], modules: set[str]) -> list[str]:
    """Private modules or names of noisevar that the dashboard, page scripts or app reach."""
    out = []
    for src in sources:
        if _in_app(src.name):
            for use in sr.uses(src, modules):
                part = sr.private_part(use, helpers_ok=False)
                if _ours(use.target) and part:
                    out.append(f"{src.where}:{use.line} {part}")
    return sr.by_place(out)


def test_every_module_has_a_layer() -> None:
    missing = [s.name for s in ALL if _ours(s.name) and _layer(s.name) is None]
    assert not missing, "add to ALLOWED or TOP_LEVEL: " + ", ".join(missing)


def test_the_table_is_layered() -> None:
    assert not sr.cycles({k: set(v) for k, v in ALLOWED.items()})
    assert set(TOP_LEVEL.values()) <= set(ALLOWED)


def test_imports_follow_the_allowed_edges() -> None:
    bad = edge_violations(ALL, MODULES)
    assert not bad, _show(bad, "imports outside the allowed edges")


def test_the_dashboard_imports_only_public_names() -> None:
    bad = app_violations(ALL, MODULES)
    assert not bad, _show(bad, "private names of noisevar used by the dashboard")


def _made_up(files: dict[str, str]) -> tuple[list[sr.Source], set[str]]:
    """Sources from ``{"pkg/mod.py": text}`` (``__init__.py`` makes a package)."""
    out = []
    for path, text in files.items():
        parts = path.removesuffix(".py").split("/")
        pkg = parts[-1] == "__init__"
        out.append(sr.Source(".".join(parts[:-1] if pkg else parts), text, pkg, path))
    return out, {s.name for s in out}


def test_the_edge_check_fails_on_hidden_imports() -> None:
    sources, modules = _made_up(
        {
            "noisevar/__init__.py": "",
            "noisevar/numeric/__init__.py": "",
            "noisevar/numeric/x.py": (
                "from typing import TYPE_CHECKING\n"
                "if TYPE_CHECKING:\n    from noisevar.kalman import model\n"
                "def f():\n    try:\n        from ..estimators import auto\n"  # relative
                "    except ImportError:\n        pass\n"
            ),
            "noisevar/filters/__init__.py": "",
            "noisevar/filters/y.py": (
                "class C:\n    def m(self):\n        import noisevar.stream.s\n"
            ),
            "noisevar/estimators/__init__.py": "",
            "noisevar/estimators/auto.py": (
                "import importlib\nimportlib.import_module('noisevar.cli')\n"
            ),
            "noisevar/stream/__init__.py": "",
            "noisevar/stream/s.py": "",
            "noisevar/cli/__init__.py": "",
            "noisevar/kalman/__init__.py": "",
            "noisevar/kalman/model.py": "",
            "noisevar/kalman/run.py": (  # the facade, the dashboard; core and estimators: fine
                "import noisevar\nfrom dashboard import page\n"
                "from noisevar.errors import E\nfrom noisevar.estimators import auto\n"
            ),
            "noisevar/errors.py": "",
            "dashboard/__init__.py": "",
            "dashboard/page.py": "",
        }
    )
    assert edge_violations(sources, modules) == [
        "noisevar/estimators/auto.py:2 estimators -> cli: noisevar.cli",
        "noisevar/filters/y.py:3 filters -> stream: noisevar.stream",  # the package's __init__
        "noisevar/filters/y.py:3 filters -> stream: noisevar.stream.s",
        "noisevar/kalman/run.py:1 kalman -> noisevar: noisevar",
        "noisevar/kalman/run.py:2 kalman -> dashboard: dashboard",
        "noisevar/kalman/run.py:2 kalman -> dashboard: dashboard.page",
        "noisevar/numeric/x.py:6 numeric -> estimators: noisevar.estimators",
        "noisevar/numeric/x.py:6 numeric -> estimators: noisevar.estimators.auto",
    ]


def test_the_dashboard_check_fails_on_private_names() -> None:
    sources, modules = _made_up(
        {
            "noisevar/__init__.py": "",
            "noisevar/_arrays.py": "",
            "noisevar/estimators/__init__.py": "",
            "noisevar/estimators/_record.py": "",
            "dashboard/a.py": (
                "import noisevar\nfrom noisevar.estimators import _record, estimate\n"
                "def f():\n    return noisevar._arrays, noisevar.estimators._private\n"
            ),
        }
    )
    assert app_violations(sources, modules) == [
        "dashboard/a.py:2 noisevar.estimators._record",
        "dashboard/a.py:4 noisevar._arrays",
        "dashboard/a.py:4 noisevar.estimators._private",
    ]


# ----------------------------------------------------------------- (b) cycles


def cycle_report(sources: Iterable[sr.Source], modules: set[str]) -> list[str]:
    """One line per group of modules that import each other: a cycle, then the group."""
    edges = sr.graph(sources, modules)
    return [
        f"{' -> '.join(sr.cycles({m: edges[m] & set(g) for m in g})[0])}  (group: {', '.join(g)})"
        for g in sr.tangles(edges)
    ]


def test_no_import_cycle() -> None:
    found = cycle_report(ALL, MODULES)
    assert not found, _show(found, "import cycles (function-level imports included)")


def test_the_walk_finds_a_cycle() -> None:
    assert sr.cycles({"a.x": {"a.y"}, "a.y": {"a.z"}, "a.z": {"a.x"}}) == [
        ["a.x", "a.y", "a.z", "a.x"]
    ]


def test_the_cycle_check_sees_function_level_imports_and_package_inits() -> None:
    sources, modules = _made_up(
        {
            "p/__init__.py": "",
            "p/a/__init__.py": "from p.a import one\n",
            "p/a/one.py": "def f():\n    from p.b.two import g\n",
            "p/b/__init__.py": "",
            "p/b/two.py": "def g():\n    import p.a.other\n",  # runs p/a/__init__.py
            "p/a/other.py": "",
            "p/c.py": "from typing import TYPE_CHECKING\nif TYPE_CHECKING:\n    import p.d\n",
            "p/d.py": "import p.c\n",
        }
    )
    assert sr.cycles(sr.graph(sources, modules)) == [["p.a", "p.a.one", "p.b.two", "p.a"]]


# ----------------------------------------------------------------- (c) private names


def private_crossings(sources: Iterable[sr.Source], modules: set[str]) -> list[str]:
    """Private modules or names of one part of noisevar used from another part."""

    def part(module: str) -> str:
        return ".".join(module.split(".")[:2])

    out = []
    for src in sources:
        if not _ours(src.name):
            continue
        for use in sr.uses(src, modules):
            reached = sr.private_part(use, helpers_ok=True)
            if reached and _ours(use.target) and part(src.name) != part(reached):
                out.append(f"{src.where}:{use.line} {reached}")
    return sr.by_place(out)


def test_no_private_name_crosses_a_subpackage() -> None:
    bad = private_crossings(ALL, MODULES)
    assert not bad, _show(bad, "private names used across a subpackage boundary")


def test_the_private_check_fails_across_and_passes_within() -> None:
    sources, modules = _made_up(
        {
            "noisevar/__init__.py": "",
            "noisevar/_arrays.py": "",
            "noisevar/filters/__init__.py": "",
            "noisevar/filters/_fir.py": "",
            "noisevar/estimators/__init__.py": "",
            "noisevar/estimators/_steps.py": "",
            "noisevar/estimators/auto.py": (
                "from noisevar._arrays import FloatArray\n"  # a top-level helper: fine
                "from noisevar.estimators._steps import _mask\n"  # same subpackage: fine
                "def f():\n    from noisevar.filters import _fir\n"
            ),
            "noisevar/diagnostics/__init__.py": "",
            "noisevar/diagnostics/s.py": (
                "from noisevar.estimators import auto\nfrom noisevar.estimators.auto import _x\n"
                "y = auto._fir\n"
            ),
        }
    )
    assert private_crossings(sources, modules) == [
        "noisevar/diagnostics/s.py:2 noisevar.estimators.auto._x",
        "noisevar/diagnostics/s.py:3 noisevar.estimators.auto._fir",
        "noisevar/estimators/auto.py:4 noisevar.filters._fir",
    ]


# ----------------------------------------------------------------- (d) one home per name
# The names of the estimators (METHODS), the Kalman R strategies (their registry, aliases
# included) and the scenarios (SCENARIOS) are read from the registries when the test runs.
# A string constant equal to one of them (the whole string: prose is not checked, nor are
# docstrings) may appear only in a home of that string: the module of the registered
# callable (spec.func / chunked / finish, a strategy's class, a scenario's generator), the
# module that assigns the spec or lists it (so the registry module is a home of each name it
# lists), or the home of the same word in another registry (an experiment, a test signal,
# a fit_kalman method). Anything else is a branch or a list that a new method, strategy or
# scenario would have to edit, unless LITERALS_ALLOWED says why not.

#: Modules that may write some registered names, and why: "<kind> names" allows every name
#: of that registry, any other key that one string. Everything else fails.
LITERALS_ALLOWED: dict[str, dict[str, str]] = {
    "noisevar.noise_model.gmwm": {"auto": "the IMU model search's keyword, not the method"},
    "noisevar.noise_model.gmwm.fitting": {"auto": "the IMU model search's keyword"},
    "dashboard.pages": {"auto": "Streamlit's initial_sidebar_state value, not the method"},
    "noisevar.experiments.gps_circle": {
        "strategy names": "reproduces the 2016 paper's Table 1, whose rows are named filters",
    },
    "noisevar.experiments.noise_step": {
        "strategy names": "the experiment compares these named strategies, by design",
    },
    "noisevar.experiments.fusion": {
        "strategy names": "the experiment compares the fusion's named local strategies",
        "noise-step": "a fault kind of FusionScenario, not the scenario",
        "noise-ramp": "a fault kind of FusionScenario, not the scenario",
    },
    "noisevar.systems.fusion_scenario": {
        "noise-step": "a fault kind of FusionScenario, not the scenario",
        "noise-ramp": "a fault kind of FusionScenario, not the scenario",
    },
    "noisevar.experiments.latency": {"fixed": "the fixed-delay compensation, not the strategy"},
    "noisevar.figures.robust": {"outliers": "a trace's label (the word), not the scenario"},
    "noisevar.figures.compare": {"somd": "MethodSpec.kind 'somd' (the family), not the method"},
    "noisevar.estimators.redundant": {"somd": "MethodSpec.kind 'somd' of somd-redundant"},
}
#: Registries whose names are checked; the others only own words (a literal in their home
#: is fine): experiments, test signals and fit_kalman's methods.
CHECKED_KINDS = ("method", "strategy", "scenario")


@functools.cache
def _assigned_names(path: str) -> frozenset[str]:
    tree = sr.parse(Path(path).read_text(encoding="utf-8"))
    names = set()
    for node in tree.body:
        targets = node.targets if isinstance(node, ast.Assign) else [getattr(node, "target", 0)]
        names.update(t.id for t in targets if isinstance(t, ast.Name))
    return frozenset(names)


def _assigned(module: ModuleType) -> list[Any]:
    """Values of the globals a module assigns itself (not the ones it imports)."""
    names = _assigned_names(module.__file__ or "")
    return [vars(module)[n] for n in names if n in vars(module)]


def _homes_of(obj: object, *callables: object) -> set[str]:
    """Modules of the callables, and of the globals holding ``obj`` (alone, in a tuple, list
    or dict): the module that writes the object, and the registry that lists it."""
    out = {c.__module__ for c in callables if c is not None}
    for name, mod in list(sys.modules.items()):
        if _ours(name) and getattr(mod, "__file__", None):
            for value in _assigned(mod):
                held = value.values() if isinstance(value, dict) else value
                if value is obj or (
                    isinstance(value, tuple | list | dict) and any(v is obj for v in held)
                ):
                    out.add(name)
    return out


@functools.cache
def registered_names() -> dict[str, dict[str, set[str]]]:
    """Kind -> name -> its home modules, read from the registries now."""
    import noisevar.experiments as experiments
    import noisevar.noise_model.kalman_fit as kalman_fit
    from noisevar.estimators import METHODS
    from noisevar.kalman.strategies import registry
    from noisevar.signals import signal_names
    from noisevar.systems.scenarios import SCENARIOS

    strategies = {n: _homes_of(s, s.cls) for n, s in registry.STRATEGIES.items()}
    return {
        "method": {n: _homes_of(s, s.func, s.chunked, s.finish) for n, s in METHODS.items()},
        "strategy": {**strategies, **{a: strategies[n] for a, n in registry.ALIASES.items()}},
        "scenario": {n: _homes_of(f, f) for n, f in SCENARIOS.items()},
        "experiment": {n: _homes_of(e, e.compute) for n, e in experiments.discover().items()},
        "signal": {n: {"noisevar.signals"} for n in signal_names()},
        "fit method": {n: {kalman_fit.__name__} for n in kalman_fit.METHODS},
    }


def literal_violations(
    sources: Iterable[sr.Source],
    names: dict[str, dict[str, set[str]]],
    allowed: dict[str, dict[str, str]],
) -> list[str]:
    """Registered names written outside their homes and the allowances."""
    homes: dict[str, set[str]] = {}
    for table in names.values():
        for name, where in table.items():
            homes.setdefault(name, set()).update(where)
    checked = {n for kind in CHECKED_KINDS for n in names.get(kind, {})}
    out = []
    for src in sources:
        ok = set(allowed.get(src.name, {}))
        for kind, table in names.items():
            if f"{kind} names" in ok:
                ok |= set(table)
        for line, value in sr.name_literals(src, checked):
            if src.name not in homes[value] and value not in ok:
                kinds = "/".join(k for k in CHECKED_KINDS if value in names.get(k, {}))
                out.append(f"{src.where}:{line} {kinds} {value!r}")
    return sr.by_place(out)


def test_no_registered_name_is_written_outside_its_home() -> None:
    bad = literal_violations(ALL, registered_names(), LITERALS_ALLOWED)
    assert not bad, _show(bad, "method, strategy or scenario names written outside their home")


def test_the_literal_check_fails_outside_the_home() -> None:
    sources, _ = _made_up(
        {
            "noisevar/estimators/auto.py": 'AUTO = ("auto",)\n',
            "noisevar/estimators/pipeline.py": (
                'def f(spec):\n    """Not for "auto"."""\n    return spec.name == "auto"\n'
            ),
            "noisevar/figures/robust.py": 'LABEL = "outliers"\n',
            "dashboard/page.py": 'CHOICES = ["auto", "noise-step"]\n',
        }
    )
    names = {
        "method": {"auto": {"noisevar.estimators.auto"}},
        "scenario": {"noise-step": {"noisevar.systems.scenarios"}, "outliers": set()},
    }
    allowed = {"noisevar.figures.robust": {"outliers": "a label"}}
    assert literal_violations(sources, names, allowed) == [
        "dashboard/page.py:1 method 'auto'",
        "dashboard/page.py:1 scenario 'noise-step'",
        "noisevar/estimators/pipeline.py:3 method 'auto'",
    ]


def test_every_allowance_is_still_used() -> None:
    names = registered_names()
    stale = []
    for module, entries in LITERALS_ALLOWED.items():
        found = {v for s in ALL if s.name == module for _, v in sr.name_literals(s, _flat(names))}
        for key in entries:
            kind = key.removesuffix(" names")
            if not (found & set(names.get(kind, {})) if key.endswith(" names") else key in found):
                stale.append(f"{module}: {key}")
    assert not stale, "allowances no longer needed: " + ", ".join(stale)


def _flat(names: dict[str, dict[str, set[str]]]) -> set[str]:
    return {n for kind in CHECKED_KINDS for n in names.get(kind, {})}


# ----------------------------------------------------------------- (e) function length


def test_long_markers_only_on_the_def_of_long_functions() -> None:
    bad = [p for s in ALL for p in sr.long_marker_problems(s, MAX_FUNCTION_LINES)]
    assert not bad, _show(bad, "'# long:' problems (over 60 lines needs one, on its def line)")


def test_the_marker_check_fails_on_misplaced_or_stale_markers() -> None:
    body = "".join(f"    x{i} = {i}\n" for i in range(61))
    src = sr.Source(
        "m",
        "# long: above the def\ndef above():\n"
        + body
        + "def short():  # long: stale\n    return 1\n"
        + "def unmarked():\n"
        + body
        + "def good(  # long: why\n    a=1,\n):\n"
        + body
        + "def inside():\n    # long: in the body\n"
        + body,  # fmt: skip
    )
    assert [p.split(" ", 1)[1] for p in sr.long_marker_problems(src, 60)] == [
        "above: 61 lines, no '# long:' on its def",
        "short: marked long but 1 lines",
        "unmarked: 61 lines, no '# long:' on its def",
        "inside: 61 lines, no '# long:' on its def",
        "'# long:' not on a def line",
        "'# long:' not on a def line",
    ]


def test_the_length_count_skips_docstrings_and_comments() -> None:
    src = 'def f():\n    """Doc.\n\n    More.\n    """\n    # note\n\n    a = 1\n    return a\n'
    node = ast.parse(src).body[0]
    assert isinstance(node, ast.FunctionDef)
    assert sr.code_lines(node, src.splitlines()) == 2


def test_modules_are_under_600_lines() -> None:
    big = [
        f"{p.relative_to(ROOT)} ({n} lines)"
        for p in SOURCES
        if (n := len(p.read_text(encoding="utf-8").splitlines())) >= MAX_MODULE_LINES
    ]
    assert not big, "modules of 600 lines or more:\n" + "\n".join(big)


def test_noisevar_never_imports_streamlit_or_the_dashboard() -> None:
    for path in PACKAGE.rglob("*.py"):
        text = path.read_text(encoding="utf-8")
        for bad in ("import dashboard", "from dashboard", "import streamlit", "from streamlit"):
            assert bad not in text, f"{path.relative_to(ROOT)}: {bad}"


def test_every_table_of_the_pages_draws_missing_cells_as_a_dash() -> None:
    """Streamlit draws a null cell "None" whatever a Styler says: every table goes through
    ``dashboard.widgets.show_table`` (its ``placeholder``)."""
    home = ROOT / "dashboard" / "widgets.py"
    bad = [
        str(p.relative_to(ROOT))
        for p in APP_FILES
        if p != home and "st.dataframe(" in p.read_text(encoding="utf-8")
    ]
    assert not bad, f"st.dataframe outside dashboard/widgets.show_table: {bad}"


# entry points a cycle inside the package would break (the graph walk covers every module)
@pytest.mark.parametrize(
    "module", ["noisevar.kalman.strategies.vb", "noisevar.kalman.run", "noisevar.kalman.steps"]
)
def test_module_imports_alone_in_a_fresh_interpreter(module):
    res = subprocess.run(
        [sys.executable, "-c", f"import {module}"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=120,
    )
    assert res.returncode == 0, res.stderr
