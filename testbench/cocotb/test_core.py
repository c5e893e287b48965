"""cocotb testbench of the pixelproc core (docs/core.md): drives the AXI4-Stream command
input with the golden model's stimulus and sinks the pixel stream, both with seeded
random stalls, and compares every pixel with the golden image.

Inputs (environment, set by run.py):
  PIXELPROC_BEATS   beats.hex: one command beat per line, the kind (1 hex digit) then
                    tdata (64 hex digits), as `pixelproc testbench --frame --sim icarus`
                    writes it (testbench/src/frame/icarus.rs).
  PIXELPROC_EXPECT  expect.txt: first line `WIDTH HEIGHT N`, then one line per pixel in
                    stream order: `RRGGBB SOF LAST` (hex, 0/1, 0/1), from the golden
                    renderer's image.
  PIXELPROC_SEED, PIXELPROC_GAP_PCT, PIXELPROC_STALL_PCT: stall pattern (default 1, 20, 30).

Protocol checks besides the pixels: the core's m_axis beat stays valid with the same
tdata/tuser/tlast until taken (AXI4-Stream), s_axis_tready is 0 during reset, and
proto_err stays 0.
"""
import os
import random

import cocotb
from cocotb.clock import Clock
from cocotb.triggers import RisingEdge


def val(sig):
    """The integer value of a port (cocotb 1.x and 2.x)."""
    v = sig.value
    return v.to_unsigned() if hasattr(v, "to_unsigned") else int(v)


def load_beats(path):
    beats = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if line:
                beats.append((int(line[0], 16), int(line[1:], 16)))
    return beats


def load_expect(path):
    with open(path) as f:
        w, h, n = (int(x) for x in f.readline().split())
        px = []
        for line in f:
            parts = line.split()
            if parts:
                px.append((int(parts[0], 16), parts[1] == "1", parts[2] == "1"))
    assert len(px) == w * h, f"expect file: {len(px)} pixels for {w}x{h}"
    return w, h, n, px


async def drive_commands(dut, beats, rng, gap_pct, state):
    """Offers the beats in order; a beat once offered stays offered until taken."""
    i = 0
    offered = False
    while i < len(beats):
        if not offered:
            offered = rng.randrange(100) >= gap_pct
        dut.s_axis_tvalid.value = int(offered)
        kind, data = beats[i]
        dut.s_axis_tdata.value = data
        dut.s_axis_tuser.value = kind
        await RisingEdge(dut.clock)
        if offered and val(dut.s_axis_tready):
            i += 1
            offered = False
        elif offered:
            state["in_stall"] += 1
    dut.s_axis_tvalid.value = 0
    state["beats_done"] = True


def check_pixel(k, beat, w, expect):
    rgb, user, last = beat
    g_rgb, g_sof, g_last = expect[k]
    x, y = k % w, k // w
    assert rgb == g_rgb, f"pixel ({x}, {y}) [stream index {k}]: core {rgb:06x}, golden {g_rgb:06x}"
    assert bool(user & 1) == g_sof, f"pixel ({x}, {y}): SOF {user & 1}, expected {int(g_sof)}"
    assert bool(last) == g_last, f"pixel ({x}, {y}): tlast {last}, expected {int(g_last)}"


async def sink_pixels(dut, w, expect, rng, stall_pct, got, state):
    """Takes pixels with random tready, checks each against the golden image as it
    arrives, and checks the AXI4-Stream hold rule."""
    npix = len(expect)
    held = None  # (tdata, tuser, tlast) of a beat offered and not taken
    while len(got) < npix:
        ready = rng.randrange(100) >= stall_pct
        dut.m_axis_tready.value = int(ready)
        await RisingEdge(dut.clock)
        if val(dut.m_axis_tvalid):
            beat = (val(dut.m_axis_tdata), val(dut.m_axis_tuser), val(dut.m_axis_tlast))
            if held is not None:
                assert beat == held, f"m_axis changed while stalled: {held} -> {beat} (pixel {len(got)})"
            if ready:
                check_pixel(len(got), beat, w, expect)
                got.append(beat)
                held = None
            else:
                state["out_stall"] += 1
                held = beat
        else:
            assert held is None, f"m_axis_tvalid dropped before the beat was taken (pixel {len(got)})"
    dut.m_axis_tready.value = 0


@cocotb.test()
async def frame(dut):
    beats = load_beats(os.environ["PIXELPROC_BEATS"])
    w, h, n, expect = load_expect(os.environ["PIXELPROC_EXPECT"])
    seed = int(os.environ.get("PIXELPROC_SEED", "1"))
    gap = int(os.environ.get("PIXELPROC_GAP_PCT", "20"))
    stall = int(os.environ.get("PIXELPROC_STALL_PCT", "30"))
    rng_in, rng_out = random.Random(seed), random.Random(seed * 7919 + 1)
    dut._log.info("%d beats, %dx%d pixels, N = %d, seed %d, gaps %d %%, stalls %d %%",
                  len(beats), w, h, n, seed, gap, stall)

    try:
        clock = Clock(dut.clock, 10, unit="ns")  # cocotb 2
    except TypeError:
        clock = Clock(dut.clock, 10, units="ns")  # cocotb 1.x
    cocotb.start_soon(clock.start())
    dut.s_axis_tvalid.value = 0
    dut.s_axis_tdata.value = 0
    dut.s_axis_tuser.value = 0
    dut.m_axis_tready.value = 0
    dut.rst.value = 1
    for i in range(3):
        await RisingEdge(dut.clock)
        if i > 0:  # from the first edge on (ports are X before it in a 4-state simulator)
            assert val(dut.s_axis_tready) == 0, "s_axis_tready must be 0 during reset"
    dut.rst.value = 0

    state = {"in_stall": 0, "out_stall": 0, "beats_done": False}
    got = []
    cocotb.start_soon(drive_commands(dut, beats, rng_in, gap, state))
    sink = cocotb.start_soon(sink_pixels(dut, w, expect, rng_out, stall, got, state))
    max_cycles = 64 * (len(beats) + len(expect)) + 10_000
    cycles = 0
    while not sink.done():
        await RisingEdge(dut.clock)
        cycles += 1
        assert val(dut.proto_err) == 0, f"proto_err set at cycle {cycles}"
        assert cycles < max_cycles, f"timeout: {len(got)} of {len(expect)} pixels after {cycles} cycles"
    await sink  # re-raises a pixel mismatch or protocol error
    assert len(got) == len(expect)
    dut._log.info("PIXELS %d identical; CYCLES %d IN_STALL %d OUT_STALL %d",
                  len(got), cycles, state["in_stall"], state["out_stall"])
    assert state["in_stall"] > 0 and state["out_stall"] > 0, "stalls were not exercised"
