//! The ports the search blocks share (seed 000, JP2569952B2, Fig. 6): the clock and reset,
//! the start inputs of both search units (blocks 2 and 3) and the result ports of the back
//! end (blocks 7, 8 and 10), each declared once here.
//!
//! rust-hdl derives a block's ports from its struct fields, so the shared ports are
//! spliced into each struct by a macro: the Verilog port names and their order stay those
//! of the fields (`clock`, `rst`, the block's own inputs, ..., `out_*`, internals).

/// Declares a search block with `clock`, `rst`, the given leading fields, the nine result
/// ports `out_*`, then the given trailing fields.
macro_rules! search_block {
    (
        $(#[$attr:meta])*
        pub struct $name:ident { $($head:tt)* }
        after_results { $($tail:tt)* }
    ) => {
        $(#[$attr])*
        #[derive(LogicBlock)]
        pub struct $name<const B: usize> {
            /// Clock.
            pub clock: Signal<In, Clock>,
            /// Synchronous reset: every register 0.
            pub rst: Signal<In, Bit>,
            $($head)*
            /// Result valid (one clock).
            pub out_valid: Signal<Out, Bit>,
            /// Result: the mask was not empty.
            pub out_hit: Signal<Out, Bit>,
            /// Result: lines tested (by the iterative search, for the same mask).
            pub out_steps: Signal<Out, Bits<LINE_BITS>>,
            /// Result: first non-zero AND result (0 if none).
            pub out_and: Signal<Out, Bits<B>>,
            /// Result: ROM word.
            pub out_rom: Signal<Out, Bits<WORD_BITS>>,
            /// Result: depth at end 1 (`zc` without hit), Q.12, 53-bit two's complement.
            pub out_z1: Signal<Out, Bits<Z_BITS>>,
            /// Result: depth at end 2.
            pub out_z2: Signal<Out, Bits<Z_BITS>>,
            /// Result: min depth.
            pub out_zmin: Signal<Out, Bits<Z_BITS>>,
            /// Result: max depth.
            pub out_zmax: Signal<Out, Bits<Z_BITS>>,
            $($tail)*
        }
    };
}

/// Declares a search unit: a [`search_block!`] whose leading fields start with the start
/// inputs `in_*` (a mask, its start corner and its plane).
macro_rules! search_unit {
    (
        $(#[$attr:meta])*
        pub struct $name:ident { $($head:tt)* }
        after_results { $($tail:tt)* }
    ) => {
        search_block! {
            $(#[$attr])*
            pub struct $name {
                /// Start a search (the pipeline takes one every clock, the iterative unit
                /// when `ready`).
                pub in_valid: Signal<In, Bit>,
                /// Fraction mask.
                pub in_mask: Signal<In, Bits<B>>,
                /// Start corner code (bit 0 right, bit 1 bottom).
                pub in_corner: Signal<In, Bits<2>>,
                /// Plane `zc`, Q.12, 48-bit two's complement.
                pub in_zc: Signal<In, Bits<PB>>,
                /// Plane `sx`.
                pub in_sx: Signal<In, Bits<PB>>,
                /// Plane `sy`.
                pub in_sy: Signal<In, Bits<PB>>,
                $($head)*
            }
            after_results { $($tail)* }
        }
    };
}

/// Builds a [`search_block!`] struct: the shared ports default, the given fields as given.
macro_rules! search_block_new {
    ($name:ident { $($field:ident $(: $value:expr)?),* $(,)? }) => {
        $name {
            clock: Default::default(),
            rst: Default::default(),
            out_valid: Default::default(),
            out_hit: Default::default(),
            out_steps: Default::default(),
            out_and: Default::default(),
            out_rom: Default::default(),
            out_z1: Default::default(),
            out_z2: Default::default(),
            out_zmin: Default::default(),
            out_zmax: Default::default(),
            $($field $(: $value)?),*
        }
    };
}

/// Builds a [`search_unit!`] struct: the shared ports default, the given fields as given.
macro_rules! search_unit_new {
    ($name:ident { $($field:ident $(: $value:expr)?),* $(,)? }) => {
        search_block_new!($name {
            in_valid: Default::default(),
            in_mask: Default::default(),
            in_corner: Default::default(),
            in_zc: Default::default(),
            in_sx: Default::default(),
            in_sy: Default::default(),
            $($field $(: $value)?),*
        })
    };
}

/// Implements `Logic` for a search unit: the unit's own kernel (an `update` written as
/// usual, with its `#[hdl_gen]`), followed by the back end's result ports forwarded to the
/// unit's `out_*` ports. The attribute, `fn` and receiver are passed through as the
/// caller's tokens: the kernel generator names its receiver after them, so the body's
/// `self` must come from the same place.
macro_rules! search_unit_logic {
    (
        $name:ident,
        $hash:tt $gen:tt
        $fn:ident $update:ident(&mut $s:ident) { $($body:tt)* }
    ) => {
        impl<const B: usize> Logic for $name<B> {
            $hash $gen
            $fn $update(&mut $s) {
                $($body)*
                $s.out_valid.next = $s.back.out_valid.val();
                $s.out_hit.next = $s.back.out_hit.val();
                $s.out_steps.next = $s.back.out_steps.val();
                $s.out_and.next = $s.back.out_and.val();
                $s.out_rom.next = $s.back.out_rom.val();
                $s.out_z1.next = $s.back.out_z1.val();
                $s.out_z2.next = $s.back.out_z2.val();
                $s.out_zmin.next = $s.back.out_zmin.val();
                $s.out_zmax.next = $s.back.out_zmax.val();
            }
        }
    };
}

/// Implements `Logic` for a stream search unit (a struct with `s_tdata`, `core`, `fifo`,
/// `k_hit` and a local `l_word`): the unit's own kernel, followed by the two word layouts.
/// `s_tdata` is taken apart onto the core's `in_*` ports, and the core's `out_*` ports
/// are packed into the FIFO's `i_data` (layouts in `stream_in_bits` and
/// `stream_out_bits`; the literal offsets are checked against them in `mod.rs`).
macro_rules! stream_unit_logic {
    (
        $name:ident,
        $hash:tt $gen:tt
        $fn:ident $update:ident(&mut $s:ident) { $($body:tt)* }
    ) => {
        impl<const B: usize, const IW: usize, const OW: usize> Logic for $name<B, IW, OW> {
            $hash $gen
            $fn $update(&mut $s) {
                $($body)*
                $s.core.in_zc.next = $s.s_tdata.val().get_bits::<PB>(0);
                $s.core.in_sx.next = $s.s_tdata.val().get_bits::<PB>(48);
                $s.core.in_sy.next = $s.s_tdata.val().get_bits::<PB>(96);
                $s.core.in_corner.next = $s.s_tdata.val().get_bits::<2>(144);
                $s.core.in_mask.next = $s.s_tdata.val().get_bits::<B>(146);
                $s.l_word.next = bit_cast::<OW, Z_BITS>($s.core.out_z1.val())
                    | (bit_cast::<OW, Z_BITS>($s.core.out_z2.val()) << 53)
                    | (bit_cast::<OW, Z_BITS>($s.core.out_zmin.val()) << 106)
                    | (bit_cast::<OW, Z_BITS>($s.core.out_zmax.val()) << 159)
                    | (bit_cast::<OW, WORD_BITS>($s.core.out_rom.val()) << 212)
                    | (bit_cast::<OW, LINE_BITS>($s.core.out_steps.val()) << 229)
                    | (bit_cast::<OW, B>($s.core.out_and.val()) << 235);
                if $s.core.out_hit.val() {
                    $s.l_word.next = $s.l_word.val() | $s.k_hit.val();
                }
                $s.fifo.i_valid.next = $s.core.out_valid.val();
                $s.fifo.i_data.next = $s.l_word.val();
            }
        }
    };
}
