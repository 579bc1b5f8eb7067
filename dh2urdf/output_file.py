"""Output files: only a regular file (or a new path) is written, and whole or not at all.

:func:`output_problem` says, before any work, why a path cannot take a command's output: a
folder, a device (``/dev/full``, ``/dev/null``), a FIFO or a socket at the path, one of the
command's input files (:func:`same_file_problem`), an unknown suffix, a missing or unwritable
folder. :func:`write_atomic` writes a temporary file in the
target's folder, flushes and syncs it, then renames it over the target; a full disk (ENOSPC,
EDQUOT, EFBIG, EIO at write, flush, fsync, close or rename) removes the temporary file, leaves a
previous file unchanged and raises :class:`~dh2urdf.exceptions.OutputWriteError` (exit 1).

Choices:

* A symbolic link to a regular file is written through: the file it points to is replaced and
  the link stays a link, as the shell's ``>`` does. A link to a device is a device.
* An output is never one of the command's inputs: ``kin collisions --robot arm.xml
  --write-srdf arm.xml`` would replace the URDF by its SRDF. The same file is the same path
  once links are resolved (``realpath``), or the same ``(st_dev, st_ino)``: a symbolic link,
  a hard link, a bind mount.
* ``/dev/null`` is refused like any device (the rename would replace the device node when run as
  root). To discard an output, write it to a temporary file, or use ``-o -`` where a command
  prints to stdout.
"""

from __future__ import annotations

import os
import stat
import tempfile
from collections.abc import Callable, Iterable
from pathlib import Path
from typing import BinaryIO

from .exceptions import OutputFileError, OutputWriteError
from .input_file import file_kind

__all__ = [
    "InputFiles",
    "checked_output",
    "output_problem",
    "same_file_problem",
    "write_atomic",
    "write_text_atomic",
]

#: The files a command reads, as ``(option, path)`` (``("--robot", "arm.urdf")``, ``("the
#: table", "arm.toml")``); a path None (not given) or ``"-"`` (standard input) is no file.
InputFiles = Iterable[tuple[str, "str | os.PathLike[str] | None"]]


def _not_regular(mode: int) -> str:
    """Why a file of ``mode`` (``st_mode``) cannot be an output."""
    kind = file_kind(mode)
    if kind == "a folder":
        return "is a folder, not a file; give a file name"
    return f"is {kind or 'a special file'}, not a regular file; give a file name"


def _identity(path: str | os.PathLike[str]) -> tuple[int, int] | None:
    """The ``(st_dev, st_ino)`` of the file at ``path`` (links followed), or None (no file)."""
    try:
        found = os.stat(path)
    except (OSError, ValueError):  # missing, unreadable folder, a NUL in the name
        return None
    return found.st_dev, found.st_ino


def _real(path: str | os.PathLike[str]) -> str | None:
    """``path`` with every link resolved, or None when it cannot be resolved."""
    try:
        return os.path.realpath(path)
    except (OSError, ValueError):
        return None


def same_file_problem(path: str | os.PathLike[str], inputs: InputFiles) -> str | None:
    """Why ``path`` cannot take an output because it is one of ``inputs``, or None.

    The same file: the same real path (a new path is compared so), or the same device and inode
    (a symbolic link, a hard link). Nothing is opened.

    Returns:
        A reason that completes ``"-o FILE: ..."`` and names the input, or None.
    """
    real = _real(path)
    identity = _identity(path)
    for option, given in inputs:
        if given is None or str(given) == "-":
            continue
        same = real is not None and _real(given) == real
        if not same and identity is not None:
            same = _identity(given) == identity
        if same:
            return (
                f"is the same file as {option} {given}, which it would overwrite; "
                "give another file name"
            )
    return None


def output_problem(
    path: str | os.PathLike[str],
    suffixes: tuple[str, ...] | None = None,
    inputs: InputFiles = (),
) -> str | None:
    """Why ``path`` cannot take an output, or None when it is a regular file or a new path.

    Checked through symbolic links; nothing is opened (a FIFO is never waited on).

    Args:
        path: The file to write.
        suffixes: Allowed suffixes of the name given (lower case, with the dot), or None for any.
        inputs: The files the command reads (:data:`InputFiles`): ``path`` must be none of them.

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
    same = same_file_problem(given, inputs)
    if same is not None:
        return same
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


def checked_output(
    path: str,
    option: str,
    suffixes: tuple[str, ...] | None = None,
    inputs: InputFiles = (),
    file_error: Callable[[str, str, str], Exception] = OutputFileError,
) -> Path:
    """``path`` as a :class:`~pathlib.Path` once :func:`output_problem` finds nothing wrong.

    Args:
        path: The file a command is to write.
        option: The option that named it, for the message (``"-o"``).
        suffixes: Allowed suffixes (lower case, with the dot), or None for any.
        inputs: The files the command reads: ``path`` must be none of them.
        file_error: Raised as ``file_error(path, option, reason)``.

    Raises:
        OutputFileError: A folder, device, FIFO or socket at the path, one of ``inputs``, a
            missing or unwritable folder, or another suffix (or ``file_error``).
    """
    problem = output_problem(path, suffixes, inputs)
    if problem is not None:
        raise file_error(path, option, problem)
    return Path(path)
