"""A bulb is judged at rest over a window of simulated time, however often the scenario process gets
to sample its speed: beside a fast simulation on a loaded machine it samples less often than every
0.02 s, and a window counted in samples then needs more simulated time than the wait's timeout
(a run that placed its bulb within 2.4 mm failed with "still moving after 10 s")."""
import pytest

from modrob_motion.bulbs_and_slides.outcome import RestWindow


def first_rest(times, speed_at, window=0.5):
    w = RestWindow(window)
    for t in times:
        w.add(t, speed_at(t))
        if w.at_rest():
            return t
    return None


def still(_t):
    return 0.0


def test_every_20_ms_at_rest_once_the_window_is_covered():
    times = [round(0.02 * i, 6) for i in range(100)]
    assert first_rest(times, still) == 0.5          # 26 samples: 0 .. 0.5 s


def test_sparse_samples_still_judge_the_window_of_simulated_time():
    times = [0.45 * i for i in range(22)]             # a starved process: one sample per 0.45 s
    assert first_rest(times, still) == pytest.approx(0.9)   # three samples covering 0.5 s
    # the count of the old rule (25 samples of 0.02 s) is not reached within a 10 s wait
    assert len([t for t in times if t < 10.0]) < 25


def test_motion_in_the_window_is_not_rest():
    times = [round(0.02 * i, 6) for i in range(200)]

    def sliding_until_1s(t):
        return 0.05 if t < 1.0 else 0.001

    assert first_rest(times, sliding_until_1s) == pytest.approx(1.5)
    sparse = [0.3 * i for i in range(20)]
    # 1.2, 1.5, 1.8: the moving 0.9 s sample has left the window
    assert first_rest(sparse, sliding_until_1s) == pytest.approx(1.8)


def test_too_few_samples_are_not_rest():
    w = RestWindow(0.5)
    w.add(0.0, 0.0)
    w.add(2.0, 0.0)
    assert not w.at_rest()
    assert not w.at_rest()        # two samples: too few, however long they span
    w.add(2.1, 0.0)
    assert w.at_rest()            # 0.0 (the newest before the window, which it covers), 2.0, 2.1
    w.add(2.2, 0.02)
    assert not w.at_rest()
