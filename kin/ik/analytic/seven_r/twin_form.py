"""What the 7R free-joint forms with a compiled twin share: the twin, its parameters, ``first_many``.

:class:`~.seven_dof.SevenDofIK` (twin ``_closed7``) and
:class:`~.spherical_shoulder7.SphericalShoulder7RIK` (twin ``_shoulder7``) each declare their
twin module and :meth:`TwinForm.c_fields` (the parameters by the twin's field names) and
:meth:`TwinForm.many_targets` (N world targets as the twin's ``first_many`` reads them); the
packing of the parameters (:func:`~.subproblems.pack_params` in the twin's ``LAYOUT``) and the
batched call are written here once. Angles in [rad], lengths in [m].
"""

from __future__ import annotations

from types import ModuleType
from typing import Any, ClassVar

import numpy as np

from ..twin_support import ScanJob, call_first_many, pack_params


class TwinForm:
    """The compiled-twin half of a 7R free-joint closed form (mixed in)."""

    #: The twin module (``kin._native.twin(...)``), or None when it is not built.
    twin_module: ClassVar[ModuleType | None] = None
    #: Whether the compiled twin is built (set from :attr:`twin_module`).
    compiled_twin: ClassVar[bool] = False

    lower: tuple[float, ...]
    upper: tuple[float, ...]
    _sin: tuple[float, ...]
    _cos: tuple[float, ...]
    _offsets: tuple[float, ...]
    _c_params: np.ndarray | None = None

    def __init_subclass__(cls, **kwargs: Any) -> None:
        super().__init_subclass__(**kwargs)
        cls.compiled_twin = cls.twin_module is not None

    def c_fields(self) -> dict[str, tuple[float, ...]]:  # pragma: no cover - the form's own
        """The twin's parameters by field name (its ``..._PARAMS`` list; lengths [m])."""
        raise NotImplementedError

    def many_targets(
        self, positions: np.ndarray, rotations: np.ndarray | None
    ) -> tuple[tuple[Any, ...], np.ndarray | None]:  # pragma: no cover - the form's own
        """The twin's leading arguments after the parameters, and the (N, width) targets."""
        raise NotImplementedError

    @property
    def c_params(self) -> np.ndarray:
        """:meth:`c_fields` packed in the order the compiled twin declares (its ``LAYOUT``)."""
        if self._c_params is None:
            if self.twin_module is None:
                raise RuntimeError(f"the compiled twin of {type(self).__name__} is not built")
            self._c_params = pack_params(self.c_fields(), self.twin_module.LAYOUT)
        return self._c_params

    @property
    def twin(self) -> Any:
        """The compiled twin module, or None when it is not built."""
        return self.twin_module

    def first_many(
        self,
        positions: np.ndarray,
        rotations: np.ndarray | None,
        starts: np.ndarray,
        steps: tuple[float, ...],
        later: bool = False,
    ) -> np.ndarray | ScanJob | None:
        """``first`` of N targets, each from its own start, the scan steps in turn.

        The compiled twin in one call (its loop without the GIL); None when it is not built (the
        caller asks ``first`` target by target).

        Args:
            positions: Tool positions in the world frame [m], (N, 3).
            rotations: Tool rotations ``R_world_tool`` (N, 3, 3), or None for positions.
            starts: Start joint vectors [rad], (N, 7).
            steps: Free-joint scan steps [rad] tried in turn (``0.0``: the start's value only).
            later: Start the scan and return at once.

        Returns:
            (N, 7) the branch of each target nearest its start [rad], NaN rows where none; with
            ``later``, a :class:`~.subproblems.ScanJob` whose ``result()`` gives them (the scan
            runs in threads meanwhile: :func:`~.subproblems.call_first_many`).
        """
        if self.twin_module is None:
            return None
        head, targets = self.many_targets(positions, rotations)
        return call_first_many(
            self.twin_module.first_many, (self.c_params, *head), targets, starts, steps, later
        )
