"""A sweep's results under out/sweeps/<name>/: trials.csv and trials.parquet (one row per trial:
trial, host, outcome, wall_s, sim_s, the parameters, the metrics, then seed, attempts, detail, out),
summary.md (success rate with a 95 % Wilson interval, median/min/max per metric, the same per value
of each varying parameter) and PNG plots (success vs parameter, metric vs parameter)."""
import math
import os

import numpy as np

FIRST = ("trial", "host", "outcome", "wall_s", "sim_s")
LAST = ("seed", "attempts", "detail", "out")
MAX_LEVELS = 8        # a parameter with more distinct values is binned into this many quantile bins


def wilson(k, n, z=1.959963984540054):
    """Wilson score interval (lo, hi) of a success rate k/n, 95 % by default; (0, 1) for n = 0."""
    if n <= 0:
        return 0.0, 1.0
    p = k / float(n)
    den = 1.0 + z * z / n
    centre = (p + z * z / (2.0 * n)) / den
    half = z * math.sqrt(p * (1.0 - p) / n + z * z / (4.0 * n * n)) / den
    # the interval contains p; rounding can put its end a hair inside (0/n, n/n): keep p in it
    return min(p, max(0.0, centre - half)), max(p, min(1.0, centre + half))


def table(rows, parameters, metrics):
    """The trial table (pandas DataFrame) with the agreed column order, sorted by trial."""
    import pandas as pd
    cols = list(FIRST) + [p for p in parameters if p not in FIRST and p not in LAST] + \
        [m for m in metrics if m not in FIRST and m not in parameters and m not in LAST] + list(LAST)
    df = pd.DataFrame(rows)
    for c in cols:
        if c not in df.columns:
            df[c] = np.nan
    df = df[cols + [c for c in df.columns if c not in cols]]
    return df.sort_values("trial").reset_index(drop=True)


def write_table(df, folder):
    os.makedirs(folder, exist_ok=True)
    csv = os.path.join(folder, "trials.csv")
    df.to_csv(csv, index=False)
    parquet = os.path.join(folder, "trials.parquet")
    # mixed-type columns (a metric that is a string in one trial) go to Parquet as text
    out = df.copy()
    for c in out.columns:
        if out[c].dtype == object:
            out[c] = out[c].map(_text)
    out.to_parquet(parquet, index=False)
    return csv, parquet


def _text(v):
    """A cell of a mixed-type column as Parquet text (missing stays missing)."""
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return None
    return str(v)


def _fmt(v):
    if isinstance(v, float):
        if math.isnan(v):
            return "-"
        return "%.4g" % v
    return str(v)


def _numeric(series):
    import pandas as pd
    return pd.to_numeric(series, errors="coerce")


def _median(series):
    """Median of the values present; nan (no warning) when there is none."""
    v = series.dropna()
    return float(v.median()) if len(v) else math.nan


def levels(df, name):
    """The groups of a parameter for the summary and plots: its values, or quantile bins when a
    numeric parameter has more than MAX_LEVELS distinct values. Returns [(label, mask)]."""
    import pandas as pd
    col = df[name]
    values = col.dropna().unique()
    num = _numeric(col)
    if len(values) > MAX_LEVELS and num.notna().all():
        bins = pd.qcut(num, MAX_LEVELS, duplicates="drop")
        return [("%s" % iv, bins == iv) for iv in bins.cat.categories]
    try:
        values = sorted(values)
    except TypeError:
        values = list(values)
    return [(_fmt(v), col == v) for v in values]


def rate_text(k, n):
    lo, hi = wilson(k, n)
    return "%d/%d = %.0f %% (95 %% CI %.0f-%.0f %%)" % (k, n, 100.0 * k / n if n else 0, 100 * lo, 100 * hi)


def summary(df, name, varying, metrics, meta=None):
    """summary.md as text."""
    n = len(df)
    ok = int((df["outcome"] == "success").sum())
    lines = ["# Sweep %s" % name, ""]
    for k, v in (meta or {}).items():
        lines.append("- %s: %s" % (k, v))
    if meta:
        lines.append("")
    lines += ["**Success: %s** (Wilson score interval)." % rate_text(ok, n), ""]
    counts = df["outcome"].value_counts()
    lines.append("Outcomes: " + ", ".join("%s %d" % (o, counts[o]) for o in counts.index) + ".")
    hosts = df["host"].value_counts()
    lines.append("Hosts: " + ", ".join("%s (%d trials)" % (h, hosts[h]) for h in hosts.index) + ".")
    wall = _numeric(df["wall_s"])
    sim = _numeric(df["sim_s"])
    lines.append("Wall time per trial: median %s s (min %s, max %s); simulated time per trial: median %s s."
                 % (_fmt(_median(wall)), _fmt(wall.min()), _fmt(wall.max()), _fmt(_median(sim))))
    lines.append("")
    cols = ["wall_s", "sim_s"] + [m for m in metrics if m not in ("wall_s", "sim_s")]
    lines += ["| metric | trials with a value | median | min | max |", "|---|---|---|---|---|"]
    for m in cols:
        v = _numeric(df[m]).dropna()
        cells = [_fmt(f()) if len(v) else "-" for f in (v.median, v.min, v.max)]
        lines.append("| %s | %d | %s | %s | %s |" % tuple([m, len(v)] + cells))
    for p in varying:
        lines += ["", "## By %s" % p, "",
                  "| %s | trials | success (95 %% CI) | %s |" % (p,
                                                                 " | ".join("median %s" % m for m in cols)),
                  "|---|---|---|" + "---|" * len(cols)]
        for label, mask in levels(df, p):
            sub = df[mask]
            k = int((sub["outcome"] == "success").sum())
            meds = [_fmt(_median(_numeric(sub[m]))) for m in cols]
            lines.append("| %s | %d | %s | %s |" % (label, len(sub), rate_text(k, len(sub)),
                                                    " | ".join(meds)))
    bad = df[df["outcome"] != "success"]
    if len(bad):
        lines += ["", "## Trials that did not succeed", "", "| trial | host | outcome | detail |",
                  "|---|---|---|---|"]
        for _, r in bad.iterrows():
            detail = str(r["detail"]).replace("|", "/")[:160]
            lines.append("| %d | %s | %s | %s |" % (r["trial"], r["host"], r["outcome"], detail))
    return "\n".join(lines) + "\n"


def plots(df, folder, varying, metrics):
    """PNG plots: success rate vs each varying parameter (Wilson bars), each metric vs each varying
    parameter (points coloured by outcome); with no varying parameter, each metric per trial."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    written = []
    colours = {"success": "tab:green", "failure": "tab:red", "crashed": "black", "timeout": "tab:orange"}
    for p in varying:
        groups = levels(df, p)
        fig, ax = plt.subplots(figsize=(6, 4))
        x = np.arange(len(groups))
        rates, err = [], [[], []]
        for _, mask in groups:
            sub = df[mask]
            k, n = int((sub["outcome"] == "success").sum()), len(sub)
            lo, hi = wilson(k, n)
            r = k / float(n) if n else 0.0
            rates.append(r)
            err[0].append(r - lo)
            err[1].append(hi - r)
        ax.errorbar(x, rates, yerr=err, fmt="o", capsize=4)
        ax.set_xticks(x)
        ax.set_xticklabels([g[0] for g in groups], rotation=30, ha="right")
        ax.set_ylim(-0.05, 1.05)
        ax.set_xlabel(p)
        ax.set_ylabel("success rate (95 % Wilson interval)")
        ax.set_title("success vs %s" % p)
        fig.tight_layout()
        path = os.path.join(folder, "success_vs_%s.png" % _safe(p))
        fig.savefig(path, dpi=90)
        plt.close(fig)
        written.append(path)
        xs = _numeric(df[p])
        for m in metrics:
            ys = _numeric(df[m])
            if ys.notna().sum() == 0:
                continue
            fig, ax = plt.subplots(figsize=(6, 4))
            if xs.notna().all():
                xv = xs
            else:
                labels = [g[0] for g in groups]
                xv = np.zeros(len(df))
                for i, (_, mask) in enumerate(groups):
                    xv[np.asarray(mask)] = i
                ax.set_xticks(range(len(labels)))
                ax.set_xticklabels(labels, rotation=30, ha="right")
            for outcome, colour in colours.items():
                sel = np.asarray(df["outcome"] == outcome)
                if sel.any():
                    ax.plot(np.asarray(xv)[sel], np.asarray(ys)[sel], "o", color=colour, label=outcome,
                            alpha=0.8)
            ax.set_xlabel(p)
            ax.set_ylabel(m)
            ax.set_title("%s vs %s" % (m, p))
            ax.legend(fontsize=8)
            fig.tight_layout()
            path = os.path.join(folder, "%s_vs_%s.png" % (_safe(m), _safe(p)))
            fig.savefig(path, dpi=90)
            plt.close(fig)
            written.append(path)
    if not varying:
        for m in metrics:
            ys = _numeric(df[m])
            if ys.notna().sum() == 0:
                continue
            fig, ax = plt.subplots(figsize=(6, 4))
            for outcome, colour in colours.items():
                sel = np.asarray(df["outcome"] == outcome)
                if sel.any():
                    ax.plot(np.asarray(df["trial"])[sel], np.asarray(ys)[sel], "o", color=colour,
                            label=outcome)
            ax.set_xlabel("trial")
            ax.set_ylabel(m)
            ax.set_title("%s per trial" % m)
            ax.legend(fontsize=8)
            fig.tight_layout()
            path = os.path.join(folder, "%s_per_trial.png" % _safe(m))
            fig.savefig(path, dpi=90)
            plt.close(fig)
            written.append(path)
    return written


def _safe(name):
    return "".join(c if c.isalnum() or c in "-_" else "_" for c in str(name))


def write_all(rows, folder, name, parameters, varying, metrics, meta=None):
    """Table, summary and plots; returns the paths written."""
    df = table(rows, parameters, metrics)
    csv, parquet = write_table(df, folder)
    path = os.path.join(folder, "summary.md")
    with open(path, "w") as fh:
        fh.write(summary(df, name, varying, metrics, meta))
    return [csv, parquet, path] + plots(df, folder, varying, metrics)
