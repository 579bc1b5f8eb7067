"""Exceptions of the ``dh2urdf`` package: one base class, specific subclasses carrying data."""

from __future__ import annotations


class Dh2UrdfError(Exception):
    """Base class of every error raised by ``dh2urdf``."""


class TableError(Dh2UrdfError, ValueError):
    """A DH table file is malformed.

    Attributes:
        path: File the table was read from (or ``"<string>"``).
        row: 1-based index of the ``[[joints]]`` row, or None for a top-level field.
        field: Name of the offending field, or None.
    """

    def __init__(self, path: str, message: str, row: int | None = None, field: str | None = None):
        self.path = path
        self.row = row
        self.field = field
        where = path
        if row is not None:
            where += f", joint row {row}"
        if field is not None:
            where += f", field '{field}'"
        super().__init__(f"{where}: {message}")


class UnknownRobotError(Dh2UrdfError, KeyError):
    """A robot name is not in the registry.

    Attributes:
        name: The unknown name.
        known: Sorted tuple of the known robot names.
    """

    def __init__(self, name: str, known: tuple[str, ...]):
        self.name = name
        self.known = known
        super().__init__(name)

    def __str__(self) -> str:
        return f"unknown robot '{self.name}'; known robots: {', '.join(self.known)}"


class UrdfBuildError(Dh2UrdfError):
    """The URDF built from a table did not pass yourdfpy's validation."""


class UnitWarning(UserWarning):
    """A value probably in another unit than the one said (degrees as radians, mm as m).

    The commands print it as one line on stderr; the value is used as given.
    """


class UrdfChainError(Dh2UrdfError, ValueError):
    """A URDF cannot give the serial chain asked for (not a URDF, unknown link, no path...).

    Attributes:
        path: The URDF file.
    """

    def __init__(self, path: str, message: str):
        self.path = path
        super().__init__(f"{path}: {message}")


class OutputFileError(Dh2UrdfError, ValueError):
    """An output path cannot take a command's output (a device, FIFO, folder, missing folder...).

    Found before any work is done; commands exit 2.

    Attributes:
        path: The file asked for.
        option: The command-line option (or argument) that named it.
    """

    def __init__(self, path: str, option: str, reason: str):
        self.path = path
        self.option = option
        super().__init__(f"{option} {path}: {reason}")


class OutputWriteError(Dh2UrdfError):
    """An output file could not be written to the end (full disk, quota, I/O error); exit 1.

    Nothing was left behind: the temporary file is removed and a previous file is unchanged.

    Attributes:
        path: The file being written.
        reason: What the operating system said.
    """

    def __init__(self, path: str, reason: str):
        self.path = path
        self.reason = reason
        super().__init__(path, reason)

    def __str__(self) -> str:
        return f"cannot write '{self.path}': {self.reason}; nothing was written"
