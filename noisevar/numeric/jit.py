"""numba's ``njit`` when it is installed, else the identity: the kernels' one decorator."""

from __future__ import annotations

from collections.abc import Callable

try:
    from numba import njit

    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - numba not installed
    HAVE_NUMBA = False


def _identity(fn: Callable) -> Callable:  # pragma: no cover - numba not installed
    return fn


# (no nogil: releasing and taking back the GIL costs more than a small kernel)
jit = njit(cache=True) if HAVE_NUMBA else _identity
#: helpers inlined into the kernels, so that the constant sizes reach their loops
inline = njit(cache=True, inline="always") if HAVE_NUMBA else _identity
