#!/usr/bin/env python3
"""Summarises a placement-seed sweep (synth/seeds_ecp5.sh) into a markdown results file.

    seeds_report.py [--script S] [--constraint C] OUT.md TITLE COMMAND TOOLS SYNTH_TIME SEED=REPORT.json=PNR_TIME...

One row per seed: the Fmax of the clock, the critical path in words (from pnr_report.py),
the place-and-route time; then the minimum, median and maximum Fmax. `--script` names
the script that wrote the file (default synth/seeds_ecp5.sh), `--constraint` where the
clock constraint comes from (default synth/ecp5/pixelproc.lpf).
"""
import argparse
import json
import os
import statistics
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pnr_report import path_words  # noqa: E402


def main():
    ap = argparse.ArgumentParser(description="Summarise a placement-seed sweep.")
    ap.add_argument("--script", default="synth/seeds_ecp5.sh")
    ap.add_argument("--constraint", default="synth/ecp5/pixelproc.lpf")
    ap.add_argument("out")
    ap.add_argument("title")
    ap.add_argument("command")
    ap.add_argument("tools")
    ap.add_argument("synth_time")
    ap.add_argument("runs", nargs="+", metavar="SEED=REPORT.json=PNR_TIME")
    a = ap.parse_args()
    out, title, command, tools, synth_time = a.out, a.title, a.command, a.tools, a.synth_time
    rows = []
    for arg in a.runs:
        seed, path, pnr_time = arg.split("=", 2)
        rep = json.load(open(path))
        fmax = rep.get("fmax", {})
        if not fmax:
            sys.exit(f"{path}: no Fmax in the nextpnr report")
        clk, f = next(iter(fmax.items()))
        cps = rep.get("critical_paths", [])
        words = path_words(cps[0]) if cps else "(no path reported)"
        # The nets list makes the table unreadable: keep the words up to it.
        words = words.split(" Nets on the way:")[0]
        rows.append((int(seed), clk, f.get("achieved", 0.0), f.get("constraint", 0.0), words, pnr_time))
    fs = [r[2] for r in rows]
    lines = [
        f"# {title}",
        "",
        f"Written by `{a.script}` (see `docs/fpga.md`); do not edit by hand.",
        "",
        "| item | value |",
        "|---|---|",
        "| device | LFE5U-85F-6 CABGA381, out of context |",
        f"| constraint | {a.constraint}: {rows[0][3]:.2f} MHz on `{rows[0][1]}` |",
        f"| command | {command} |",
        f"| tools | {tools} |",
        f"| synthesis time (once) | {synth_time} |",
        "",
        f"**Fmax over {len(fs)} seed{'s' if len(fs) != 1 else ''}: minimum {min(fs):.2f}, median {statistics.median(fs):.2f}, "
        f"maximum {max(fs):.2f} MHz** (one netlist; only the placement seed differs).",
        "",
        "| seed | Fmax | met | critical path | place and route time |",
        "|---:|---:|---|---|---|",
    ]
    for seed, _clk, ach, con, words, t in sorted(rows):
        lines.append(f"| {seed} | {ach:.2f} MHz | {'yes' if ach >= con else 'no'} | {words} | {t} |")
    open(out, "w").write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main()
