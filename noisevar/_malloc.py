"""glibc's allocator told to keep freed memory for reuse (Linux; a no-op elsewhere).

A record estimated in chunks allocates and frees the same few megabytes of work arrays
for every chunk. With glibc's defaults, freed memory at the top of the heap goes back to
the system and every new array is page-faulted in again, which on some machines costs
more than the arithmetic. Raising the trim threshold keeps up to :data:`KEEP` bytes per
arena for reuse; memory actually used stays what the chunks need.
"""

from __future__ import annotations

import ctypes
import sys

#: Bytes of freed memory glibc may keep at the top of each arena.
KEEP = 128 << 20
#: Allocations below this come from the heap, not from a fresh mapping (glibc's maximum).
MMAP_AT = 32 << 20
_M_TRIM_THRESHOLD, _M_MMAP_THRESHOLD = -1, -3
_done = False


def keep_freed_memory() -> None:
    """Raise glibc's trim and mmap thresholds once per process (no effect off glibc)."""
    global _done
    if _done or not sys.platform.startswith("linux"):
        return
    _done = True
    try:
        libc = ctypes.CDLL("libc.so.6")
        libc.mallopt(_M_MMAP_THRESHOLD, MMAP_AT)
        libc.mallopt(_M_TRIM_THRESHOLD, KEEP)
    except (OSError, AttributeError):  # not glibc (musl, ...): nothing to tune
        pass
