"""glibc's allocator set so that a process's resident memory falls back after a large
request: every server worker and every heavy-pool process (app/work/pool.py) sets it as
it starts (a spawned pool process inherits nothing of its parent's setting).

M_MMAP_THRESHOLD fixed at 256 kB — an array above it is mmap-ed and its pages go back
to the system when freed. glibc otherwise raises the threshold after each large free
(up to 32 MB), so the large arrays of worst-case requests (a 500 × 500 grid, 250 000
pairs, a 16 MB CSV) came from its heaps and stayed resident: in the soak (bench/soak.py)
two workers grew from 608 MB after warm-up to 1 278 MB with no cache above its byte
bound, and the pool's processes stepped up by 30–150 MB at a time after their first
large jobs. M_ARENA_MAX 2 — one heap per thread (the kernels' thread pool: up to
8 × cores) each keeps its own free memory; two bound that.
"""
from __future__ import annotations

import ctypes
import ctypes.util

#: mallopt's parameter numbers (malloc.h) and the values set
M_MMAP_THRESHOLD, M_ARENA_MAX = -3, -8
MMAP_THRESHOLD_BYTES = 256 * 1024
ARENA_MAX = 2


def return_large_frees_to_the_system() -> bool:
    """Set the allocator as above (glibc only; elsewhere nothing is changed). Whether it
    was set."""
    name = ctypes.util.find_library("c")
    try:
        libc = ctypes.CDLL(name)
        return bool(libc.mallopt(M_MMAP_THRESHOLD, MMAP_THRESHOLD_BYTES)
                    and libc.mallopt(M_ARENA_MAX, ARENA_MAX))
    except (OSError, AttributeError, TypeError):
        return False
