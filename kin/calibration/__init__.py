"""Kinematic calibration: the DH table of the arm you actually have, from measured poses.

A nominal DH table and measurements of the real arm (joint values with a tracker's positions,
poses or several markers per row) give a calibrated table and URDF. The parameter model
(:mod:`~kin.calibration.parameters`: DH values per row, Hayati's tilt where consecutive axes are
parallel, the measurement frame, the tool or markers), the measurement file reader
(:mod:`~kin.calibration.measurements`), identifiability (:mod:`~kin.calibration.identifiability`),
the fit (:mod:`~kin.calibration.fit`, :func:`calibrate`), the report
(:mod:`~kin.calibration.report`), the output files (:mod:`~kin.calibration.outputs`), pose planning
(:mod:`~kin.calibration.pose_plan`) and synthetic cases with a known truth
(:mod:`~kin.calibration.synthetic`). The command is ``dh2urdf calibrate``
(:mod:`kin.commands.calibrate`).
"""

from .calibration import Calibration, calibrate
from .errors import Errors
from .exceptions import CalibrationError
from .fit import Noise
from .identifiability import Identifiability, Unidentifiable
from .measurements import Measurements, read_measurements
from .outputs import calibrated_table, calibrated_urdf
from .parameters import Parameter, ParameterModel
from .pose_plan import PosePlan, plan_poses
from .report import calibration_json, calibration_text
from .synthetic import TrueArm, held_out_errors, true_arm

__all__ = [
    "Calibration",
    "CalibrationError",
    "Errors",
    "Identifiability",
    "Measurements",
    "Noise",
    "Parameter",
    "ParameterModel",
    "PosePlan",
    "TrueArm",
    "Unidentifiable",
    "calibrate",
    "calibrated_table",
    "calibrated_urdf",
    "calibration_json",
    "calibration_text",
    "held_out_errors",
    "plan_poses",
    "read_measurements",
    "true_arm",
]
