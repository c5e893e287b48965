//! The pixelproc core: the pixel-processor array of seed 001 (Matsumoto) behind an
//! AXI4-Stream command input with a FIFO, a readout controller that streams each finished
//! tile-line out while the next one is drawn, the shading step of seed 001 (section 2,
//! "correct the intensity and store it"; section 6's table), and an AXI4-Stream pixel
//! output with a FIFO. `docs/core.md` documents the protocol bit by bit; the stream
//! formats live in `pixelproc_formats::core_stream`, the cycle-level golden twin in
//! `pixelproc_sim::core_model`.
//!
//! # Ports
//!
//! | port | dir | width | meaning |
//! |---|---|---|---|
//! | `clock` | in | 1 | rising edge |
//! | `rst` | in | 1 | synchronous reset (FIFOs emptied, controller idle, a RESET token down the array); `s_axis_tready` is 0 while it is 1 |
//! | `s_axis_tvalid`, `s_axis_tready` | in, out | 1, 1 | command stream handshake |
//! | `s_axis_tdata` | in | 256 | span word, or a TILE/TABLE/LATCH argument |
//! | `s_axis_tuser` | in | 4 | beat kind (`core_stream::KIND_*`) |
//! | `m_axis_tvalid`, `m_axis_tready` | out, in | 1, 1 | pixel stream handshake |
//! | `m_axis_tdata` | out | 24 | final RGB888 |
//! | `m_axis_tuser` | out | 51 | start of frame; debug fields (`core_stream::OUT_USER_FIELDS`) |
//! | `m_axis_tlast` | out | 1 | last pixel of a tile-line |
//! | `proto_err` | out | 1 | sticky: a beat of an unknown kind, or a TILE whose `LAST ≥ N`, was seen (or a pixel met a full output FIFO, which the credit check rules out) |
//! | `in_level` | out | `IA + 1` | beats in the command FIFO |
//!
//! # Controller, one rising edge
//!
//! The head of the input FIFO is *issued* (popped and given to the array) unless it is a
//! TILE or END beat while a readout job is still waiting or sweeping (`job_v`): such a
//! beat would overwrite the readout registers being read. That is the only input stall;
//! the source never pads. The stall is a register, `hold`, loaded at every edge with
//! `job_v`'s next value and the frame flag (TILE or END) of the beat at the head after the
//! edge: a beat's frame flag is decoded as it enters the FIFO (bit 0 of the stored beat),
//! and the FIFO gives it a clock ahead (`StreamFifo::next_tag`). So the FIFO's fetch, the
//! clock enable of its head register, reads three flip-flops (`job_v` and the head's
//! decoded kind in front of it were the worst path at N = 16, 32 and 64 on an ECP5).
//! - SPAN, CHECK, CLEAR_FLAGS, ACCUMULATE, LATCH_SHADOW, NOP: the array's command port.
//! - TILE: CLEAR_LINE with the beat's background; the tile base register takes `BASE`.
//!   If a tile-line was pending in the array, a readout job for it starts (wait counter
//!   [`READOUT_WAIT`], then addresses `0 ..= LAST`); the new tile-line becomes pending.
//! - END: the same CLEAR_LINE and job, nothing pending afterwards.
//! - TABLE: one shading-table write, in the table one edge later (the shading unit
//!   registers it: `shade_unit::TW_DELAY`).
//!
//! The sweep sends one address per clock while the output FIFO has room for every pixel
//! in flight (`level + inflight < 16`, kept in one register, `credit`, and read from another,
//! `no_room`, equal to `credit ≥ 16` after every edge). A pixel whose
//! address the array samples at edge `E` is in the output FIFO after edge
//! `E + `[`READ_TO_FIFO`] (array readout: 2 registers; then the core's tracking register
//! and the shading unit's `SHADE_STAGES` stages).
//!
//! **Why [`READOUT_WAIT`] = 4 is enough.** A TILE issued at edge `E` reaches processor
//! `a`'s readout registers at edge `E + 6 + a` (`LATENCY_PROC0 = 6`). The sweep's first
//! address is sampled at `E + 5` and address `a` at `E + 5 + a` or later; the array shows
//! processor `a`'s readout registers as they were after the next edge, `E + 6 + a`. The
//! job ends when its last address is sent, and a TILE may issue on the next clock: it
//! reaches processor `a` at least 7 edges after `a` was read.

use crate::layout::{
    BeatFields, PixFields, ReadoutFields, TileFields, UserFields, BEAT_W, PIX_W, READOUT_W, SPAN_W,
};
use crate::opcodes::*;
use crate::pixel_array::PixelProcessorArray;
use crate::shade_unit::{ShadeUnit, META_W};
use crate::stream_fifo::StreamFifo;
use pixelproc_formats::core_stream::{
    CoreRegs, KIND_BITS, KIND_END, KIND_TABLE, KIND_TILE, OUT_USER_BITS,
};
use pixelproc_formats::regs::RGB_BITS;
use pixelproc_formats::SPAN_XL;
use rust_hdl::prelude::*;

// The core reads a fetched beat's frame flag from bit 0 of the input FIFO's `next_tag`.
const _: () = assert!(crate::stream_fifo::TAG_BITS >= 1 && crate::layout::BEAT_FRAME.lsb == 0);

/// Width of a column number.
const X_W: usize = SPAN_XL.width;
/// Clocks a readout job waits before its first address (see the module header).
pub const READOUT_WAIT: u32 = 4;
/// Address bits of the output FIFO (16 pixels).
pub const OUT_FIFO_ABITS: usize = 4;
/// Slices of the input FIFO's RAM, each with its own copy of the FIFO's pointers
/// (`lut_ram::SlicedLutRam`): a 261-bit beat in slices of 32 to 36 bits, so one read
/// pointer copy addresses 16 or 18 LUT RAM primitives instead of 130.
pub const IN_FIFO_SLICES: usize = 8;
/// Edges from the array sampling a readout address to the pixel being in the output FIFO.
pub const READ_TO_FIFO: u32 = 3 + pixelproc_formats::core_stream::SHADE_STAGES as u32;

/// The core with an input FIFO of `2^IA` beats (`IA1 = IA + 1`). Build with
/// [`PixelprocCore::new`].
#[derive(LogicBlock)]
pub struct PixelprocCore<const IA: usize, const IA1: usize> {
    /// Clock.
    pub clock: Signal<In, Clock>,
    /// Synchronous reset.
    pub rst: Signal<In, Bit>,
    /// Command stream: a beat is offered.
    pub s_axis_tvalid: Signal<In, Bit>,
    /// Command stream: the core takes the beat at the next edge.
    pub s_axis_tready: Signal<Out, Bit>,
    /// Command stream: data.
    pub s_axis_tdata: Signal<In, Bits<SPAN_W>>,
    /// Command stream: beat kind.
    pub s_axis_tuser: Signal<In, Bits<KIND_BITS>>,
    /// Pixel stream: a pixel is offered.
    pub m_axis_tvalid: Signal<Out, Bit>,
    /// Pixel stream: the sink takes the pixel at the next edge.
    pub m_axis_tready: Signal<In, Bit>,
    /// Pixel stream: RGB888.
    pub m_axis_tdata: Signal<Out, Bits<RGB_BITS>>,
    /// Pixel stream: start of frame and debug fields.
    pub m_axis_tuser: Signal<Out, Bits<OUT_USER_BITS>>,
    /// Pixel stream: last pixel of a tile-line.
    pub m_axis_tlast: Signal<Out, Bit>,
    /// Sticky protocol error.
    pub proto_err: Signal<Out, Bit>,
    /// Beats in the command FIFO (status for a host or DMA).
    pub in_level: Signal<Out, Bits<IA1>>,
    /// The command FIFO.
    pub in_fifo: StreamFifo<BEAT_W, IA, IA1>,
    /// The pixel-processor array.
    pub array: PixelProcessorArray,
    /// The shading unit.
    pub shade: ShadeUnit,
    /// The pixel FIFO.
    pub out_fifo: StreamFifo<PIX_W, OUT_FIFO_ABITS, 5>,
    base_r: DFF<Bits<X_W>>,
    pend_v: DFF<Bit>,
    pend_last: DFF<Bits<X_W>>,
    pend_sof: DFF<Bit>,
    job_v: DFF<Bit>,
    /// `hold = frame(head) ∧ job_v` whenever the input FIFO presents a beat: the input
    /// stall, from one flip-flop (module header, "Controller").
    hold: DFF<Bit>,
    job_wait: DFF<Bits<3>>,
    job_last: DFF<Bits<X_W>>,
    job_sof: DFF<Bit>,
    ra: DFF<Bits<X_W>>,
    t1: DFF<Bits<3>>,
    t2: DFF<Bits<3>>,
    t3: DFF<Bits<3>>,
    inflight: DFF<Bits<5>>,
    credit: DFF<Bits<6>>,
    /// `credit ≥ 16` after every edge (no room for another pixel): the sweep's room check
    /// from one flip-flop.
    no_room: DFF<Bit>,
    err: DFF<Bit>,
    l_beat: Signal<Local, Bits<BEAT_W>>,
    l_data: Signal<Local, Bits<SPAN_W>>,
    l_kind: Signal<Local, Bits<KIND_BITS>>,
    l_frame: Signal<Local, Bit>,
    l_tile: Signal<Local, Bit>,
    l_table: Signal<Local, Bit>,
    l_arr: Signal<Local, Bit>,
    l_issue: Signal<Local, Bit>,
    l_jv: Signal<Local, Bit>,
    l_nframe: Signal<Local, Bit>,
    l_go: Signal<Local, Bit>,
    l_cp1: Signal<Local, Bits<6>>,
    l_cm1: Signal<Local, Bits<6>>,
    l_cm2: Signal<Local, Bits<6>>,
    l_credit: Signal<Local, Bits<6>>,
    l_pop: Signal<Local, Bit>,
    l_lost: Signal<Local, Bit>,
    l_t1: Signal<Local, Bits<3>>,
    l_rdw: Signal<Local, Bits<READOUT_W>>,
    l_user: Signal<Local, Bits<OUT_USER_BITS>>,
    l_pix: Signal<Local, Bits<PIX_W>>,
    l_ow: Signal<Local, Bits<READOUT_W>>,
    l_meta: Signal<Local, Bits<META_W>>,
    k_tile: Constant<Bits<KIND_BITS>>,
    k_end: Constant<Bits<KIND_BITS>>,
    k_table: Constant<Bits<KIND_BITS>>,
    k_clear: Constant<Bits<OP_BITS>>,
    k_cl4: Constant<Bits<KIND_BITS>>,
    k_rst4: Constant<Bits<KIND_BITS>>,
    k_eight: Constant<Bits<KIND_BITS>>,
    k_wait: Constant<Bits<3>>,
    k_zero3: Constant<Bits<3>>,
    k_one3: Constant<Bits<3>>,
    k_zero12: Constant<Bits<X_W>>,
    k_one12: Constant<Bits<X_W>>,
    k_nlast: Constant<Bits<X_W>>,
    k_zero5: Constant<Bits<5>>,
    k_one5: Constant<Bits<5>>,
    k_no_room: Constant<Bits<6>>,
    k_zero6: Constant<Bits<6>>,
    k_one6: Constant<Bits<6>>,
    k_minus1_6: Constant<Bits<6>>,
    k_minus2_6: Constant<Bits<6>>,
    k_debug: Constant<Bit>,
    k_two3: Constant<Bits<3>>,
    k_four3: Constant<Bits<3>>,
    k_zero_beat: Constant<Bits<BEAT_W>>,
    k_zero_rd: Constant<Bits<READOUT_W>>,
    k_zero_user: Constant<Bits<OUT_USER_BITS>>,
    k_zero_pix: Constant<Bits<PIX_W>>,
}

impl<const IA: usize, const IA1: usize> PixelprocCore<IA, IA1> {
    /// A core with an array of `width` processors (1 ..= 4096), the span-parity logic
    /// and the shading table iff `shadows`, and the debug fields on `m_axis_tuser` iff
    /// `debug`.
    pub fn new(width: usize, shadows: bool, debug: bool) -> Result<Self, crate::RtlError> {
        fn k<const W: usize>(v: u64) -> Constant<Bits<W>> {
            Constant::new(v.to_bits())
        }
        let array = PixelProcessorArray::new(width, shadows)?;
        Ok(PixelprocCore {
            clock: Default::default(),
            rst: Default::default(),
            s_axis_tvalid: Default::default(),
            s_axis_tready: Default::default(),
            s_axis_tdata: Default::default(),
            s_axis_tuser: Default::default(),
            m_axis_tvalid: Default::default(),
            m_axis_tready: Default::default(),
            m_axis_tdata: Default::default(),
            m_axis_tuser: Default::default(),
            m_axis_tlast: Default::default(),
            proto_err: Default::default(),
            in_level: Default::default(),
            in_fifo: StreamFifo::with_slices(IN_FIFO_SLICES).writing_every_edge(),
            array,
            shade: ShadeUnit::new(shadows),
            out_fifo: Default::default(),
            base_r: Default::default(),
            pend_v: Default::default(),
            pend_last: Default::default(),
            pend_sof: Default::default(),
            job_v: Default::default(),
            hold: Default::default(),
            l_jv: Default::default(),
            l_nframe: Default::default(),
            job_wait: Default::default(),
            job_last: Default::default(),
            job_sof: Default::default(),
            ra: Default::default(),
            t1: Default::default(),
            t2: Default::default(),
            t3: Default::default(),
            inflight: Default::default(),
            credit: Default::default(),
            no_room: Default::default(),
            err: Default::default(),
            l_beat: Default::default(),
            l_data: Default::default(),
            l_kind: Default::default(),
            l_frame: Default::default(),
            l_tile: Default::default(),
            l_table: Default::default(),
            l_arr: Default::default(),
            l_issue: Default::default(),
            l_go: Default::default(),
            l_cp1: Default::default(),
            l_cm1: Default::default(),
            l_cm2: Default::default(),
            l_credit: Default::default(),
            l_pop: Default::default(),
            l_lost: Default::default(),
            l_t1: Default::default(),
            l_rdw: Default::default(),
            l_user: Default::default(),
            l_pix: Default::default(),
            l_ow: Default::default(),
            l_meta: Default::default(),
            k_tile: k(KIND_TILE),
            k_end: k(KIND_END),
            k_table: k(KIND_TABLE),
            k_clear: k(OP_CLEAR_LINE),
            k_cl4: k(OP_CLEAR_LINE),
            k_rst4: k(OP_RESET),
            k_eight: k(8),
            k_wait: k(READOUT_WAIT as u64),
            k_zero3: k(0),
            k_one3: k(1),
            k_zero12: k(0),
            k_one12: k(1),
            k_nlast: k(width as u64 - 1),
            k_zero5: k(0),
            k_one5: k(1),
            k_no_room: k(0x3f & !((1 << OUT_FIFO_ABITS) - 1)),
            k_zero6: k(0),
            k_one6: k(1),
            k_minus1_6: k(0b11_1111),
            k_minus2_6: k(0b11_1110),
            k_debug: Constant::new(debug),
            k_two3: k(2),
            k_four3: k(4),
            k_zero_beat: k(0),
            k_zero_rd: k(0),
            k_zero_user: k(0),
            k_zero_pix: k(0),
        })
    }

    /// Number of processors.
    pub fn width(&self) -> usize {
        self.array.width()
    }

    /// Input FIFO depth in beats.
    pub const IN_DEPTH: usize = 1 << IA;

    /// The control registers, for the clock-by-clock comparison with the golden model.
    pub fn probe(&self) -> CoreRegs {
        let u = |b: u64| b as u32;
        let t = |d: &DFF<Bits<3>>| d.q.val().index() as u8;
        CoreRegs {
            in_fifo: self.in_fifo.probe(),
            out_fifo: self.out_fifo.probe(),
            base: u(self.base_r.q.val().to_u64()),
            pending: (
                self.pend_v.q.val(),
                u(self.pend_last.q.val().to_u64()),
                self.pend_sof.q.val(),
            ),
            job: (
                self.job_v.q.val(),
                u(self.job_wait.q.val().to_u64()),
                u(self.job_last.q.val().to_u64()),
                self.job_sof.q.val(),
                u(self.ra.q.val().to_u64()),
            ),
            track: [t(&self.t1), t(&self.t2), t(&self.t3)],
            inflight: u(self.inflight.q.val().to_u64()),
            err: self.err.q.val(),
        }
    }
}

impl<const IA: usize, const IA1: usize> Logic for PixelprocCore<IA, IA1> {
    #[hdl_gen]
    fn update(&mut self) {
        dff_setup!(
            self, clock, base_r, pend_v, pend_last, pend_sof, job_v, hold, job_wait, job_last,
            job_sof, ra, t1, t2, t3, inflight, credit, no_room, err
        );
        self.l_jv.next = self.job_v.q.val();
        self.in_fifo.clock.next = self.clock.val();
        self.array.clock.next = self.clock.val();
        self.shade.clock.next = self.clock.val();
        self.out_fifo.clock.next = self.clock.val();
        self.in_fifo.rst.next = self.rst.val();
        self.array.rst.next = self.rst.val();
        self.shade.rst.next = self.rst.val();
        self.out_fifo.rst.next = self.rst.val();
        // ---- Command stream into the input FIFO.
        self.l_beat.next = self.k_zero_beat.val();
        self.l_beat.next.set_value_tdata(self.s_axis_tdata.val());
        self.l_beat.next.set_value_kind(self.s_axis_tuser.val());
        // The frame flag, decoded as the beat enters: TILE or END.
        self.l_beat.next.set_value_frame(
            (self.s_axis_tuser.val() == self.k_tile.val())
                | (self.s_axis_tuser.val() == self.k_end.val()),
        );
        self.in_fifo.in_data.next = self.l_beat.val();
        self.in_fifo.in_valid.next = self.s_axis_tvalid.val();
        self.s_axis_tready.next = self.in_fifo.in_ready.val();
        self.in_level.next = self.in_fifo.level.val();
        // ---- Decode the head beat; issue it unless it would start a second readout job.
        self.l_data.next = self.in_fifo.out_data.val().get_value_tdata();
        self.l_kind.next = self.in_fifo.out_data.val().get_value_kind();
        self.l_tile.next = self.l_kind.val() == self.k_tile.val();
        self.l_frame.next = self.in_fifo.out_data.val().get_value_frame();
        self.l_table.next = self.l_kind.val() == self.k_table.val();
        self.l_arr.next = (self.l_kind.val() < self.k_eight.val())
            & (self.l_kind.val() != self.k_cl4.val())
            & (self.l_kind.val() != self.k_rst4.val());
        // The stall `frame(head) ∧ job_v` is the register `hold` (set below from both
        // values after the edge), so the FIFO's fetch, the clock enable of its 261-bit head
        // register, reads three flip-flops. `rst` is left out of the FIFO's `out_ready`:
        // the FIFO's own reset overrides every register a pop or fetch would change (and
        // the head register holds nothing while `dv` is 0); it stays in the issue.
        self.in_fifo.out_ready.next = !self.hold.q.val();
        self.l_issue.next = self.in_fifo.out_valid.val() & !self.hold.q.val() & !self.rst.val();
        // ---- The array's command port.
        self.array.cmd_valid.next = self.l_issue.val() & (self.l_arr.val() | self.l_frame.val());
        self.array.cmd_op.next = self.l_kind.val().get_bits::<OP_BITS>(0);
        if self.l_frame.val() {
            self.array.cmd_op.next = self.k_clear.val();
        }
        self.array.cmd_bg.next = self.l_data.val().get_value_bg();
        self.array.cmd_word.next = self.l_data.val();
        // The tile's first column, for the commands that use it (SPAN and CHECK: their
        // range and the tile offset): `base_r`, which a TILE beat loads. The CLEAR_LINE a
        // TILE or END beat sends ignores it, so no decode of the head beat sits in front
        // of the array's tile-offset subtraction.
        self.array.tile_base.next = self.base_r.q.val();
        // ---- Shading-table writes.
        // `l_issue & l_table`, spelled without the readout hold: a TABLE beat is never a
        // TILE or END, so it issues whenever it is at the head and `rst` is 0. The
        // shading unit registers the write with each bank's enable decoded (one edge
        // late: `shade_unit::TW_DELAY`).
        self.shade.tw_en.next = self.in_fifo.out_valid.val() & self.l_table.val() & !self.rst.val();
        self.shade.tw_addr.next = self.l_data.val().get_value_taddr();
        self.shade.tw_data.next = self.l_data.val().get_value_tentry();
        // ---- Tile framing: a TILE or END starts the readout of the pending tile-line.
        if self.l_issue.val() & self.l_tile.val() {
            self.base_r.d.next = self.l_data.val().get_value_base();
            if self.l_data.val().get_value_last() > self.k_nlast.val() {
                self.err.d.next = true;
            }
        }
        if self.l_issue.val() & self.l_frame.val() {
            if self.pend_v.q.val() {
                self.l_jv.next = true;
                self.job_wait.d.next = self.k_wait.val();
                self.job_last.d.next = self.pend_last.q.val();
                self.job_sof.d.next = self.pend_sof.q.val();
                self.ra.d.next = self.k_zero12.val();
            }
            self.pend_v.d.next = self.l_tile.val();
            self.pend_last.d.next = self.l_data.val().get_value_last();
            self.pend_sof.d.next = self.l_data.val().get_value_sof();
        }
        if self.l_issue.val() & !(self.l_arr.val() | self.l_frame.val() | self.l_table.val()) {
            self.err.d.next = true;
        }
        // ---- Readout sweep: one address per clock while the output FIFO has room.
        if self.job_v.q.val() & (self.job_wait.q.val() != self.k_zero3.val()) {
            self.job_wait.d.next = self.job_wait.q.val() - self.k_one3.val();
        }
        // The room check reads `no_room`, a register equal to `credit ≥ 16` after every
        // edge; `credit` is a register equal to `out_fifo.level + inflight` (both count the
        // pixels sent and not yet taken by the sink). So neither FIFO pointer arithmetic
        // nor `credit`'s compare sits in front of the sweep's enables (the compare, a
        // carry chain in front of `hold`, `ra` and `credit` itself, was among the worst
        // paths at N = 8, 16 and 32: `docs/fpga.md`).
        self.l_go.next = self.job_v.q.val()
            & (self.job_wait.q.val() == self.k_zero3.val())
            & !self.no_room.q.val();
        self.array.rd_addr.next = self.ra.q.val();
        self.l_t1.next = self.k_zero3.val();
        if self.l_go.val() {
            self.ra.d.next = self.ra.q.val() + self.k_one12.val();
            self.l_t1.next = self.l_t1.val() | self.k_one3.val();
            if self.ra.q.val() == self.job_last.q.val() {
                self.l_jv.next = false;
                self.l_t1.next = self.l_t1.val() | self.k_two3.val();
            }
            if (self.ra.q.val() == self.k_zero12.val()) & self.job_sof.q.val() {
                self.l_t1.next = self.l_t1.val() | self.k_four3.val();
            }
        }
        self.t1.d.next = self.l_t1.val();
        self.t2.d.next = self.t1.q.val();
        self.t3.d.next = self.t2.q.val();
        // ---- The array's readout port, as one word, into the shading unit.
        self.l_rdw.next = self.k_zero_rd.val();
        self.l_rdw.next.set_value_zb(self.array.rd_zb.val());
        self.l_rdw.next.set_value_rgb(self.array.rd_rgb.val());
        self.l_rdw.next.set_value_dsf(self.array.rd_dsf.val());
        self.l_rdw.next.set_value_fsf(self.array.rd_fsf.val());
        self.l_rdw.next.set_value_count(self.array.rd_count.val());
        self.l_rdw.next.set_value_mask(self.array.rd_mask.val());
        self.l_rdw.next.set_value_nclass(self.array.rd_nclass.val());
        self.l_rdw.next.set_value_sh(self.array.rd_sh.val());
        self.l_rdw.next.set_value_won(self.array.rd_won.val());
        self.shade.in_valid.next = self.t3.q.val().get_bit(0);
        self.shade.in_word.next = self.l_rdw.val();
        self.shade.in_meta.next = self.t3.q.val().get_bits::<META_W>(1);
        // ---- Shaded pixels into the output FIFO.
        self.l_ow.next = self.shade.out_word.val();
        self.l_meta.next = self.shade.out_meta.val();
        self.l_user.next = self.k_zero_user.val();
        self.l_user
            .next
            .set_value_usof(self.l_meta.val().get_bit(1));
        if self.k_debug.val() {
            self.l_user
                .next
                .set_value_uzb(self.l_ow.val().get_value_zb());
            self.l_user
                .next
                .set_value_udsf(self.l_ow.val().get_value_dsf());
            self.l_user
                .next
                .set_value_ufsf(self.l_ow.val().get_value_fsf());
            self.l_user
                .next
                .set_value_ucount(self.l_ow.val().get_value_count());
            self.l_user
                .next
                .set_value_umask(self.l_ow.val().get_value_mask());
            self.l_user
                .next
                .set_value_unclass(self.l_ow.val().get_value_nclass());
        }
        self.l_pix.next = self.k_zero_pix.val();
        self.l_pix
            .next
            .set_value_prgb(self.l_ow.val().get_value_rgb());
        self.l_pix.next.set_value_puser(self.l_user.val());
        self.l_pix
            .next
            .set_value_plast(self.l_meta.val().get_bit(0));
        self.out_fifo.in_valid.next = self.shade.out_valid.val();
        if self.shade.out_valid.val() & !self.out_fifo.in_ready.val() {
            // Never in a correct core (the sweep's credit check): a lost pixel is an error.
            self.err.d.next = true;
        }
        self.out_fifo.in_data.next = self.l_pix.val();
        if self.l_go.val() & !self.shade.out_valid.val() {
            self.inflight.d.next = self.inflight.q.val() + self.k_one5.val();
        }
        if !self.l_go.val() & self.shade.out_valid.val() {
            self.inflight.d.next = self.inflight.q.val() - self.k_one5.val();
        }
        // credit' = credit + sent − taken by the sink − lost (a pixel that met a full FIFO,
        // never in a correct core): level' + inflight' exactly.
        self.l_pop.next = self.out_fifo.out_valid.val() & self.m_axis_tready.val();
        self.l_lost.next = self.shade.out_valid.val() & !self.out_fifo.in_ready.val();
        // The change (+1 .. −2) is decoded from the three bits while the three possible
        // sums, straight from `credit`, run in parallel: the decode selects a sum instead
        // of feeding an adder (`l_go` itself depends on `credit`).
        self.l_cp1.next = self.credit.q.val() + self.k_one6.val();
        self.l_cm1.next = self.credit.q.val() + self.k_minus1_6.val();
        self.l_cm2.next = self.credit.q.val() + self.k_minus2_6.val();
        self.l_credit.next = self.credit.q.val();
        if self.l_go.val() & !self.l_pop.val() & !self.l_lost.val() {
            self.l_credit.next = self.l_cp1.val();
        }
        if (self.l_go.val() & self.l_pop.val() & self.l_lost.val())
            | (!self.l_go.val() & (self.l_pop.val() ^ self.l_lost.val()))
        {
            self.l_credit.next = self.l_cm1.val();
        }
        if !self.l_go.val() & self.l_pop.val() & self.l_lost.val() {
            self.l_credit.next = self.l_cm2.val();
        }
        // ---- Pixel stream.
        self.out_fifo.out_ready.next = self.m_axis_tready.val();
        self.m_axis_tvalid.next = self.out_fifo.out_valid.val();
        self.m_axis_tdata.next = self.out_fifo.out_data.val().get_value_prgb();
        self.m_axis_tuser.next = self.out_fifo.out_data.val().get_value_puser();
        self.m_axis_tlast.next = self.out_fifo.out_data.val().get_value_plast();
        self.proto_err.next = self.err.q.val();
        if self.rst.val() {
            self.pend_v.d.next = false;
            self.l_jv.next = false;
            self.job_wait.d.next = self.k_zero3.val();
            self.t1.d.next = self.k_zero3.val();
            self.t2.d.next = self.k_zero3.val();
            self.t3.d.next = self.k_zero3.val();
            self.inflight.d.next = self.k_zero5.val();
            self.l_credit.next = self.k_zero6.val();
            self.err.d.next = false;
            self.base_r.d.next = self.k_zero12.val();
            self.ra.d.next = self.k_zero12.val();
        }
        self.credit.d.next = self.l_credit.val();
        self.no_room.d.next = (self.l_credit.val() & self.k_no_room.val()) != self.k_zero6.val();
        // ---- The stall after this edge: `job_v` after it, and the frame flag of the head
        // beat after it (the fetched beat's on a fetch, else the held one's). While the
        // FIFO presents nothing (`dv = 0`) `hold` is not used, and a fetch, which sets
        // `dv`, loads it from the beat's own flag.
        self.job_v.d.next = self.l_jv.val();
        self.l_nframe.next = self.l_frame.val();
        if self.in_fifo.fetching.val() {
            self.l_nframe.next = self.in_fifo.next_tag.val().get_bit(0);
        }
        self.hold.d.next = self.l_jv.val() & self.l_nframe.val();
    }
}

/// Input FIFO address bits of the exported core (32 beats).
pub const DEFAULT_IN_ABITS: usize = 5;
/// The core as exported: a 32-beat input FIFO.
pub type DefaultCore = PixelprocCore<DEFAULT_IN_ABITS, { DEFAULT_IN_ABITS + 1 }>;

/// Module name of the exported core: `pixelproc_core_n{N}[_shadow][_debug]`.
pub fn core_module_name(width: usize, shadows: bool, debug: bool) -> String {
    format!(
        "pixelproc_core_n{width}{}{}",
        if shadows { "_shadow" } else { "" },
        if debug { "_debug" } else { "" }
    )
}

/// The core's Verilog (one self-contained file) and its module name.
pub fn core_verilog(
    width: usize,
    shadows: bool,
    debug: bool,
) -> Result<(String, String), crate::RtlError> {
    let name = core_module_name(width, shadows, debug);
    let core = DefaultCore::new(width, shadows, debug)?;
    Ok((crate::verilog::export(core, &name), name))
}
