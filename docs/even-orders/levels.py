"""Even drum orders (2, 4, 6) against odd ones (1, 3, 5) per speed range, from washdyn runs'
sensor files (<run>/sensors.parquet), by an order analysis of its own (numpy, independent of
washdyn's): the drum angle from the integrated speed, each channel resampled to 64 points per
revolution, Hann-windowed blocks of 8 revolutions, amplitude-corrected DFT at orders 1-6.

Usage: python3 levels.py RUN [RUN ...]   (the first run is the one the others are set against)
Prints per run, channel group (tub, cabinet) and speed range the largest level of each order
over the group's channels (dB re 1 m/s^2), the even-over-odd margin, and each even order's
change from the first run. docs/even-orders.md gives the commands that made the runs."""
import sys
import numpy as np
import pyarrow.parquet as pq

RANGES = [(100, 400), (400, 800), (800, 1401)]
PER_REV, REVS, ORDERS = 64, 8, range(1, 7)


def blocks(t):
    """Per channel: a list of (block's mean rpm, amplitudes of ORDERS)."""
    time, rpm = t["time_s"], t["drum_rpm"]
    phi = np.concatenate(([0.0], np.cumsum(0.5 * (rpm[1:] + rpm[:-1]) * np.diff(time)) / 60.0))
    grid = np.arange(0.0, phi[-1], 1.0 / PER_REV)
    rpm_g = np.interp(grid, phi, rpm)
    n = PER_REV * REVS
    w = np.hanning(n)
    out = {}
    for c, x in t.items():
        if c in ("time_s", "drum_rpm") or not c[-3:] in ("_ax", "_ay", "_az"):
            continue
        xg = np.interp(grid, phi, x)
        rows = []
        for s in range(0, len(grid) - n, n // 2):
            seg = xg[s:s + n] * w
            spec = np.fft.rfft(seg) * 2.0 / w.sum()
            rows.append((rpm_g[s:s + n].mean(), [abs(spec[k * REVS]) for k in ORDERS]))
        out[c] = rows
    return out


def levels(run, prefix):
    t = pq.read_table(f"{run}/sensors.parquet").to_pandas()
    cols = {c: t[c].to_numpy() for c in t.columns if c in ("time_s", "drum_rpm") or c.startswith(prefix)}
    b = blocks(cols)
    out = {}
    for lo, hi in RANGES:
        amp = {k: 1e-30 for k in ORDERS}
        for rows in b.values():
            for r, a in rows:
                if lo <= r < hi:
                    for k, v in zip(ORDERS, a):
                        amp[k] = max(amp[k], v)
        out[(lo, hi)] = {k: 20 * np.log10(v) for k, v in amp.items()}
    return out


def main():
    runs = sys.argv[1:]
    for prefix in ("tub", "cabinet"):
        base = None
        for run in runs:
            lv = levels(run, prefix)
            if all(v < -500 for row in lv.values() for v in row.values()):
                continue  # a rigid, fixed cabinet reads zero
            print(f"\n{run} [{prefix}, largest over channels, dB re 1 m/s^2]")
            for rg, row in lv.items():
                even = max(row[2], row[4], row[6])
                odd = max(row[1], row[3], row[5])
                line = " ".join(f"o{k} {row[k]:6.1f}" for k in ORDERS)
                rel = ""
                if base is not None:
                    rel = "  vs first: " + " ".join(f"o{k} {row[k] - base[rg][k]:+6.1f}" for k in (2, 4, 6))
                print(f"  {rg[0]:4.0f}-{min(rg[1], 1400):4.0f} rpm: {line}  even-odd {even - odd:6.1f} dB{rel}")
            if base is None:
                base = lv


if __name__ == "__main__":
    main()
