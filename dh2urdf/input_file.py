"""Input files opened safely: a regular file after links, read up to a stated size.

``Path.read_bytes`` on ``/dev/zero`` (or a link to it) reads until memory runs out, and on a
FIFO without a writer it waits forever. Every reader of a user's file (a DH table, a URDF, an
SRDF, a scene, a path, a reach map, a mesh) opens it here instead:

- the path is looked up with ``os.stat`` (links followed) before it is opened: a folder, a
  device, a FIFO or a socket is refused by what it is, and a FIFO is never opened;
- it is opened with ``O_NONBLOCK`` and looked up again on the open descriptor, so a FIFO put in
  its place between the two steps cannot block either;
- at most ``limit`` bytes are read; a larger file is refused, not cut.

Errors are :class:`OSError` whose ``strerror`` says what is wrong and the fix, so each caller's
``except OSError`` turns it into its own package's one-line error, as for a missing file.
"""

from __future__ import annotations

import errno
import io
import os
import stat
from typing import BinaryIO

__all__ = ["MAX_INPUT_BYTES", "TOO_LARGE_FIX", "file_kind", "open_input", "read_input"]

#: Most bytes of a text input (DH table, URDF, SRDF, scene, path JSON) [bytes]: 64 MiB. The
#: largest URDF of example-robot-data is under 1 MiB; a file beyond 64 MiB is not a robot or a
#: cell description but a wrong file, and reading it whole would only fill the memory.
MAX_INPUT_BYTES = 64 * 1024 * 1024

_NOT_REGULAR = (
    (stat.S_ISDIR, "a folder"),
    (stat.S_ISCHR, "a character device"),
    (stat.S_ISBLK, "a block device"),
    (stat.S_ISFIFO, "a FIFO"),
    (stat.S_ISSOCK, "a socket"),
)


def file_kind(mode: int) -> str | None:
    """What a file of ``mode`` (``st_mode``) is when not a regular file (``"a folder"``...).

    Returns:
        None for a regular file.
    """
    for test, name in _NOT_REGULAR:
        if test(mode):
            return name
    return None if stat.S_ISREG(mode) else "a special file"


#: The fix said after "larger than the cap", unless a reader knows a better one.
TOO_LARGE_FIX = "is it the right file?"


def _checked(name: str, result: os.stat_result, limit: int, fix: str) -> None:
    kind = file_kind(result.st_mode)
    if kind is not None:
        code = errno.EISDIR if stat.S_ISDIR(result.st_mode) else errno.EINVAL
        raise OSError(code, f"{kind}, not a regular file; give the file itself", name)
    if result.st_size > limit:
        raise OSError(errno.EFBIG, _too_large(result.st_size, limit, fix), name)


def _too_large(size: int, limit: int, fix: str) -> str:
    return f"{size:,} bytes, more than the {limit / 2**20:g} MiB read from such a file; {fix}"


def open_input(
    path: str | os.PathLike[str], limit: int = MAX_INPUT_BYTES, fix: str = TOO_LARGE_FIX
) -> BinaryIO:
    """The regular file ``path`` opened for binary reading, after the checks above.

    Args:
        path: The input file (links are followed).
        limit: Largest size accepted [bytes].
        fix: What the message of a larger file tells the user to do.

    Raises:
        OSError: Missing, a link loop, not a regular file, larger than ``limit``, or unreadable;
            ``strerror`` says which.
    """
    name = os.fspath(path)
    try:
        _checked(name, os.stat(name), limit, fix)
    except OSError as err:
        if err.errno == errno.ELOOP:
            raise OSError(errno.ELOOP, "a loop of symbolic links; link a real file", name) from None
        raise
    flags = os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_NOCTTY", 0)
    fd = os.open(name, flags | getattr(os, "O_CLOEXEC", 0))
    try:
        _checked(name, os.fstat(fd), limit, fix)  # what was opened, should the path have changed
        return io.open(fd, "rb", closefd=True)  # noqa: UP020 - a descriptor, not a path
    except BaseException:
        os.close(fd)
        raise


def read_input(
    path: str | os.PathLike[str], limit: int = MAX_INPUT_BYTES, fix: str = TOO_LARGE_FIX
) -> bytes:
    """The bytes of the regular file ``path``, at most ``limit`` of them (see :func:`open_input`).

    Raises:
        OSError: As :func:`open_input`, or the file grew beyond ``limit`` while it was read.
    """
    with open_input(path, limit, fix) as handle:
        data = handle.read(limit + 1)
    if len(data) > limit:
        raise OSError(errno.EFBIG, _too_large(len(data), limit, fix), os.fspath(path))
    return data
