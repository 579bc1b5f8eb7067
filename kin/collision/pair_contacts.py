"""Which link pairs touch at a configuration, without padding: the sampling rules' one test.

The rules that decide pairs by sampling (:mod:`.always_pairs` when a DH model is built,
:mod:`.srdf_generator` for ``kin collisions``) ask the same question of many configurations: of
these link pairs, which are in contact at ``q``? :class:`PairContacts` answers it with the
verdict of :mod:`.requests` at zero padding (closer than
:data:`~kin.collision.requests.CONTACT_TOLERANCE`): a pair touches when any shape of one link
touches any shape of the other. :func:`sampling_bounds` are the bounds the samples are drawn in.
"""

from __future__ import annotations

import math
from collections.abc import Iterable

import numpy as np
import numpy.typing as npt
import pinocchio as pin

from .requests import prepare_requests

__all__ = ["PairContacts", "sampling_bounds"]


def sampling_bounds(model: pin.Model) -> tuple[np.ndarray, np.ndarray]:
    """Lower and upper bounds of the random configurations [rad] or [m], shape (nq,) each.

    The joint limits; an unbounded joint within +-pi [rad], as MoveIt bounds a continuous joint
    (moveit_core/robot_model/src/revolute_joint_model.cpp, ``setContinuous``).
    """
    lower = np.where(np.isfinite(model.lowerPositionLimit), model.lowerPositionLimit, -math.pi)
    upper = np.where(np.isfinite(model.upperPositionLimit), model.upperPositionLimit, math.pi)
    return lower, upper


class PairContacts:
    """The link pairs of a geometry model in contact at a configuration, padding 0.

    Args:
        model: The arm's Pinocchio model (it places the shapes).
        geometry_model: The shapes, with one collision pair per shape pair of ``pair_owners``.
        pair_owners: Per collision pair of ``geometry_model``, its ``(a, b)`` link pair.
    """

    def __init__(
        self,
        model: pin.Model,
        geometry_model: pin.GeometryModel,
        pair_owners: Iterable[tuple[str, str]],
    ):
        self._model = model
        self._geometry_model = geometry_model
        self._data = model.createData()
        self._geometry_data = pin.GeometryData(geometry_model)
        prepare_requests(self._geometry_data, 0.0)
        self._indices: dict[tuple[str, str], list[int]] = {}
        for index, owners in enumerate(pair_owners):
            self._indices.setdefault(owners, []).append(index)

    @classmethod
    def of_pairs(
        cls,
        model: pin.Model,
        geometry_model: pin.GeometryModel,
        owners: tuple[str, ...],
        pairs: Iterable[tuple[str, str]],
    ) -> PairContacts:
        """A test of ``pairs`` on the shapes of ``geometry_model`` (its own pairs left out).

        Args:
            model: The arm's Pinocchio model.
            geometry_model: The shapes (not changed: the test keeps a copy).
            owners: Per geometry object, the link it belongs to.
            pairs: The ``(a, b)`` link pairs to test.
        """
        by_owner: dict[str, list[int]] = {}
        for index, owner in enumerate(owners):
            by_owner.setdefault(owner, []).append(index)
        shapes = pin.GeometryModel(geometry_model)
        shapes.removeAllCollisionPairs()
        pair_owners = []
        for a, b in pairs:
            for i in by_owner.get(a, ()):
                for j in by_owner.get(b, ()):
                    shapes.addCollisionPair(pin.CollisionPair(i, j))
                    pair_owners.append((a, b))
        return cls(model, shapes, pair_owners)

    @property
    def pairs(self) -> frozenset[tuple[str, str]]:
        """The link pairs this test can answer for."""
        return frozenset(self._indices)

    def at(
        self, q: npt.ArrayLike, pairs: Iterable[tuple[str, str]] | None = None
    ) -> set[tuple[str, str]]:
        """The ``pairs`` (default: all of :attr:`pairs`) in contact at ``q`` [rad] or [m]."""
        pin.updateGeometryPlacements(
            self._model, self._data, self._geometry_model, self._geometry_data, np.asarray(q)
        )
        return {
            pair
            for pair in (self._indices if pairs is None else pairs)
            if any(
                pin.computeCollision(self._geometry_model, self._geometry_data, k)
                for k in self._indices[pair]
            )
        }
