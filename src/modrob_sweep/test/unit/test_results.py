"""The trial table, the summary and the plots (pure)."""
import math
import os

import pytest

from modrob_sweep import results


@pytest.mark.parametrize("k, n, lo, hi", [
    (19, 20, 0.7639, 0.9911),      # textbook Wilson 95 % values
    (0, 10, 0.0, 0.2775),
    (10, 10, 0.7225, 1.0),
    (5, 10, 0.2366, 0.7634),
])
def test_wilson_interval(k, n, lo, hi):
    a, b = results.wilson(k, n)
    assert a == pytest.approx(lo, abs=5e-4) and b == pytest.approx(hi, abs=5e-4)


def test_wilson_interval_contains_the_rate():
    # 0/3 and 10/10 once had ends 1e-17 beyond the rate: the plot's error bars were refused
    for n in range(1, 120):
        for k in range(n + 1):
            lo, hi = results.wilson(k, n)
            assert 0.0 <= lo <= k / float(n) <= hi <= 1.0, (k, n, lo, hi)


def test_wilson_of_nothing_is_everything():
    assert results.wilson(0, 0) == (0.0, 1.0)


def rows():
    out = []
    for k in range(8):
        mu = [0.1, 0.2][k % 2]
        ok = mu == 0.2 or k == 0
        out.append({"trial": 7 - k, "host": "h%d" % (k % 2), "outcome": "success" if ok else "failure",
                    "wall_s": 1.0 + k, "sim_s": 0.5, "mu": mu, "distance": 1.0 / mu + k, "seed": 7 - k,
                    "attempts": 1, "detail": "exit 0", "out": "/x"})
    out.append({"trial": 8, "host": "h0", "outcome": "timeout", "wall_s": 30.0, "sim_s": math.nan, "mu": 0.1,
                "distance": math.nan, "seed": 8, "attempts": 1, "detail": "no end after 30 s: stopped",
                "out": "/x"})
    return out


def test_table_columns_and_files(tmp_path):
    paths = results.write_all(rows(), str(tmp_path), "t", ["mu"], ["mu"], ["distance"], {"run": "test"})
    import pandas as pd
    df = pd.read_csv(tmp_path / "trials.csv")
    assert list(df.columns) == ["trial", "host", "outcome", "wall_s", "sim_s", "mu", "distance", "seed",
                                "attempts",
                                "detail", "out"]
    assert list(df["trial"]) == list(range(9))
    pq = pd.read_parquet(tmp_path / "trials.parquet")
    assert list(pq.columns) == list(df.columns) and len(pq) == 9
    names = sorted(os.path.basename(p) for p in paths)
    assert names == sorted(["trials.csv", "trials.parquet", "summary.md", "success_vs_mu.png",
                            "distance_vs_mu.png"])
    for p in paths:
        assert os.path.getsize(p) > 0
    with open(tmp_path / "success_vs_mu.png", "rb") as fh:
        assert fh.read(8) == b"\x89PNG\r\n\x1a\n"


def test_summary_numbers():
    df = results.table(rows(), ["mu"], ["distance"])
    text = results.summary(df, "t", ["mu"], ["distance"])
    assert "**Success: 5/9 = 56 % (95 % CI 27-81 %)**" in text
    assert "Outcomes: success 5, failure 3, timeout 1." in text
    # per value of mu: 0.1 has trials 7, 5, 3, 1 (k = 0 succeeded) and the timeout; 0.2 all succeed
    assert "| 0.1 | 5 | 1/5 = 20 % (95 % CI 4-62 %) |" in text
    assert "| 0.2 | 4 | 4/4 = 100 % (95 % CI 51-100 %) |" in text
    assert "| 8 | h0 | timeout | no end after 30 s: stopped |" in text


def test_many_values_are_binned():
    rs = [{"trial": k, "host": "h", "outcome": "success", "wall_s": 1.0, "sim_s": 1.0, "x": k / 10.0,
           "seed": k,
           "attempts": 1, "detail": "", "out": ""} for k in range(40)]
    df = results.table(rs, ["x"], [])
    groups = results.levels(df, "x")
    assert len(groups) == results.MAX_LEVELS
    assert sum(int(m.sum()) for _, m in groups) == 40
