"""Shared-memory arenas that carry the large arrays of one sandbox message between processes.

The process sandbox (:mod:`voxposer.lmp.sandbox_process`) sends value maps (100 x 100 x 100
floats, 4-8 MB) and occupancy grids between the parent and its worker. Pickling them through the
pipe would copy each one three times; instead the sender writes the array into an *arena*, a
shared-memory segment, and the message names its offset, dtype and shape. The receiver copies the
array out before it answers, so one arena per direction is enough (the protocol is strictly
request/response: nothing is written into an arena whose last message has not been read).

The parent creates, grows and unlinks every segment (:class:`Arena`), so a worker killed by a
limit leaks nothing; the worker maps them by name (:class:`MappedArena`) without registering them
anywhere. Linux only (segments live in ``/dev/shm``), like the worker's ``resource`` limits.
"""

from __future__ import annotations

import mmap
import os
from multiprocessing import shared_memory
from typing import Final

import numpy as np
from numpy.typing import NDArray

#: Offsets of arrays in an arena are multiples of this [bytes] (cache lines, SIMD loads).
ALIGN: Final = 64
#: Size of a new arena [bytes]; it grows to what one message needs.
INITIAL_BYTES: Final = 16 * 1024 * 1024


def aligned(nbytes: int) -> int:
    """``nbytes`` rounded up to a multiple of :data:`ALIGN`."""
    return (nbytes + ALIGN - 1) // ALIGN * ALIGN


class Arena:
    """A shared-memory segment owned (created and unlinked) by the parent process.

    Args:
        nbytes: size [bytes], at least 1.
    """

    def __init__(self, nbytes: int = INITIAL_BYTES) -> None:
        self._shm = shared_memory.SharedMemory(create=True, size=max(int(nbytes), ALIGN))
        self.name: str = self._shm.name
        self.size: int = self._shm.size
        buf = self._shm.buf
        if buf is None:
            raise OSError(f"shared memory segment {self.name} has no buffer")
        self.buf: memoryview = buf

    def close(self) -> None:
        """Unmap and unlink the segment (idempotent)."""
        if self._shm is None:
            return
        self.buf.release()
        self._shm.close()
        try:
            self._shm.unlink()
        except FileNotFoundError:
            pass
        self._shm = None  # type: ignore[assignment]


class MappedArena:
    """The worker's mapping of a parent's :class:`Arena`, by name.

    Args:
        name: the segment's name (``Arena.name``).
        size: its size [bytes].
    """

    def __init__(self, name: str, size: int) -> None:
        fd = os.open(f"/dev/shm/{name}", os.O_RDWR)
        try:
            self._map = mmap.mmap(fd, size)
        finally:
            os.close(fd)  # the mapping stays valid; the worker has few file descriptors
        self.name = name
        self.size = size
        self.buf = memoryview(self._map)

    def close(self) -> None:
        """Unmap (idempotent)."""
        if self._map is not None:
            self.buf.release()
            self._map.close()
            self._map = None  # type: ignore[assignment]


def write_array(buf: memoryview, offset: int, arr: NDArray) -> None:
    """Copy ``arr`` into ``buf`` at ``offset`` [bytes] in C order (one copy, any strides)."""
    if arr.size:
        np.ndarray(arr.shape, arr.dtype, buffer=buf, offset=offset)[...] = arr


def read_array(buf: memoryview, offset: int, dtype: np.dtype, shape: tuple[int, ...]
               ) -> NDArray:
    """A fresh copy of the C-order array of ``dtype`` and ``shape`` at ``offset`` of ``buf``.

    Raises:
        ValueError: the array would extend past the end of ``buf``.
    """
    count = int(np.prod(shape, dtype=np.int64))
    nbytes = count * dtype.itemsize
    if offset < 0 or offset + nbytes > len(buf):
        raise ValueError(f"array of {nbytes} bytes at offset {offset} lies outside the "
                         f"{len(buf)}-byte arena")
    if count == 0:
        return np.empty(shape, dtype)
    return np.frombuffer(buf, dtype, count, offset).reshape(shape).copy()
