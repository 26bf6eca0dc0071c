"""The seed paper's Figure 14: a channel's speed plot (its signal against the drum speed) and its
asymmetry about zero, from washdyn runs' sensor files (<run>/sensors.parquet), independent of
washdyn's own analysis (numpy).

Per revolution of the drum: the signal's largest value (upper envelope) and smallest (lower
envelope). A signal symmetric about zero has max = -min; the asymmetry (max + min) / (max - min)
is 0 for it, +1 for a signal that never goes below zero. Even harmonics make it nonzero; a
restoring force stiffer one way than the other makes the softer side's peaks larger.

Usage: python3 speed_plot.py CHANNEL OUT.png RUN [RUN ...]
Prints per run and speed range the median asymmetry and the envelopes at the range's largest
peak; writes the envelopes over speed of every run to OUT.png (matplotlib, if present)."""
import sys
import numpy as np
import pyarrow.parquet as pq

RANGES = [(100, 400), (400, 800), (800, 1401)]


def envelopes(run, channel):
    """Per drum revolution: (mean rpm, max, min) of the channel."""
    t = pq.read_table(f"{run}/sensors.parquet", columns=["time_s", "drum_rpm", channel])
    time = t["time_s"].to_numpy()
    rpm = t["drum_rpm"].to_numpy()
    x = t[channel].to_numpy()
    revs = np.concatenate(([0.0], np.cumsum(0.5 * (rpm[1:] + rpm[:-1]) * np.diff(time)) / 60.0))
    k = np.floor(revs).astype(int)
    edges = np.flatnonzero(np.diff(k)) + 1
    rows = []
    for a, b in zip(edges[:-1], edges[1:]):
        seg = x[a:b]
        if len(seg) > 8:
            rows.append((rpm[a:b].mean(), seg.max(), seg.min()))
    return np.array(rows)


def main():
    channel, png, runs = sys.argv[1], sys.argv[2], sys.argv[3:]
    curves = {}
    for run in runs:
        e = envelopes(run, channel)
        curves[run] = e
        print(f"\n{run} [{channel}, per revolution; asymmetry (max + min) / (max - min)]")
        for lo, hi in RANGES:
            sel = e[(e[:, 0] >= lo) & (e[:, 0] < hi)]
            if len(sel) == 0:
                continue
            asym = (sel[:, 1] + sel[:, 2]) / (sel[:, 1] - sel[:, 2])
            top = np.argmax(sel[:, 1] - sel[:, 2])
            print(
                f"  {lo:4.0f}-{min(hi, 1400):4.0f} rpm: median {np.median(asym):+.3f}, "
                f"at the largest swing ({sel[top, 0]:.0f} rpm) max {sel[top, 1]:+.3f} "
                f"min {sel[top, 2]:+.3f} m/s^2, asymmetry {asym[top]:+.3f}"
            )
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("matplotlib missing: no plot")
        return
    fig, ax = plt.subplots(len(runs), 1, figsize=(8, 2.6 * len(runs)), sharex=True, squeeze=False)
    for a, (run, e) in zip(ax[:, 0], curves.items()):
        a.fill_between(e[:, 0], e[:, 2], e[:, 1], color="tab:blue", lw=0)
        a.axhline(0.0, color="k", lw=0.5)
        a.set_ylabel(f"{channel} [m/s²]")
        a.set_title(run.rstrip("/").split("/")[-1], fontsize=9)
    ax[-1, 0].set_xlabel("drum speed [rpm]")
    fig.tight_layout()
    fig.savefig(png, dpi=110)


if __name__ == "__main__":
    main()
