//! Per-clock command opcodes of the pixel-processor array (seed 001, Matsumoto,
//! sections 3 to 6: span expansion, the shadow-flag program, the counter and the
//! several-lights mask).
//!
//! The array's command port (`pixelproc_rtl::pixel_array`) mirrors the golden model's
//! `Command` enum (`pixelproc_sim::pixel_array::Command`) one for one. A cycle with
//! `cmd_valid = 0` is a `Nop` whatever the opcode. Defined here, beside the span word, so
//! that the RTL and the testbench encoders share one list.

/// Width of the `cmd_op` port.
pub const OP_BITS: usize = 3;

/// No operation (a bubble).
pub const OP_NOP: u64 = 0;
/// Start a new scanline: `ZB := Z_FAR`, intensity := `cmd_bg`, flags and counter := 0;
/// the registers' previous values are copied into the readout registers first.
pub const OP_CLEAR_LINE: u64 = 1;
/// Expand the span word on `cmd_word`.
pub const OP_SPAN: u64 = 2;
/// `DSF := 0; FSF := 0` (next point light of an area light).
pub const OP_CLEAR_FLAGS: u64 = 3;
/// `COUNT := min(COUNT + FSF, 255)`.
pub const OP_ACCUMULATE: u64 = 4;
/// `MASK := MASK | (FSF << bit)`: latch one point light's shadow into the light mask
/// (seed 001 section 6, several lights). The bit index travels in `cmd_bg[2:0]`.
pub const OP_LATCH_SHADOW: u64 = 5;
/// `FSF := FSF | DSF` for `XL <= col <= XR` only: the software form's check span (seed
/// 001 section 5). The range travels in the span word's `XL`/`XR` fields of `cmd_word`.
pub const OP_CHECK: u64 = 6;
/// Reset, the `rst` input as a token: it travels down the chain behind the entry
/// pipeline, so processor `p` is reset `LATENCY_PROC0 + p` edges after `rst` was sampled
/// and no reset net fans out to every processor. A command with this opcode resets too.
pub const OP_RESET: u64 = 7;
