"""The k nearest samples of the seed table (kin/ik/numeric/seed_table.py): NumPy's full stable sort.

:func:`~kin.ik.numeric.seed_table.nearest_first` ranks a neighbourhood without sorting it all; it
must give exactly the indices of ``np.argsort(distances, kind="stable")[:k]``, ties and NaN
included, and the table's queries the samples a brute-force ranking of every sample gives.
"""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from kin.ik.numeric.seed_table import nearest_first

#: Few distinct values (ties everywhere), NaN and infinities among them.
_VALUES = st.one_of(
    st.sampled_from([0.0, 1.0, 2.0, 2.0, np.inf, np.nan]),
    st.floats(min_value=-1e300, max_value=1e300),
)


@settings(max_examples=300, deadline=None)
@given(
    distances=hnp.arrays(np.float64, st.integers(0, 400), elements=_VALUES),
    k=st.integers(0, 60),
)
@example(distances=np.array([1.0] * 50 + [0.0] * 3), k=5)  # ties at the k-th: lowest index first
@example(distances=np.array([np.nan] * 40 + [3.0, 1.0]), k=4)  # fewer numbers than k
@example(distances=np.arange(100.0)[::-1].copy(), k=1)
def test_nearest_first_is_the_stable_sort(distances: np.ndarray, k: int) -> None:
    """Index for index the head of NumPy's stable argsort, whatever the ties, NaN or k."""
    expected = np.argsort(distances, kind="stable")[:k]
    np.testing.assert_array_equal(nearest_first(distances, k), expected)


def test_a_large_neighbourhood_is_ranked_as_by_a_full_sort() -> None:
    """20,000 distances with many exact ties (rounded) and k = 8: the partitioned path itself."""
    rng = np.random.default_rng(3)
    distances = np.round(rng.random(20_000), 3)
    for k in (1, 2, 8, 64):
        np.testing.assert_array_equal(
            nearest_first(distances, k), np.argsort(distances, kind="stable")[:k]
        )
