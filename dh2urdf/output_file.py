"""Output files: only a regular file (or a new path) is written, and whole or not at all.

:func:`output_problem` says, before any work, why a path cannot take a command's output: a
folder, a device (``/dev/full``, ``/dev/null``), a FIFO or a socket at the path, an unknown
suffix, a missing or unwritable folder. :func:`write_atomic` writes a temporary file in the
target's folder, flushes and syncs it, then renames it over the target; a full disk (ENOSPC,
EDQUOT, EFBIG, EIO at write, flush, fsync, close or rename) removes the temporary file, leaves a
previous file unchanged and raises :class:`~dh2urdf.exceptions.OutputWriteError` (exit 1).

Choices:

* A symbolic link to a regular file is written through: the file it points to is replaced and
  the link stays a link, as the shell's ``>`` does. A link to a device is a device.
* ``/dev/null`` is refused like any device (the rename would replace the device node when run as
  root). To discard an output, write it to a temporary file, or use ``-o -`` where a command
  prints to stdout.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import BinaryIO

from .exceptions import OutputFileError, OutputWriteError

__all__ = ["checked_output", "output_problem", "write_atomic", "write_text_atomic"]

#: What a non-regular file at an output path is, by the ``stat`` test that finds it.
_KINDS = (
    (stat.S_ISDIR, "a folder, not a file; give a file name"),
    (stat.S_ISCHR, "a character device, not a regular file; give a file name"),
    (stat.S_ISBLK, "a block device, not a regular file; give a file name"),
    (stat.S_ISFIFO, "a FIFO (named pipe), not a regular file; give a file name"),
    (stat.S_ISSOCK, "a socket, not a regular file; give a file name"),
)


def _not_regular(mode: int) -> str:
    """Why a file of ``mode`` (``st_mode``) cannot be an output."""
    for test, text in _KINDS:
        if test(mode):
            return f"is {text}"
    return "is not a regular file; give a file name"


def output_problem(
    path: str | os.PathLike[str], suffixes: tuple[str, ...] | None = None
) -> str | None:
    """Why ``path`` cannot take an output, or None when it is a regular file or a new path.

    Checked through symbolic links; nothing is opened (a FIFO is never waited on).

    Args:
        path: The file to write.
        suffixes: Allowed suffixes of the name given (lower case, with the dot), or None for any.

    Returns:
        A reason that completes ``"-o FILE: ..."``, or None.
    """
    given = Path(path)
    target = Path(os.path.realpath(given))
    try:
        mode: int | None = os.stat(target).st_mode
    except FileNotFoundError:
        mode = None
    except OSError as err:
        return f"cannot be checked: {err.strerror or err}"
    if mode is not None and not stat.S_ISREG(mode):
        if str(target) == os.devnull:
            return _not_regular(mode) + " (to discard the output, write it to a temporary file)"
        return _not_regular(mode)
    if suffixes is not None and given.suffix.lower() not in suffixes:
        return f"unknown file type {given.suffix or '(no suffix)'!r}; use " + ", ".join(suffixes)
    folder = target.parent
    shown = str(given.parent) if str(given.parent) else "."
    if not folder.is_dir():
        return f"the folder {shown!r} does not exist"
    if not os.access(folder, os.W_OK | os.X_OK):
        return f"the folder {shown!r} is not writable"
    return None


def _new_mode(target: Path) -> int:
    """The permission bits of the written file: the old file's, else 0666 less the umask."""
    try:
        return stat.S_IMODE(os.stat(target).st_mode)
    except OSError:
        umask = os.umask(0)
        os.umask(umask)
        return 0o666 & ~umask


def write_atomic(
    path: str | os.PathLike[str],
    write: Callable[[BinaryIO], object],
    file_error: Callable[[str, str, str], Exception] = OutputFileError,
    write_error: Callable[[str, str], Exception] = OutputWriteError,
) -> Path:
    """Call ``write`` on a binary handle, then put its bytes at ``path`` whole, or change nothing.

    Args:
        path: A regular file or a new path (a link to one is written through).
        write: Writes the content to the handle it is given.
        file_error: Raised as ``file_error(path, "path", reason)`` when ``path`` is not a
            regular file or a new path in a writable folder (checked first).
        write_error: Raised as ``write_error(path, reason)`` when the operating system fails
            part-way (full disk, quota, I/O error); the temporary file is gone by then.

    Returns:
        ``path``.

    Raises:
        OutputFileError: ``path`` cannot take an output (or ``file_error``).
        OutputWriteError: Writing failed part-way (or ``write_error``).
    """
    shown = str(path)
    problem = output_problem(path)
    if problem is not None:
        raise file_error(shown, "path", problem)
    target = Path(os.path.realpath(path))
    mode = _new_mode(target)
    try:
        fd, temporary = tempfile.mkstemp(
            prefix=f".{target.name}.", suffix=".part", dir=target.parent
        )
    except OSError as err:
        raise write_error(shown, err.strerror or str(err)) from err
    try:
        with os.fdopen(fd, "wb") as handle:
            write(handle)
            handle.flush()
            os.fsync(handle.fileno())
            os.fchmod(handle.fileno(), mode)
        os.replace(temporary, target)
    except OSError as err:
        Path(temporary).unlink(missing_ok=True)
        raise write_error(shown, err.strerror or str(err)) from err
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
    return Path(path)


def write_text_atomic(
    path: str | os.PathLike[str],
    text: str,
    file_error: Callable[[str, str, str], Exception] = OutputFileError,
    write_error: Callable[[str, str], Exception] = OutputWriteError,
) -> Path:
    """Write ``text`` (UTF-8, newlines as given) to ``path`` with :func:`write_atomic`."""
    data = text.encode("utf-8")
    return write_atomic(path, lambda handle: handle.write(data), file_error, write_error)


def checked_output(path: str, option: str, suffixes: tuple[str, ...] | None = None) -> Path:
    """``path`` as a :class:`~pathlib.Path` once :func:`output_problem` finds nothing wrong.

    Args:
        path: The file a command is to write.
        option: The option that named it, for the message (``"-o"``).
        suffixes: Allowed suffixes (lower case, with the dot), or None for any.

    Raises:
        OutputFileError: A folder, device, FIFO or socket at the path, a missing or unwritable
            folder, or another suffix.
    """
    problem = output_problem(path, suffixes)
    if problem is not None:
        raise OutputFileError(path, option, problem)
    return Path(path)
