//! The program's allocator: the system allocator, with every large block (a frame's
//! buffers: processor states, depth and colour planes, fragment and command lists) mapped
//! on its own and marked for transparent huge pages.
//!
//! A 1080p frame touches tens of megabytes of fresh memory, and the kernel faults it in a
//! 4 KiB page at a time. Where that is slow (virtual machines, memory cgroups) the faults
//! were half of a plain frame's time. Linux's transparent huge pages map 2 MiB per fault,
//! but with the common setting `madvise` only in regions that ask for them. Blocks of
//! [`LARGE`] bytes or more are therefore their own anonymous mappings (fresh, zeroed, so
//! `alloc_zeroed` needs no clearing), advised with `MADV_HUGEPAGE`, and returned with
//! `munmap` when freed; a block that grows stays large with `mremap`. Smaller blocks,
//! over-aligned ones and every block on other systems go to the system allocator
//! unchanged. With THP `never` the advice is ignored and only the mapping remains; with
//! `always` the kernel already did this. What is computed does not change.

use std::alloc::{GlobalAlloc, Layout, System};

/// Smallest block mapped on its own (4 MiB): two huge pages.
#[cfg_attr(not(target_os = "linux"), allow(dead_code))]
pub const LARGE: usize = 4 << 20;

/// The allocator (`#[global_allocator]` in `main.rs`).
pub struct HugePageAlloc;

#[cfg(target_os = "linux")]
mod map {
    use super::LARGE;
    use std::alloc::Layout;
    use std::ptr::null_mut;

    /// `mmap` returns page-aligned memory; larger alignments go to the system allocator.
    const PAGE: usize = 4096;

    /// The layout is served by a mapping of its own.
    pub fn is_large(l: &Layout) -> bool {
        l.size() >= LARGE && l.align() <= PAGE
    }

    /// Asks for huge pages on the whole mapping `[p, p + size)`; the kernel uses them on
    /// the aligned 2 MiB pages inside it. (Advice on part of a mapping would split it, and
    /// `mremap` cannot resize a range that spans two.)
    fn advise(p: *mut u8, size: usize) {
        // SAFETY: the range is a mapping this module made; `madvise` with MADV_HUGEPAGE
        // changes no contents and fails harmlessly where unsupported.
        unsafe {
            libc::madvise(p.cast(), size, libc::MADV_HUGEPAGE);
        }
    }

    /// A fresh zeroed anonymous mapping of `size` bytes, or null.
    pub fn map(size: usize) -> *mut u8 {
        // SAFETY: an anonymous private mapping at an address the kernel picks; no
        // existing memory is affected.
        let p = unsafe {
            libc::mmap(
                null_mut(),
                size,
                libc::PROT_READ | libc::PROT_WRITE,
                libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
                -1,
                0,
            )
        };
        if p == libc::MAP_FAILED {
            return null_mut();
        }
        advise(p.cast(), size);
        p.cast()
    }

    /// Returns a mapping made by [`map`] or [`remap`].
    ///
    /// # Safety
    /// `p` and `size` are those of a live mapping from this module.
    pub unsafe fn unmap(p: *mut u8, size: usize) {
        libc::munmap(p.cast(), size);
    }

    /// Resizes a mapping made by [`map`] to `new` bytes (moving it if needed), or null
    /// (the old mapping then stays valid).
    ///
    /// # Safety
    /// `p` and `old` are those of a live mapping from this module.
    pub unsafe fn remap(p: *mut u8, old: usize, new: usize) -> *mut u8 {
        let q = libc::mremap(p.cast(), old, new, libc::MREMAP_MAYMOVE);
        if q == libc::MAP_FAILED {
            return null_mut();
        }
        advise(q.cast(), new);
        q.cast()
    }
}

// SAFETY: every block is either the system allocator's (passed through unchanged) or a
// mapping of its own, told apart by its layout alone (`map::is_large`), which the caller
// gives back unchanged to `dealloc` and `realloc`.
#[cfg(target_os = "linux")]
unsafe impl GlobalAlloc for HugePageAlloc {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        if map::is_large(&l) {
            map::map(l.size())
        } else {
            System.alloc(l)
        }
    }

    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        if map::is_large(&l) {
            // A fresh anonymous mapping reads as zeros.
            map::map(l.size())
        } else {
            System.alloc_zeroed(l)
        }
    }

    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        if map::is_large(&l) {
            map::unmap(p, l.size())
        } else {
            System.dealloc(p, l)
        }
    }

    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        // SAFETY (of the layout): `GlobalAlloc::realloc` requires `new`, rounded up to
        // `l.align()`, not to overflow `isize`, which is what `Layout` checks.
        let nl = Layout::from_size_align_unchecked(new, l.align());
        match (map::is_large(&l), map::is_large(&nl)) {
            (false, false) => System.realloc(p, l, new),
            (true, true) => {
                let q = map::remap(p, l.size(), new);
                if q.is_null() {
                    // The kernel could not resize it: a new block and a copy.
                    moved(self, p, l, nl)
                } else {
                    q
                }
            }
            _ => moved(self, p, l, nl),
        }
    }
}

/// `realloc` by a new block of layout `nl`, a copy and freeing the old one; null (the old
/// block kept) when no new block can be had.
///
/// # Safety
/// `p` is a live block of `a` with layout `l`.
#[cfg(target_os = "linux")]
unsafe fn moved(a: &HugePageAlloc, p: *mut u8, l: Layout, nl: Layout) -> *mut u8 {
    let q = a.alloc(nl);
    if !q.is_null() {
        std::ptr::copy_nonoverlapping(p, q, l.size().min(nl.size()));
        a.dealloc(p, l);
    }
    q
}

// SAFETY: the system allocator, unchanged.
#[cfg(not(target_os = "linux"))]
unsafe impl GlobalAlloc for HugePageAlloc {
    unsafe fn alloc(&self, l: Layout) -> *mut u8 {
        System.alloc(l)
    }
    unsafe fn alloc_zeroed(&self, l: Layout) -> *mut u8 {
        System.alloc_zeroed(l)
    }
    unsafe fn dealloc(&self, p: *mut u8, l: Layout) {
        System.dealloc(p, l)
    }
    unsafe fn realloc(&self, p: *mut u8, l: Layout, new: usize) -> *mut u8 {
        System.realloc(p, l, new)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A byte pattern that tells positions apart.
    fn pattern(i: usize) -> u8 {
        (i * 131 + i / 4093) as u8
    }

    /// Large blocks (own mappings) and small ones, zeroed and not, grown and shrunk across
    /// the threshold and within it: contents survive every resize and zeroed blocks read
    /// as zeros. Each step goes through `HugePageAlloc` directly.
    #[test]
    fn blocks_keep_their_contents_through_every_resize() {
        let a = HugePageAlloc;
        let sizes = [
            100,
            LARGE - 1,
            LARGE,
            LARGE + 12_345,
            3 * LARGE,
            LARGE / 2,
            7 * LARGE + 1,
            64,
        ];
        unsafe {
            let mut l = Layout::from_size_align(sizes[0], 8).unwrap();
            let mut p = a.alloc_zeroed(l);
            assert!(!p.is_null());
            assert!((0..l.size()).all(|i| *p.add(i) == 0));
            for i in 0..l.size() {
                *p.add(i) = pattern(i);
            }
            for &new in &sizes[1..] {
                let q = a.realloc(p, l, new);
                assert!(!q.is_null(), "realloc to {new}");
                let kept = l.size().min(new);
                assert!(
                    (0..kept).all(|i| *q.add(i) == pattern(i)),
                    "{} -> {new}",
                    l.size()
                );
                for i in 0..new {
                    *q.add(i) = pattern(i);
                }
                (p, l) = (q, Layout::from_size_align(new, 8).unwrap());
            }
            a.dealloc(p, l);
            // A large zeroed block, written and freed, then another: zeros again.
            for _ in 0..2 {
                let l = Layout::from_size_align(2 * LARGE + 5, 64).unwrap();
                let p = a.alloc_zeroed(l);
                assert!(!p.is_null() && (p as usize).is_multiple_of(64));
                assert!((0..l.size()).step_by(997).all(|i| *p.add(i) == 0));
                std::ptr::write_bytes(p, 0xA5, l.size());
                a.dealloc(p, l);
            }
        }
    }

    /// Blocks of sizes that are not whole huge pages, grown one after another beside other
    /// mappings (the growth of a `Vec` collected from an iterator): each growth keeps the
    /// contents. (Advice on part of a mapping splits it, and a mapping split in two
    /// cannot be resized as one: the first version failed here.)
    #[test]
    fn odd_sized_blocks_grow_in_place_or_moved() {
        let a = HugePageAlloc;
        let mut v: Vec<(u32, u32)> = Vec::new();
        for i in 0..3_000_000u32 {
            v.push((i, i ^ 0x5555));
        }
        assert!((0..v.len())
            .step_by(4099)
            .all(|i| v[i] == (i as u32, i as u32 ^ 0x5555)));
        unsafe {
            let mut blocks = Vec::new();
            for &size in &[6_946_816usize, 4_200_001, 5 * LARGE / 2 + 4096] {
                let l = Layout::from_size_align(size, 8).unwrap();
                let p = a.alloc(l);
                assert!(!p.is_null());
                std::ptr::write_bytes(p, 7, size);
                let q = a.realloc(p, l, 2 * size);
                assert!(!q.is_null(), "growing {size}");
                assert!((0..size).step_by(1021).all(|i| *q.add(i) == 7));
                blocks.push((q, Layout::from_size_align(2 * size, 8).unwrap()));
            }
            for (q, l) in blocks {
                a.dealloc(q, l);
            }
        }
    }

    /// An alignment larger than a page goes to the system allocator and is honoured.
    #[test]
    fn over_aligned_large_blocks_are_aligned() {
        let a = HugePageAlloc;
        let l = Layout::from_size_align(LARGE, 1 << 16).unwrap();
        unsafe {
            let p = a.alloc(l);
            assert!(!p.is_null() && (p as usize).is_multiple_of(1 << 16));
            std::ptr::write_bytes(p, 1, l.size());
            a.dealloc(p, l);
        }
    }
}
