"""Exceptions of ``kin.viewer``: one base class (a :class:`kin.KinError`), specific subclasses."""

from __future__ import annotations

from ..exceptions import KinError, OutputWriteError, RunFaultError


class ViewerError(KinError):
    """Base class of every error raised by ``kin.viewer``."""


class ViewerInputError(ViewerError, ValueError):
    """A value to show is malformed (wrong shape, not finite, empty path)."""


class PageWriteError(ViewerError, OutputWriteError, OSError):
    """The static page cannot be written (commands exit 1: checked beforehand, it is a fault).

    Attributes:
        path: The page's path.
        reason: What the operating system said.
    """

    def __init__(self, path: str, reason: str):
        super().__init__(path, reason)

    def __str__(self) -> str:
        return f"cannot write the page '{self.path}': {self.reason}"


class PictureWriteError(PageWriteError):
    """The picture (``kin preview --png``) cannot be written; commands exit 1."""

    def __str__(self) -> str:
        return f"cannot write the picture '{self.path}': {self.reason}"


class NoBrowserError(ViewerError):
    """No headless browser to take a picture with (commands exit 2: install one)."""


class ScreenshotError(ViewerError, RunFaultError):
    """The browser ran but gave no picture (it failed, or hung past its time); commands exit 1."""
