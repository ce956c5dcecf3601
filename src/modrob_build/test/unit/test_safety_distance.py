"""Safety distance between bases: the corrected seed equation 10, repeated until no conflict."""
import itertools
import math
import random

import pytest

from modrob_build.errors import LayoutError
from modrob_build.safety_distance import enforce_safety_distance, min_pair_distance


def xy_dist(a, b):
    return math.hypot(a[0] - b[0], a[1] - b[1])


def test_pair_moved_along_the_line_to_exactly_dmin():
    bases, msgs = enforce_safety_distance([(1.0, 1.0, 0.5), (1.3, 1.4, 0.7)], 1.0)
    assert bases[0] == (1.0, 1.0, 0.5)
    # base0 + dmin/dp (base1 - base0): dp = 0.5, direction (0.6, 0.8)
    assert bases[1][0] == pytest.approx(1.6) and bases[1][1] == pytest.approx(1.8)
    assert bases[1][2] == 0.7   # z kept
    assert len(msgs) == 1 and "modrob1" in msgs[0] and "0.500 m" in msgs[0]


def test_far_pair_untouched_and_zero_is_off():
    far = [(0.0, 0.0, 0.0), (2.0, 0.0, 0.0)]
    assert enforce_safety_distance(far, 1.0) == (far, [])
    close = [(0.0, 0.0, 0.0), (0.1, 0.0, 0.0), (0.1, 0.0, 0.0)]
    assert enforce_safety_distance(close, 0.0) == (close, [])


def test_chain_of_three():
    bases, msgs = enforce_safety_distance([(0, 0, 0), (0.5, 0, 0), (1.0, 0, 0)], 1.0)
    assert bases[1][:2] == pytest.approx((1.0, 0.0))
    assert min_pair_distance(bases) >= 1.0 - 1e-9
    assert len(msgs) >= 2


def test_coincident_bases_deterministic():
    a, msgs_a = enforce_safety_distance([(0.5, 0.5, 1.0)] * 3, 0.8)
    b, _ = enforce_safety_distance([(0.5, 0.5, 1.0)] * 3, 0.8)
    assert a == b
    assert a[1][:2] == pytest.approx((1.3, 0.5))
    assert min_pair_distance(a) >= 0.8 - 1e-9
    assert any("coincident" in m for m in msgs_a)


def test_random_layouts_end_conflict_free():
    rng = random.Random(7)
    for _ in range(50):
        n = rng.randint(2, 6)
        bases = [(rng.uniform(-0.5, 0.5), rng.uniform(-0.5, 0.5), 1.02) for _ in range(n)]
        d_min = rng.uniform(0.2, 1.0)
        out, _ = enforce_safety_distance(bases, d_min)
        for p, q in itertools.combinations(out, 2):
            assert xy_dist(p, q) >= d_min - 1e-9
        assert out[0] == bases[0]


@pytest.mark.parametrize("bad", [-0.1, float("nan"), float("inf")])
def test_bad_distance_refused(bad):
    with pytest.raises(LayoutError, match="safety_distance"):
        enforce_safety_distance([(0, 0, 0), (0, 0, 0)], bad)
