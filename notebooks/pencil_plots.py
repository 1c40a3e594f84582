"""Plots of the pencil renderer's experiments (paper section 5, Figs. 8-10, and the rho sweep).

Reads what `pencil figures` / `pencil sweep` write into a directory (CSV, JSON, OpenEXR) and
writes PNG plots beside them. Used by notebooks/figures.ipynb and run by `pencil figures` as
    /usr/bin/python3 notebooks/pencil_plots.py DIR
Needs only numpy and matplotlib (Debian's python3-numpy, python3-matplotlib): the OpenEXR files
are read by the small reader below (scanline files, uncompressed, ZIPS or ZIP, as io/ writes).
"""
import csv
import json
import os
import struct
import sys
import zlib

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402

PAPER = {"speedup_9": 7.6, "ratio_49": 0.1, "within": 0.998, "max_error": 0.66}


# ---- OpenEXR (the subset io/ writes: one scanline part of 32-bit float channels) --------------

def _cstr(buf, i):
    j = buf.index(b"\0", i)
    return buf[i:j].decode(), j + 1


def read_exr(path):
    """Return {channel name: float32 array (height, width)} and the string attributes."""
    with open(path, "rb") as f:
        buf = f.read()
    if buf[:4] != b"\x76\x2f\x31\x01":
        raise ValueError(f"{path}: not an OpenEXR file")
    i, attrs, channels = 8, {}, []
    while buf[i] != 0:
        name, i = _cstr(buf, i)
        typ, i = _cstr(buf, i)
        (size,) = struct.unpack_from("<i", buf, i)
        i += 4
        val = buf[i:i + size]
        i += size
        if name == "channels":
            j = 0
            while val[j] != 0:
                cname, j = _cstr(val, j)
                ptype = struct.unpack_from("<i", val, j)[0]
                j += 16
                channels.append((cname, ptype))
        elif name == "compression":
            attrs["compression"] = val[0]
        elif name == "dataWindow":
            attrs["dataWindow"] = struct.unpack("<4i", val)
        elif typ == "string":
            attrs[name] = val.decode(errors="replace")
    i += 1
    x0, y0, x1, y1 = attrs["dataWindow"]
    w, h = x1 - x0 + 1, y1 - y0 + 1
    comp = attrs.get("compression", 0)
    lines = {0: 1, 2: 1, 3: 16}.get(comp)
    if lines is None:
        raise ValueError(f"{path}: compression {comp} not supported by this reader")
    if any(p != 2 for _, p in channels):
        raise ValueError(f"{path}: only float channels are supported")
    nchunk = (h + lines - 1) // lines
    offsets = struct.unpack_from(f"<{nchunk}Q", buf, i)
    out = {c: np.empty((h, w), np.float32) for c, _ in channels}
    for off in offsets:
        y, size = struct.unpack_from("<ii", buf, off)
        data = buf[off + 8:off + 8 + size]
        n = min(lines, y1 - y + 1)
        raw = 4 * w * len(channels) * n
        if comp != 0 and size < raw:
            d = np.frombuffer(zlib.decompress(data), np.uint8).astype(np.int64)
            d[1:] -= 128  # undo the predictor: t[i] = t[i-1] + d[i] - 128 (mod 256)
            t = (np.cumsum(d) & 0xFF).astype(np.uint8)
            half = (len(t) + 1) // 2  # then the two halves hold the even and the odd bytes
            inter = np.empty(len(t), np.uint8)
            inter[0::2] = t[:half]
            inter[1::2] = t[half:]
            data = inter.tobytes()
        rows = np.frombuffer(data, "<f4").reshape(n, len(channels), w)
        for k, (c, _) in enumerate(channels):
            out[c][y - y0:y - y0 + n] = rows[:, k, :]
    return out, attrs


# ---- CSV / JSON -----------------------------------------------------------------------------

def read_csv(path):
    """A CSV of pencil's as columns; the provenance lines at its top ('# ...') are skipped."""
    with open(path, newline="") as f:
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    return {k: np.array([_num(r[k]) for r in rows]) for k in rows[0]} if rows else {}


def provenance(path):
    """Where a pencil output came from: a CSV's provenance lines ('# version: ...', '# commit:
    ...', '# date: ...', '# command_line: ...') or an EXR's pencil:* header attributes, as a dict
    of those four keys (empty when it has none)."""
    keys = ("version", "commit", "date", "command_line")
    if path.endswith(".exr"):
        _, attrs = read_exr(path)
        return {k: attrs["pencil:" + k] for k in keys if "pencil:" + k in attrs}
    out = {}
    with open(path, encoding="utf-8", errors="replace") as f:
        for line in f:
            if not line.startswith("# "):
                break
            k, _, v = line[2:].rstrip("\n").partition(": ")
            if k in keys:
                out[k] = v
    return out


def save(fig, path, source, dpi=100):
    """fig as PNG at path, its text chunks saying what drew it and from which output (source):
    Software, Source and that output's pencil:version, pencil:commit, pencil:date and
    pencil:command_line, as pencil's own PNGs carry them."""
    meta = {"Software": f"pencil notebooks/pencil_plots.py (matplotlib {matplotlib.__version__})",
            "Source": os.path.basename(source)}
    meta.update({"pencil:" + k: v for k, v in provenance(source).items()})
    fig.savefig(path, dpi=dpi, metadata=meta)


def _num(s):
    try:
        return float(s)
    except ValueError:
        return s


# ---- plots ----------------------------------------------------------------------------------

def plot_fig9(d, show=False):
    t = read_csv(os.path.join(d, "fig9.csv"))
    fig, ax = plt.subplots(1, 2, figsize=(10, 4))
    ax[0].plot(t["spp"], t["ratio"], "o-", label="this run (pencil / exact CPU time)")
    ax[0].plot([9], [1 / PAPER["speedup_9"]], "s", color="C3", label="paper: 7.6x faster at 9 spp")
    ax[0].plot([49], [PAPER["ratio_49"]], "v", color="C3", label="paper: below 1/10 at 49 spp")
    ax[0].axhline(1.0, color="grey", lw=0.8)
    ax[0].set_xlabel("samples per pixel")
    ax[0].set_ylabel("time ratio pencil / exact")
    ax[0].set_yscale("log")
    if max(t["spp"]) > 49:  # extended past the paper's grids (--fig9-spp)
        ax[0].axhline(PAPER["ratio_49"], color="C3", lw=0.6, ls=":")
        for a in ax:
            a.set_xscale("log")
    ax[0].set_title("Fig. 9: CPU time ratio, rho = 1/2")
    ax[0].legend(fontsize=8)
    ax[1].plot(t["spp"], t["exact_s"], "o-", label="exact")
    ax[1].plot(t["spp"], t["pencil_s"], "o-", label="pencil")
    ax[1].set_xlabel("samples per pixel")
    ax[1].set_ylabel("CPU seconds (median)")
    ax[1].legend()
    fig.tight_layout()
    save(fig, os.path.join(d, "fig9.png"), os.path.join(d, "fig9.csv"))
    return fig if show else plt.close(fig)


def plot_fig10(d, show=False):
    h = read_csv(os.path.join(d, "fig10_hist.csv"))
    s = json.load(open(os.path.join(d, "summary.json")))["fig10"]
    lo, cnt = h["error_lo"], h["samples"]
    fig, ax = plt.subplots(figsize=(6, 4))
    nz = cnt[:-1] > 0
    ax.bar(lo[:-1][nz], cnt[:-1][nz], width=lo[1] - lo[0], align="edge")
    ax.axvline(s["rho"], color="C3", label=f"rho = {s['rho']}")
    ax.axvline(PAPER["max_error"], color="C1", ls="--", label="paper's largest error 0.66")
    ax.set_yscale("log")
    ax.set_xlim(0, max(1.0, 1.2 * min(s["max_error"], lo[-1])))
    ax.set_xlabel("error (pixel intervals on the checkerboard)")
    ax.set_ylabel("samples")
    ax.set_title(f"Fig. 10: {100 * s['fraction_within']:.3f}% within rho "
                 f"(paper 99.8%), max {s['max_error']:.3f}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    save(fig, os.path.join(d, "fig10_hist.png"), os.path.join(d, "fig10_hist.csv"))
    return fig if show else plt.close(fig)


def plot_images(d, show=False):
    p, _ = read_exr(os.path.join(d, "fig8.exr"))
    x, _ = read_exr(os.path.join(d, "fig8_exact.exr"))
    rgb = lambda c: np.clip(np.stack([c["R"], c["G"], c["B"]], -1), 0, 1) ** (1 / 2.2)
    diff = np.abs(np.stack([p[k] - x[k] for k in "RGB"], -1)).max(-1)
    fig, ax = plt.subplots(1, 4, figsize=(16, 4.4))
    ax[0].imshow(rgb(p))
    ax[0].set_title("Fig. 8: pencil tracing, 9 spp")
    ax[1].imshow(rgb(x))
    ax[1].set_title("exact tracing")
    im = ax[2].imshow(diff, cmap="magma", vmin=0, vmax=max(0.05, float(np.percentile(diff, 99.9))))
    ax[2].set_title("|pencil - exact| (RGB max)")
    plt.colorbar(im, ax=ax[2], fraction=0.046)
    err = p["pencil.error"].copy()
    im = ax[3].imshow(np.where(np.isfinite(err), err, np.nan), cmap="viridis", vmin=0, vmax=0.5)
    ax[3].set_title("Fig. 10: largest error per pixel")
    plt.colorbar(im, ax=ax[3], fraction=0.046)
    for a in ax:
        a.set_xticks([])
        a.set_yticks([])
    fig.tight_layout()
    save(fig, os.path.join(d, "fig8_compare.png"), os.path.join(d, "fig8.exr"), dpi=90)
    return fig if show else plt.close(fig)


def plot_sweep(d, show=False):
    t = read_csv(os.path.join(d, "sweep.csv"))
    fig, ax = plt.subplots(1, 3, figsize=(15, 4))
    for i, v in enumerate(dict.fromkeys(t["variant"])):
        m, col = t["variant"] == v, f"C{i}"
        ax[0].plot(t["rho"][m], t["ratio"][m], "o-", color=col, label=v)
        ax[1].plot(t["rho"][m], 100 * t["fraction_within"][m], "o-", color=col, label=v)
        ax[2].plot(t["rho"][m], t["p99"][m] / t["rho"][m], "o-", color=col, label=f"{v}: p99 / rho")
        ax[2].plot(t["rho"][m], np.minimum(t["max_error"][m], 1e3) / t["rho"][m], "x--", color=col,
                   label=f"{v}: max / rho")
    ax[0].set_ylabel("time ratio pencil / exact")
    ax[1].set_ylabel("% of samples within rho")
    ax[2].set_ylabel("error / rho")
    ax[2].axhline(1.0, color="grey", lw=0.8)
    ax[2].set_yscale("log")
    for a in ax:
        a.set_xscale("log")
        a.set_xlabel("rho")
        a.legend(fontsize=7)
    ax[0].set_title(f"what accuracy costs ({int(t['spp'][0])} spp)")
    fig.tight_layout()
    save(fig, os.path.join(d, "sweep.png"), os.path.join(d, "sweep.csv"))
    return fig if show else plt.close(fig)


def plot_curves(path, show=False):
    """Issue 26's curves (scripts/curves' CSV): the ratio pencil / exact against each curve's x,
    default and certified mode, by CPU time and, where counted, by instructions; saved beside
    the CSV as curves.png."""
    t = read_csv(path)
    with open(path, newline="") as f:  # the instruction columns are empty where not counted
        rows = list(csv.DictReader(line for line in f if not line.startswith("#")))
    names = [c for c in ("spp", "size", "spheres", "rho") if c in set(t["curve"])]
    xlabel = {"spp": "samples per pixel", "size": "image side (pixels)",
              "spheres": "spheres over the board", "rho": "rho (pixel intervals)"}
    fig, ax = plt.subplots(1, len(names), figsize=(4.2 * len(names), 3.8), squeeze=False)
    for a, c in zip(ax[0], names):
        for i, mode in enumerate(("default", "certified")):
            m = (t["curve"] == c) & (t["mode"] == mode)
            if m.any():
                a.plot(t["x"][m], t["ratio"][m], "o-", color=f"C{i}", label=f"{mode}, CPU time")
        ins = [(float(r["x"]), float(r["instruction_ratio"])) for r in rows
               if r["curve"] == c and r["instruction_ratio"] != ""]
        if ins:
            a.plot(*zip(*ins), "s--", color="C2", label="default, instructions")
        a.axhline(PAPER["ratio_49"], color="C3", lw=0.6, ls=":")
        a.axhline(1.0, color="grey", lw=0.8)
        a.set_xscale("log")
        a.set_yscale("log")
        a.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        a.set_xlabel(xlabel[c])
        a.set_ylabel("pencil / exact")
        a.set_title(c)
        a.legend(fontsize=7)
    fig.tight_layout()
    save(fig, os.path.join(os.path.dirname(path), "curves.png"), path)
    return fig if show else plt.close(fig)


def plot_all(d):
    done = []
    for name, fn, need in [("fig9", plot_fig9, "fig9.csv"), ("fig10", plot_fig10, "fig10_hist.csv"),
                           ("fig8", plot_images, "fig8.exr"), ("sweep", plot_sweep, "sweep.csv")]:
        if os.path.exists(os.path.join(d, need)):
            fn(d)
            done.append(name)
    return done


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: pencil_plots.py DIR")
    print("plots:", ", ".join(plot_all(sys.argv[1])) or "nothing to plot")
