"""A reference URDF (e.g. the maker's), its frame driven by the table's joint vector.

The table's joints map onto the URDF's actuated joints by name when the URDF has every one of
them, else by order (the first ``dof`` actuated joints, base to tip); other joints stay at their
neutral value. Continuous joints (``nq = 2`` in Pinocchio) are set through ``(cos, sin)``.
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import IO
from xml.etree import ElementTree

import numpy as np
import numpy.typing as npt

from dh2urdf import DHTable

from .exceptions import AuditError

#: Joint range [rad] sampled for revolute joints with wider or no limits.
REVOLUTE_SPAN = np.pi


@dataclass(frozen=True, eq=False)
class ReferenceUrdf:
    """A URDF frame as a function of the table's joint vector.

    Attributes:
        path: The URDF file.
        frame: Name of the frame compared with the table's tool.
        model: Pinocchio model of the URDF.
        frame_id: Index of ``frame`` in ``model.frames``.
        q_index: Per table joint, index of its value in the URDF's configuration vector.
        continuous: Per table joint, True for a continuous joint (configuration ``(cos, sin)``).
        mapped_by: ``"name"`` or ``"order"``: how the table's joints were matched.
    """

    path: str
    frame: str
    model: object
    frame_id: int
    q_index: tuple[int, ...]
    continuous: tuple[bool, ...]
    mapped_by: str

    def poses(self, q: npt.ArrayLike) -> np.ndarray:
        """``T_root_frame`` (N, 4, 4) [m] at the table's joint vectors ``q`` (N, dof) [rad, m]."""
        import pinocchio as pin

        model = self.model
        data = model.createData()  # type: ignore[attr-defined]
        q = np.atleast_2d(np.asarray(q, dtype=float))
        out = np.empty((len(q), 4, 4))
        for k, row in enumerate(q):
            full = pin.neutral(model)
            for value, index, continuous in zip(row, self.q_index, self.continuous, strict=True):
                if continuous:
                    full[index : index + 2] = (np.cos(value), np.sin(value))
                else:
                    full[index] = value
            pin.framesForwardKinematics(model, data, full)
            out[k] = data.oMf[self.frame_id].homogeneous
        return out


@contextlib.contextmanager
def _captured_stderr() -> Iterator[IO[str]]:
    """Send what C++ code writes on file descriptor 2 (urdfdom's parse errors) to a file."""
    sys.stderr.flush()
    with tempfile.TemporaryFile(mode="w+") as sink:
        saved = os.dup(2)
        try:
            os.dup2(sink.fileno(), 2)
            yield sink
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            sink.seek(0)


def load_reference(path: str | Path, frame: str, table: DHTable) -> ReferenceUrdf:
    """Load ``path`` and find ``frame`` and the joints of ``table`` in it.

    Raises:
        AuditError: The file cannot be read or loaded, it has no frame ``frame`` (the message
            lists the frames), or fewer actuated joints than the table.
    """
    import pinocchio as pin

    where = str(path)
    if not Path(path).is_file():
        raise AuditError("no such URDF file", where)
    try:
        root = ElementTree.parse(where).getroot()
    except ElementTree.ParseError as err:
        raise AuditError(f"not valid XML: {err}", where) from err
    if root.tag != "robot":
        raise AuditError(f"not a URDF: the root element is <{root.tag}>, not <robot>", where)
    with _captured_stderr() as messages:
        try:
            model = pin.buildModelFromUrdf(where)
        except (RuntimeError, ValueError) as err:
            said = " ".join(messages.read().split()) or str(err)
            raise AuditError(f"Pinocchio cannot load the URDF: {said}", where) from err
    if not model.existFrame(frame):
        links = [f.name for f in model.frames if f.type == pin.FrameType.BODY]
        raise AuditError(
            f"the URDF has no frame '{frame}'; available frames: {', '.join(links)}", where
        )
    actuated = [j for j in range(1, model.njoints) if model.joints[j].nv == 1]
    joint_names = [model.names[j] for j in actuated]
    if all(name in joint_names for name in table.joint_names):
        chosen, mapped_by = [actuated[joint_names.index(n)] for n in table.joint_names], "name"
    elif len(actuated) >= table.dof:
        chosen, mapped_by = actuated[: table.dof], "order"
    else:
        raise AuditError(
            f"the URDF has {len(actuated)} actuated joints ({', '.join(joint_names)}), "
            f"the table {table.dof}",
            where,
        )
    return ReferenceUrdf(
        path=where,
        frame=frame,
        model=model,
        frame_id=int(model.getFrameId(frame)),
        q_index=tuple(int(model.idx_qs[j]) for j in chosen),
        continuous=tuple(model.joints[j].nq == 2 for j in chosen),
        mapped_by=mapped_by,
    )


def sample_joint_vectors(
    table: DHTable, reference: ReferenceUrdf, count: int, seed: int = 0
) -> np.ndarray:
    """``count`` joint vectors (count, dof) [rad, m], uniform within both models' limits.

    Revolute ranges are clipped to [-pi, pi] (a turn tells nothing more).
    """
    model = reference.model
    lower, upper = table.lower.copy(), table.upper.copy()
    for k, (index, continuous) in enumerate(
        zip(reference.q_index, reference.continuous, strict=True)
    ):
        if not continuous:
            low = float(model.lowerPositionLimit[index])  # type: ignore[attr-defined]
            high = float(model.upperPositionLimit[index])  # type: ignore[attr-defined]
            if np.isfinite(low) and np.isfinite(high) and high > low:
                lower[k], upper[k] = max(lower[k], low), min(upper[k], high)
        if table.rows[k].joint_type == "revolute":
            lower[k], upper[k] = max(lower[k], -REVOLUTE_SPAN), min(upper[k], REVOLUTE_SPAN)
    upper = np.maximum(upper, lower)
    return np.random.default_rng(seed).uniform(lower, upper, size=(count, table.dof))
