//! Per-clock command opcodes of the pixel-processor array.
//!
//! The array's command port mirrors the golden model's `Command` enum
//! (`pixelproc_sim::pixel_array::Command`) one for one. A cycle with `cmd_valid = 0` is a
//! `Nop` whatever the opcode.

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
