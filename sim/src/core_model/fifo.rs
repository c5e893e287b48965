//! The golden twin of the RTL's stream FIFO (`pixelproc_rtl::stream_fifo`).

/// The RTL's first-word-fall-through FIFO (`pixelproc_rtl::stream_fifo`), register for
/// register: write and read pointers of `abits + 1` bits, the head-valid flag, the RAM.
#[derive(Clone, Debug)]
pub struct Fifo<T: Copy + Default> {
    abits: u32,
    wr: u32,
    rd: u32,
    dv: bool,
    mem: Vec<T>,
}

impl<T: Copy + Default> Fifo<T> {
    /// An empty FIFO of `2^abits` entries.
    pub fn new(abits: u32) -> Fifo<T> {
        Fifo {
            abits,
            wr: 0,
            rd: 0,
            dv: false,
            mem: vec![T::default(); 1 << abits],
        }
    }
    fn pmask(&self) -> u32 {
        (2 << self.abits) - 1
    }
    /// Entries held (`wr − rd + dv`).
    pub fn level(&self) -> u32 {
        (self.wr.wrapping_sub(self.rd).wrapping_add(self.dv as u32)) & self.pmask()
    }
    /// `in_ready`.
    pub fn in_ready(&self, rst: bool) -> bool {
        !rst && self.level() != 1 << self.abits
    }
    /// The head entry, when `out_valid`.
    pub fn head(&self) -> Option<T> {
        self.dv
            .then(|| self.mem[(self.rd.wrapping_sub(1) & ((1 << self.abits) - 1)) as usize])
    }
    /// `(wr, rd, dv)`, as the RTL probe reads them.
    pub fn regs(&self) -> (u32, u32, bool) {
        (self.wr, self.rd, self.dv)
    }
    /// One rising edge: `push` is written if `in_ready`, the head is popped if `pop` and
    /// `out_valid`. Returns whether `push` was taken.
    pub fn edge(&mut self, push: Option<T>, pop: bool, rst: bool) -> bool {
        let pop = self.dv && pop;
        let fetch = self.wr != self.rd && (!self.dv || pop);
        let taken = push.is_some() && self.in_ready(rst);
        if fetch {
            self.rd = (self.rd + 1) & self.pmask();
        }
        self.dv = fetch || (self.dv && !pop);
        if let (Some(v), true) = (push, taken) {
            let a = (self.wr & ((1 << self.abits) - 1)) as usize;
            self.mem[a] = v;
            self.wr = (self.wr + 1) & self.pmask();
        }
        if rst {
            (self.wr, self.rd, self.dv) = (0, 0, false);
        }
        taken
    }
}
