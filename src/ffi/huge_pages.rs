//! The global allocator: the system's, except that large blocks are mapped straight from
//! the kernel and marked for transparent huge pages (`madvise(MADV_HUGEPAGE)`).
//!
//! Why: a fairing run allocates and frees blocks of hundreds of megabytes at every Newton
//! step (the Hessians' partial sums, the multigrid levels' matrices). glibc maps each such
//! block afresh and the kernel faults it in 4 KiB at a time, where it gives huge pages only
//! to memory that asks for them (`enabled = madvise`, as on the machine measured). On the
//! 223 487-vertex Catmull–Clark junction (`surfkit fair t3r4.obj -o o.obj --surface
//! catmull-clark --method multilevel`, back to back, 2026-11-29): 2.4 million page faults
//! against 37.4 million, 69.9 s of system time against 106.8 s, the Hessian passes 177.0 s
//! against 202.2 s, the run 496.1 s against 521.3 s, at a peak 0.25 GiB higher (4.03 GiB).
//! Small blocks stay with the system allocator, which reuses them in place.

use std::alloc::{GlobalAlloc, Layout, System};
use std::ptr;

/// Blocks of at least this many bytes are mapped directly: those glibc maps afresh for
/// every allocation anyway (its threshold for mapping a block moves up to 32 MiB as blocks
/// are freed, so that smaller ones are reused from its heap). Mapping the conjugate
/// gradients' 5 MB vectors afresh too (a threshold of 4 MiB) made the 223k junction's run
/// 12 % slower (570.3 s against 508.5 s, its CG 203.9 s against 136.9 s, 2026-11-29).
const MAPPED_BYTES: usize = 32 << 20;

/// The alignment a fresh mapping has (the base page).
const PAGE_BYTES: usize = 4096;

/// [`System`], with blocks of [`MAPPED_BYTES`] and more on their own huge-page mappings.
pub struct HugePageAllocator;

/// Whether a block of `layout` gets its own mapping: the size decides, so that `dealloc`
/// and `realloc`, which get the same layout, know where a block came from.
fn mapped(layout: Layout) -> bool {
    layout.size() >= MAPPED_BYTES && layout.align() <= PAGE_BYTES
}

/// A fresh anonymous mapping of `size` bytes (zeroed by the kernel), advised onto huge
/// pages; null if the kernel refuses it.
unsafe fn map(size: usize) -> *mut u8 {
    let block = libc::mmap(
        ptr::null_mut(),
        size,
        libc::PROT_READ | libc::PROT_WRITE,
        libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
        -1,
        0,
    );
    if block == libc::MAP_FAILED {
        return ptr::null_mut();
    }
    // Advice only: a kernel without transparent huge pages refuses it, and the block
    // stays on base pages.
    libc::madvise(block, size, libc::MADV_HUGEPAGE);
    block.cast()
}

// SAFETY: every block is either the system allocator's, handled by it, or a whole mapping
// of at least `layout.size()` bytes at page (≥ `layout.align()`) alignment, unmapped once
// in `dealloc`; `mapped` gives the same answer for a block's allocation and its release.
unsafe impl GlobalAlloc for HugePageAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if mapped(layout) {
            map(layout.size())
        } else {
            System.alloc(layout)
        }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if mapped(layout) {
            map(layout.size())
        } else {
            System.alloc_zeroed(layout)
        }
    }

    unsafe fn dealloc(&self, block: *mut u8, layout: Layout) {
        if mapped(layout) {
            libc::munmap(block.cast(), layout.size());
        } else {
            System.dealloc(block, layout)
        }
    }

    unsafe fn realloc(&self, block: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        let new_layout = Layout::from_size_align_unchecked(new_size, layout.align());
        match (mapped(layout), mapped(new_layout)) {
            (false, false) => System.realloc(block, layout, new_size),
            // The kernel moves the pages (no copy); the mapping keeps its advice.
            (true, true) => {
                let moved =
                    libc::mremap(block.cast(), layout.size(), new_size, libc::MREMAP_MAYMOVE);
                if moved == libc::MAP_FAILED {
                    ptr::null_mut()
                } else {
                    moved.cast()
                }
            }
            _ => {
                let moved = self.alloc(new_layout);
                if !moved.is_null() {
                    ptr::copy_nonoverlapping(block, moved, layout.size().min(new_size));
                    self.dealloc(block, layout);
                }
                moved
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A block through every path of the allocator: small, grown past the threshold
    /// (copied into a mapping), grown again (remapped), shrunk back (copied out).
    #[test]
    fn a_block_keeps_its_contents_through_every_path() {
        let pattern = |n: usize| (0..n).map(|i| (i % 251) as u8).collect::<Vec<u8>>();
        let mut v = pattern(1000);
        for n in [MAPPED_BYTES + 1, 3 * MAPPED_BYTES, MAPPED_BYTES - 1, 10] {
            if n > v.len() {
                v.reserve_exact(n - v.len());
                v.extend((v.len()..n).map(|i| (i % 251) as u8));
            } else {
                v.truncate(n);
                v.shrink_to_fit();
            }
            assert_eq!(v.len(), n);
            assert_eq!(v, pattern(n));
        }
    }

    /// A large zeroed block is zero even where a freed block of the same size, written
    /// all over, came just before it (a mapping is not handed out again dirty).
    #[test]
    fn a_large_zeroed_block_is_zero_after_a_dirty_one_is_freed() {
        // `black_box`: the optimizer knows the allocator's calls, and would drop an
        // allocation no one reads and fold the reads of a zeroed one to zero.
        drop(std::hint::black_box(vec![u64::MAX; MAPPED_BYTES / 8 + 1]));
        let v = std::hint::black_box(vec![0u64; MAPPED_BYTES / 8 + 1]);
        assert!(v.iter().all(|&x| x == 0));
    }

    /// The address range of a /proc/self/smaps mapping header (`start-end perms …`), `None`
    /// for the mapping's detail lines.
    fn mapping_range(line: &str) -> Option<std::ops::Range<usize>> {
        let (start, end) = line.split_once(' ')?.0.split_once('-')?;
        Some(usize::from_str_radix(start, 16).ok()?..usize::from_str_radix(end, 16).ok()?)
    }

    /// The `VmFlags` of the mapping that holds `address`.
    fn flags_of(address: usize) -> Option<String> {
        let smaps = std::fs::read_to_string("/proc/self/smaps").ok()?;
        let mut inside = false;
        for line in smaps.lines() {
            if let Some(range) = mapping_range(line) {
                inside = range.contains(&address);
            } else if let Some(flags) = line.strip_prefix("VmFlags:").filter(|_| inside) {
                return Some(flags.trim().to_string());
            }
        }
        None
    }

    /// The kernel's record of a large block's mapping carries the advice (`hg` among its
    /// `VmFlags` in /proc/self/smaps), and a small block's does not.
    #[test]
    fn a_large_block_is_advised_onto_huge_pages() {
        let large = vec![1u8; MAPPED_BYTES];
        let small = vec![1u8; 4096];
        let large_flags = flags_of(large.as_ptr() as usize).expect("the block's mapping");
        let small_flags = flags_of(small.as_ptr() as usize).expect("the heap's mapping");
        assert!(large_flags.split(' ').any(|f| f == "hg"), "{large_flags}");
        assert!(!small_flags.split(' ').any(|f| f == "hg"), "{small_flags}");
    }
}
