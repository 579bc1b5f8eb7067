"""The residuals of a calibration as a picture: per measurement, before and after (matplotlib)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .calibration import Calibration


def plot_residuals(calibration: Calibration, path: str | Path) -> None:
    """Write a PNG (whole or not at all) of each row's position error before and after the fit [mm] (and rotation [deg]).

    Bars of the nominal arm's errors (placed by its best base and tool) and the calibrated arm's,
    row by row in file order; the cross-validated errors as points when there are some.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = np.arange(1, calibration.measurements.count + 1)
    rotation = calibration.after.rotation is not None
    figure, axes = plt.subplots(
        2 if rotation else 1, 1, figsize=(9, 6 if rotation else 3.5), squeeze=False
    )
    top = axes[0, 0]
    top.bar(
        rows,
        calibration.before.position.max(axis=1) * 1e3,
        color="#d0d0d0",
        label="before (nominal)",
    )
    top.bar(
        rows, calibration.after.position.max(axis=1) * 1e3, color="#1f77b4", label="after (fit)"
    )
    if calibration.cross_validated is not None:
        top.plot(
            rows,
            calibration.cross_validated.position.max(axis=1) * 1e3,
            "k.",
            label="cross-validated",
        )
    top.set_yscale("log")
    top.set_ylabel("position error [mm]")
    top.legend(loc="upper right", fontsize=8)
    if rotation:
        low = axes[1, 0]
        assert calibration.before.rotation is not None and calibration.after.rotation is not None
        low.bar(rows, np.degrees(calibration.before.rotation), color="#d0d0d0")
        low.bar(rows, np.degrees(calibration.after.rotation), color="#ff7f0e")
        low.set_yscale("log")
        low.set_ylabel("rotation error [deg]")
    axes[-1, 0].set_xlabel("measurement (row of the file)")
    figure.suptitle(
        f"calibration of {calibration.table.name}: {calibration.measurements.count} rows"
    )
    figure.tight_layout()
    from dh2urdf.output_file import write_atomic

    try:
        write_atomic(path, lambda handle: figure.savefig(handle, format="png", dpi=100))
    finally:
        plt.close(figure)
