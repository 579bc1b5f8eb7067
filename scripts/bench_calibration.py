"""Benchmark kinematic calibration against the truth, beside figaroh on the same cases.

Cases (issue 45): UR10, Panda and humanoid7 built with errors (every joint origin moved 0.5 mm and
0.05 deg per component, zero offsets 0.05 deg, an unknown tracker pose and marker or tool frame),
measured with noise 0.05 mm per coordinate and 0.01 deg per axis at 100 and 30 random
configurations (positions, or full poses), kin.calibration.synthetic. Each calibration is scored
on 1,000 fresh configurations of the TRUE arm (noise-free): held-out RMS and maximum position
error [mm], RMS rotation error [deg]; and its wall time [s]. Goals: RMS <= 0.04 mm (100 rows),
<= 0.08 mm (30 rows), max <= 3x RMS; rotation <= 0.006 / 0.01 deg; each fit <= 1 s.

figaroh (PyPI, over Pinocchio) runs in its own virtual environment (it pins other versions):
``--figaroh /path/to/venv/bin/python``, or FIGAROH_PYTHON; this script then runs itself there as a
worker on the same URDF (the nominal table's), the same CSV rows and the same fresh
configurations: full_params, unknown base and tip frames, its closed-form frame guess, LM;
positions as differences, poses with its SE(3) log-map residual (position weight 1, rotation
0.5, as its UR10 example). Without figaroh the columns say why.
"""

from __future__ import annotations

import os

# One BLAS thread: idle OpenBLAS threads spinning on a 2-core machine make timings noisy.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ARMS = ("ur10", "panda", "humanoid7")
ROWS = (100, 30)
FRESH = 1000
CONFIG = """robot:
  name: "{name}"
  properties:
    joints:
      active_joints: [{joints}]
tasks:
  calibration:
    enabled: true
    type: kinematic_calibration
    parameters:
      calibration_level: "full_params"
      include_non_geometric: false
      regularization_coefficient: 0.0
      outlier_threshold: 1.0
    kinematics:
      base_frame: "universe"
      tool_frame: "{tool_frame}"
    measurements:
      markers:
        - name: "marker"
          reference_joint: "{last_joint}"
          measurable_dof: [true, true, true, {rotations}, {rotations}, {rotations}]
      poses:
        base_pose: [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
        tool_pose: [0.0, 0.0, 0.0, 0.0, 0.0, 0.0]
    data:
      source_file: "{data}"
      number_of_samples: {rows}
"""


def figaroh_worker(job_file: str) -> None:
    """Run one figaroh calibration described by ``job_file`` (JSON); print its predictions."""
    import pinocchio as pin
    from figaroh.calibration.base_calibration import BaseCalibration
    from figaroh.calibration.calibration_tools import calc_updated_fkm

    job = json.loads(Path(job_file).read_text())

    class Calibration(BaseCalibration):  # type: ignore[misc]
        def cost_function(self, var):  # type: ignore[no-untyped-def]
            estimated = calc_updated_fkm(
                self.model, self.data, var, self.q_measured, self.calib_config
            )
            if not job["poses"]:
                return estimated - self.PEE_measured
            raw = self._compute_logmap_residuals(self.PEE_measured, estimated)
            return self.apply_measurement_weighting(raw, pos_weight=1.0, orient_weight=0.5)

    robot = pin.RobotWrapper.BuildFromURDF(job["urdf"])
    clock = time.perf_counter()
    calibration = Calibration(robot, job["config"])
    calibration.calib_config["known_baseframe"] = False
    calibration.calib_config["known_tipframe"] = False
    calibration.initialize()
    calibration.solve(enable_logging=False)
    seconds = time.perf_counter() - clock
    fresh = np.array(job["fresh"])
    config = dict(calibration.calib_config, NbSample=len(fresh))
    q = np.tile(np.array(config["q0"], dtype=float), (len(fresh), 1))
    q[:, config["config_idx"]] = fresh
    values = calc_updated_fkm(robot.model, robot.data, calibration.var_, q, config)
    values = values.reshape(6 if job["poses"] else 3, len(fresh)).T
    rotations = [pin.rpy.rpyToMatrix(v[3:]).tolist() for v in values] if job["poses"] else None
    print(
        json.dumps({"points": values[:, :3].tolist(), "rotations": rotations, "seconds": seconds})
    )


def _case(name: str, rows: int, poses: bool, seed: int):  # type: ignore[no-untyped-def]
    from dh2urdf import get_robot
    from kin.calibration import true_arm
    from kin.calibration.synthetic import random_configurations

    table = get_robot(name).load_table()
    arm = true_arm(table, seed=seed)
    rng = np.random.default_rng(1000 + seed)
    return table, arm, arm.measure(random_configurations(table, rows, rng), poses, rng)


def _scores(truth, points: np.ndarray, rotations: np.ndarray | None) -> tuple[float, float, float]:  # type: ignore[no-untyped-def]
    from kin.calibration.fit import rotation_errors

    distance = np.linalg.norm(points - truth.points[:, 0], axis=1)
    rms = float(np.sqrt(np.mean(distance**2)))
    rot = np.nan
    if rotations is not None:
        rot = float(
            np.degrees(
                np.sqrt(np.mean(np.sum(rotation_errors(truth.rotations, rotations) ** 2, axis=1)))
            )
        )
    return rms * 1e3, float(distance.max()) * 1e3, rot


def _figaroh(python: str, table, data, fresh: np.ndarray, folder: Path):  # type: ignore[no-untyped-def]
    from scipy.spatial.transform import Rotation

    from dh2urdf.urdf_writer import urdf_string

    urdf, csv, config, job = (
        folder / n for n in ("arm.urdf", "data.csv", "config.yaml", "job.json")
    )
    urdf.write_text(urdf_string(table))
    poses = data.rotations is not None
    head = (
        ["x1", "y1", "z1"]
        + (["phix1", "phiy1", "phiz1"] if poses else [])
        + list(table.joint_names)
    )
    values = data.points[:, 0]
    if poses:
        values = np.hstack([values, Rotation.from_matrix(data.rotations).as_euler("xyz")])
    lines = [",".join(head)] + [
        ",".join(repr(float(v)) for v in [*a, *b]) for a, b in zip(values, data.q)
    ]
    csv.write_text("\n".join(lines) + "\n")
    last = table.rows[-1].name
    config.write_text(
        CONFIG.format(
            name=table.name,
            joints=", ".join(f'"{n}"' for n in table.joint_names),
            tool_frame=f"frame{table.dof}",
            last_joint=last,
            rotations="true" if poses else "false",
            data=csv,
            rows=data.count,
        )
    )
    job.write_text(
        json.dumps(
            {"urdf": str(urdf), "config": str(config), "poses": poses, "fresh": fresh.tolist()}
        )
    )
    done = subprocess.run(
        [python, __file__, "--figaroh-worker", str(job)],
        capture_output=True,
        text=True,
        check=False,
    )
    if done.returncode != 0:
        return None, done.stderr.strip().splitlines()[-1][:80] if done.stderr.strip() else "failed"
    out = json.loads(done.stdout.strip().splitlines()[-1])
    rotations = None if out["rotations"] is None else np.array(out["rotations"])
    return (np.array(out["points"]), rotations, out["seconds"]), ""


def main(argv: list[str] | None = None) -> int:
    """Print the table of cases: ours, then figaroh's."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["--figaroh-worker"]:  # in figaroh's venv: no kin there
        figaroh_worker(argv[1])
        return 0
    from dh2urdf.command_line import whole_number
    from kin.cli import ArgumentParser

    parser = ArgumentParser(prog="bench_calibration.py", description=__doc__.splitlines()[0])
    parser.add_argument(
        "--figaroh",
        metavar="PYTHON",
        default=os.environ.get("FIGAROH_PYTHON"),
        help="python of a venv with figaroh (default: $FIGAROH_PYTHON, else not run)",
    )
    parser.add_argument("--seed", type=whole_number, default=1, help="case seed (1)")
    parser.add_argument("--arms", nargs="+", choices=ARMS, default=list(ARMS), help="arms (all)")
    parser.add_argument(
        "--rows", nargs="+", type=int, choices=ROWS, default=list(ROWS), help="rows (100 30)"
    )
    args = parser.parse_args(argv)
    from kin.calibration import calibrate
    from kin.calibration.prediction import predict
    from kin.calibration.synthetic import random_configurations

    print(f"held-out errors on {FRESH} fresh configurations of the true arm; seed {args.seed}")
    print(
        f"{'case':<26} {'ours: RMS [mm]':>14} {'max':>7} {'rot [deg]':>10} {'time [s]':>9}   {'figaroh: RMS':>12} {'max':>7} {'rot [deg]':>10} {'time [s]':>9}"
    )
    note = "" if args.figaroh else "figaroh: not run (give --figaroh PYTHON of a venv with figaroh)"
    for name in args.arms:
        for poses in (False, True):
            for rows in args.rows:
                table, arm, data = _case(name, rows, poses, args.seed)
                fresh = random_configurations(table, FRESH, np.random.default_rng(12345))
                truth = arm.measure(fresh, poses)
                clock = time.perf_counter()
                found = calibrate(table, data, folds=0)
                seconds = time.perf_counter() - clock
                pred = predict(found.model, found.x, fresh)
                rms, top, rot = _scores(truth, pred.points[:, 0], pred.rotations)
                line = f"{name + (' poses' if poses else ' positions') + f' {rows}':<26} {rms:>14.4f} {top:>7.4f} {rot:>10.5f} {seconds:>9.3f}"
                if args.figaroh:
                    with tempfile.TemporaryDirectory() as folder:
                        got, why = _figaroh(args.figaroh, table, data, fresh, Path(folder))
                    if got is None:
                        line += f"   figaroh failed: {why}"
                    else:
                        f_rms, f_top, f_rot = _scores(truth, got[0], got[1])
                        line += f"   {f_rms:>12.4f} {f_top:>7.4f} {f_rot:>10.5f} {got[2]:>9.3f}"
                print(line, flush=True)
    if note:
        print(note)
    return 0


if __name__ == "__main__":
    sys.exit(main())
