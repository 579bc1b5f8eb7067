"""Exceptions of the ``kin`` package: one base class, specific subclasses carrying data."""

from __future__ import annotations

from dh2urdf.exceptions import OutputFileError as _Dh2UrdfOutputFileError
from dh2urdf.exceptions import OutputWriteError as _Dh2UrdfOutputWriteError


class KinError(Exception):
    """Base class of every error raised by ``kin``."""


class ModelLoadError(KinError):
    """A robot model could not be loaded (missing or broken URDF, bad table)."""


class JointVectorError(KinError, ValueError):
    """A joint vector has the wrong size or non-finite values.

    Attributes:
        expected: Number of joint values the model needs.
        got: Number of values given.
    """

    def __init__(self, message: str, expected: int, got: int):
        self.expected = expected
        self.got = got
        super().__init__(message)


class FrameError(KinError, KeyError):
    """A frame name does not exist in the model.

    Attributes:
        frame: The unknown name.
        available: Names of the model's frames.
    """

    def __init__(self, frame: str, available: tuple[str, ...]):
        self.frame = frame
        self.available = available
        super().__init__(frame)

    def __str__(self) -> str:
        return f"frame '{self.frame}' does not exist; available frames: {', '.join(self.available)}"


class NotWithinLimitsError(KinError, ValueError):
    """A joint value is outside its limits.

    Attributes:
        joint: Joint name.
        value: Joint value [rad] or [m].
        lower: Lower limit [rad] or [m].
        upper: Upper limit [rad] or [m].
        unit: ``"rad"`` or ``"m"``.
    """

    def __init__(self, joint: str, value: float, lower: float, upper: float, unit: str = "rad"):
        self.joint = joint
        self.value = value
        self.lower = lower
        self.upper = upper
        self.unit = unit
        super().__init__(
            f"joint '{joint}' value {value:.6g} {unit} is outside its limits "
            f"[{lower:.6g}, {upper:.6g}] {unit}"
        )


class OutputFileError(KinError, _Dh2UrdfOutputFileError):
    """An output file cannot be written as asked; found before any work, commands exit 2.

    A device, FIFO or folder at the path, a missing or unwritable folder, an unknown suffix.

    Attributes:
        path: The file asked for.
        option: The command-line option (or argument) that named it.
    """


class OutputWriteError(KinError, _Dh2UrdfOutputWriteError):
    """An output file could not be written to the end (full disk, quota, I/O error); exit 1.

    The temporary file is removed and a previous file is unchanged.

    Attributes:
        path: The file being written.
        reason: What the operating system said.
    """


class RunFaultError(KinError):
    """A run failed part-way for a reason outside its input; commands exit 1 (not 2).

    A lost Dask scheduler, or a chunk whose worker process died every time it ran.
    """


class CollisionModelError(KinError, ValueError):
    """A collision model's input is bad: a scene file, an SRDF, a mesh of the scene.

    The message names the file and the field (``scene.toml: box[2].size: ...``); commands exit 2.

    Attributes:
        path: The file at fault (empty when the input came from memory).
    """

    def __init__(self, path: str, message: str):
        self.path = path
        super().__init__(f"{path}: {message}" if path else message)


class NamedStateError(KinError, ValueError):
    """A named joint state (``--seed-q ready``) the robot does not have, or only in part.

    Attributes:
        name: The name asked for.
        known: The robot's named states (full joint vectors), in their order.
    """

    def __init__(self, message: str, name: str, known: tuple[str, ...]):
        self.name = name
        self.known = known
        super().__init__(message)
