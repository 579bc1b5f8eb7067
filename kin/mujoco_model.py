"""Load the same generated URDF into MuJoCo, keeping every frame (no fusing of fixed links).

MuJoCo's URDF import fuses links attached by fixed joints unless told otherwise; the tool frame
would disappear. URDFs written by dh2urdf carry ``<mujoco><compiler fusestatic="false"/></mujoco>``
themselves; for a URDF without a ``<mujoco>`` element the loader adds it to the text, so every URDF
link (``frame{i}``, ``tool``) is a MuJoCo body of the same name.

MuJoCo is imported inside the function: ``import kin`` stays light.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .exceptions import ModelLoadError
from .robot_model import RobotModel

if TYPE_CHECKING:  # pragma: no cover
    import mujoco

_COMPILER = (
    '<mujoco><compiler fusestatic="false" discardvisual="false" '
    'balanceinertia="true" angle="radian"/></mujoco>'
)


def mujoco_urdf_text(robot: RobotModel) -> str:
    """URDF text of ``robot`` with the MuJoCo compiler options that keep fixed links."""
    text = robot.urdf
    if "<mujoco>" in text:
        return text
    start = text.find("<robot")
    if start < 0:
        raise ModelLoadError(f"'{robot.name}': URDF text has no <robot> element")
    end = text.find(">", start)
    body = text[start:]
    header_end = end - start + 1
    return body[:header_end] + _COMPILER + body[header_end:]


def load_mujoco_model(robot: RobotModel) -> mujoco.MjModel:
    """MuJoCo model of ``robot`` built from its URDF, fixed links kept as bodies.

    A continuous joint (a table row's ``continuous``) is unlimited in it, as in the MJCF writer.

    Raises:
        ModelLoadError: MuJoCo is not installed or rejects the URDF.
    """
    try:
        import mujoco
    except ImportError as err:  # pragma: no cover
        raise ModelLoadError("MuJoCo is not installed: pip install mujoco") from err
    try:
        model = mujoco.MjModel.from_xml_string(mujoco_urdf_text(robot))
    except ValueError as err:
        raise ModelLoadError(f"'{robot.name}': MuJoCo cannot load the URDF: {err}") from err
    for row in robot.table.rows:  # a continuous joint has no limits (the URDF's [-pi, pi] aside)
        if row.continuous:
            model.jnt_limited[model.joint(row.name).id] = 0
    return model
