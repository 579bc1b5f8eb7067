"""Exceptions of ``kin.viewer``: one base class (a :class:`kin.KinError`), specific subclasses."""

from __future__ import annotations

from ..exceptions import KinError


class ViewerError(KinError):
    """Base class of every error raised by ``kin.viewer``."""


class ViewerInputError(ViewerError, ValueError):
    """A value to show is malformed (wrong shape, not finite, empty path)."""


class PageWriteError(ViewerError, OSError):
    """The static page cannot be written.

    Attributes:
        path: The page's path.
        reason: What the operating system said.
    """

    def __init__(self, path: str, reason: str):
        self.path = path
        self.reason = reason
        super().__init__(f"cannot write the page '{path}': {reason}")

    def __str__(self) -> str:
        return f"cannot write the page '{self.path}': {self.reason}"
