"""Public names of a package loaded on first use (PEP 562 module ``__getattr__``)."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Iterable, Mapping
from typing import Any


def lazy_names(
    package: str, sources: Mapping[str, str], public: Iterable[str]
) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """``__getattr__`` and ``__dir__`` for ``package``: each name of ``sources`` is imported
    from its module on first use, then kept in the package.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    sources : mapping of str to str
        Public name -> the module that defines it.
    public : iterable of str
        The package's ``__all__`` (listed by ``dir``, loaded or not).

    Returns
    -------
    (__getattr__, __dir__) : tuple of callables
    """
    public = tuple(public)

    def __getattr__(name: str) -> Any:  # noqa: N807 - the PEP 562 hook
        source = sources.get(name)
        if source is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(source), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:  # noqa: N807 - the PEP 562 hook
        return sorted(set(vars(sys.modules[package])) | set(public))

    return __getattr__, __dir__
