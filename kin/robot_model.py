"""Load a robot (registry name or DH table path) into a Pinocchio model built from its URDF.

A URDF chain with a mimic joint in series is refused by :func:`load_robot` (every table row is
one independent joint) and loaded by :func:`kin.mimic.arm.load_arm` as a
:class:`kin.mimic.arm.MimicArm` (which imports this module, not the other way).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from dh2urdf import ROBOTS, DHTable, get_robot, load_table
from dh2urdf.input_file import read_input

from .exceptions import ModelLoadError

if TYPE_CHECKING:
    from dh2urdf.urdf_chain import UrdfChain


@dataclass(frozen=True, eq=False)
class RobotModel:
    """A robot ready for kinematics.

    Attributes:
        name: Robot name.
        table: Its DH table (SI units).
        model: Pinocchio model built from the generated URDF.
        urdf: URDF text the model was built from (visuals included).
        tool_frame: Name of the tool frame.
        urdf_source: For a robot loaded from a URDF, ``(file, base link, tip link)`` of the
            chain its table was read from (the preview draws the maker's meshes from it).
    """

    name: str
    table: DHTable
    model: pin.Model
    urdf: str
    tool_frame: str = "tool"
    urdf_source: tuple[str, str, str] | None = None

    @property
    def nq(self) -> int:
        """Number of joint values."""
        return int(self.model.nq)

    @property
    def joint_names(self) -> tuple[str, ...]:
        """Names of the actuated joints, base to tip."""
        return tuple(self.model.names[1:])

    @property
    def lower(self) -> np.ndarray:
        """Lower joint limits [rad] or [m]."""
        return self.model.lowerPositionLimit.copy()

    @property
    def upper(self) -> np.ndarray:
        """Upper joint limits [rad] or [m]."""
        return self.model.upperPositionLimit.copy()

    @property
    def frame_names(self) -> tuple[str, ...]:
        """Names of all frames of the model."""
        return tuple(frame.name for frame in self.model.frames)


@functools.lru_cache(maxsize=32)
def _load_by_name(name: str) -> RobotModel:
    description = get_robot(name)
    table = description.load_table()
    path = description.urdf_path
    try:
        text = read_input(path).decode("utf-8")
    except OSError as err:
        raise ModelLoadError(
            f"{path}: cannot read the URDF of '{name}' ({err.strerror}); "
            "run: python scripts/generate_urdfs.py"
        ) from err
    return _build(name, table, text, str(path))


def _build(name: str, table: DHTable, text: str, where: str) -> RobotModel:
    from dh2urdf.exceptions import UrdfChainError
    from dh2urdf.urdf_parse import build_pinocchio_model

    try:
        model = build_pinocchio_model(text, where)
    except UrdfChainError as err:
        raise ModelLoadError(str(err)) from err
    model.name = name
    return RobotModel(name=name, table=table, model=model, urdf=text)


def robot_from_table(table: DHTable) -> RobotModel:
    """Robot of an in-memory DH table (e.g. a variant of a shipped one), through its URDF.

    Raises:
        ModelLoadError: Pinocchio cannot load it.
    """
    from dh2urdf.urdf_writer import urdf_string  # string formatting: no yourdfpy, no trimesh

    return _build(table.name, table, urdf_string(table), table.path or table.name)


def urdf_file(robot: str | Path) -> str | None:
    """``robot`` as a path when it names a URDF file (not a registry name), else None.

    A URDF is a ``.urdf``, a ``.xacro``, or any other file whose root element is ``<robot>``.
    """
    from dh2urdf.urdf_parse import is_urdf_file

    text = str(robot)
    return text if text not in ROBOTS and is_urdf_file(text) else None


def robot_from_chain(chain: UrdfChain) -> RobotModel:
    """Robot of a URDF chain read as a DH table (one independent joint per row).

    Raises:
        dh2urdf.urdf_chain.UrdfChainError: The table does not reproduce the chain.
        ModelLoadError: A joint of the chain follows another (mimic): the message names it,
            what takes such a chain (``kin fk``, ``kin ik``, :func:`kin.load_arm`) and
            the fix.
    """
    from dh2urdf.urdf_to_dh import check_table, table_from_chain

    for joint in chain.joints:
        if joint.mimic is not None:
            raise ModelLoadError(
                f"{chain.path}: joint {joint.name!r} follows {joint.mimic.leader!r} (mimic): "
                "kin fk and kin ik follow it (kin.load_arm in Python); this command "
                "takes one independent joint per DH row: choose a --tip before it"
            )
    table = table_from_chain(chain)
    check_table(chain, table)
    model = robot_from_table(table)
    return replace(model, urdf_source=(chain.path, chain.base, chain.tip))


def load_robot(robot: str | Path, base: str | None = None, tip: str | None = None) -> RobotModel:
    """Load a shipped robot by name, a DH table file, or the chain of a URDF file.

    A URDF (``.urdf``, or ``.xacro`` with the optional ``xacrodoc``; any other file whose root
    element is ``<robot>``, whatever its suffix) is read as a DH table
    (:func:`dh2urdf.urdf_to_dh.table_from_urdf`: the chain from ``base`` to ``tip``), and the
    model is built from that table like any other: every solver sees one DH table.

    Args:
        robot: Registry name (e.g. ``"ur5"``), path to a ``.toml`` DH table, or a URDF.
        base: Base link of a URDF's chain (default: its root link).
        tip: Tip link of a URDF's chain (default: the single leaf below its last joint).

    Raises:
        dh2urdf.UnknownRobotError: Not a known name (the message lists them) nor a path.
        dh2urdf.TableError: The table file is malformed.
        dh2urdf.urdf_chain.UrdfChainError: The URDF gives no serial chain from base to tip, or
            the file is another kind of XML (an MJCF ``<mujoco>``...).
        ModelLoadError: The URDF cannot be read or loaded; base or tip given for a table; a
            mimic joint on the URDF's chain (:func:`kin.load_arm` follows it: the loader of
            ``kin fk`` and ``kin ik``, whose arm :func:`kin.ik.get_solver` solves as they do).
    """
    path = urdf_file(robot)
    if path is not None:
        from dh2urdf.urdf_chain import read_chain

        return robot_from_chain(read_chain(path, base, tip))
    return _load_table_robot(robot, base, tip)


def _load_table_robot(robot: str | Path, base: str | None, tip: str | None) -> RobotModel:
    """A shipped robot or a DH table file (``base`` and ``tip`` must be None)."""
    text = str(robot)
    if base is not None or tip is not None:
        raise ModelLoadError(f"{text}: --base and --tip choose links of a URDF, not of a DH table")
    if isinstance(robot, Path) or text.endswith(".toml") or "/" in text:
        return robot_from_table(load_table(robot))
    return _load_by_name(text)
