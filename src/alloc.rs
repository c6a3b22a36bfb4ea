//! The `frfup` binary's allocator: the system allocator, except that while a
//! UFF file is read ([`huge_pages_for_reading`]) blocks of 32 KiB to 16 MiB
//! are carved from 64 MiB regions advised for transparent huge pages.
//!
//! Reading decodes tens of MB into fresh memory. With 4 KiB pages each page
//! costs a fault: 7,700 faults for a 13 MB 58b file, 28 ms of kernel time
//! against 5 ms of parsing. A region is faulted in 2 MiB at a time. Only
//! allocations made inside the reading scope use regions, so solvers and long
//! batch runs keep the system allocator's reuse of freed memory. A region is
//! unmapped when its last block is freed; its blocks are never reused one by
//! one (a bump allocator), which costs nothing for decoded data that lives as
//! long as the file's records.
//!
//! Huge pages are advised for no more of the regions than the scope expects
//! to fill ([`huge_pages_for_reading`] takes the file's size): a huge page
//! is faulted whole, so the one past the data would be up to 2 MiB of zeros
//! counted in the peak memory (1.5 MiB of 14 MiB for the 13 MB 58b benchmark
//! file). The rest of a region is advised `MADV_NOHUGEPAGE` (also when THP
//! is `always`) and faulted 4 KiB at a time.
//!
//! Elsewhere than Linux, or if `mmap` fails, everything goes to the system
//! allocator.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::UnsafeCell;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// Install with `#[global_allocator]` in a binary.
pub struct FrfupAllocator;

/// Size of a region (a multiple of [`HUGE_PAGE`]).
const REGION: usize = 64 << 20;
/// Transparent huge page size on x86-64 and aarch64 (4 KiB base pages).
const HUGE_PAGE: usize = 2 << 20;
/// Smallest block served from a region.
const MIN_BLOCK: usize = 32 << 10;
/// Largest block served from a region (larger ones are mmap'd by the system).
const MAX_BLOCK: usize = 16 << 20;
const MAX_REGIONS: usize = 64;

/// Nesting depth of [`huge_pages_for_reading`] scopes (all threads).
static READING: AtomicUsize = AtomicUsize::new(0);
/// Regions currently mapped (fast path of `dealloc`).
static MAPPED: AtomicUsize = AtomicUsize::new(0);
static LOCK: AtomicBool = AtomicBool::new(false);

#[derive(Clone, Copy)]
struct Region {
    /// Start of the mapping (0: free slot) and its length.
    map: usize,
    map_len: usize,
    /// First huge-page-aligned byte: blocks live in [base, base + REGION).
    base: usize,
    /// Bytes from `base` advised for huge pages (whole huge pages).
    huge: usize,
    live: usize,
}

struct State {
    regions: [Region; MAX_REGIONS],
    /// Bytes of regions still to be mapped that may be advised for huge
    /// pages (set by [`huge_pages_for_reading`]).
    huge_budget: usize,
    /// The region blocks are bumped from, and its first free offset.
    current: Option<usize>,
    top: usize,
    /// Offset of the current region from which its memory was never handed
    /// out since it was mapped: still zero (`top` goes back to 0 when the
    /// region's blocks are all freed, `clean` does not).
    clean: usize,
}

struct Shared(UnsafeCell<State>);
// SAFETY: every access goes through `with_state`, which holds `LOCK`.
unsafe impl Sync for Shared {}

static STATE: Shared = Shared(UnsafeCell::new(State::empty(usize::MAX)));

fn with_state<R>(f: impl FnOnce(&mut State) -> R) -> R {
    while LOCK
        .compare_exchange_weak(false, true, Ordering::Acquire, Ordering::Relaxed)
        .is_err()
    {
        std::hint::spin_loop();
    }
    // SAFETY: the lock is held; `f` does not allocate.
    let r = f(unsafe { &mut *STATE.0.get() });
    LOCK.store(false, Ordering::Release);
    r
}

/// Runs `f` with large allocations (of every thread) in regions, of which
/// the first `expected_bytes` (rounded down to whole huge pages) are advised
/// for huge pages: what the read is expected to fill. The latest scope's
/// figure applies; `usize::MAX` advises every region whole.
pub fn huge_pages_for_reading<R>(expected_bytes: usize, f: impl FnOnce() -> R) -> R {
    struct Scope;
    impl Drop for Scope {
        fn drop(&mut self) {
            READING.fetch_sub(1, Ordering::Relaxed);
        }
    }
    with_state(|s| {
        // Pages of the current region past its top are not faulted yet.
        let ahead = s
            .current
            .map_or(0, |c| s.regions[c].huge.saturating_sub(s.top));
        s.huge_budget = expected_bytes.saturating_sub(ahead);
    });
    READING.fetch_add(1, Ordering::Relaxed);
    let _scope = Scope;
    f()
}

fn eligible(layout: &Layout) -> bool {
    cfg!(target_os = "linux")
        && (MIN_BLOCK..=MAX_BLOCK).contains(&layout.size())
        && layout.align() <= 4096
}

/// Maps a region whose first `huge` bytes (a multiple of [`HUGE_PAGE`], at
/// most [`REGION`]) are advised for huge pages and the rest not.
#[cfg(target_os = "linux")]
fn map_region(huge: usize) -> Option<(usize, usize, usize)> {
    let len = REGION + HUGE_PAGE;
    // SAFETY: an anonymous private mapping; the result is checked.
    let p = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            len,
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_PRIVATE | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if p == libc::MAP_FAILED {
        return None;
    }
    let map = p as usize;
    let base = (map + HUGE_PAGE - 1) & !(HUGE_PAGE - 1);
    // SAFETY: [base, base + REGION) lies inside the mapping. Advice only.
    unsafe {
        if huge > 0 {
            libc::madvise(base as *mut libc::c_void, huge, libc::MADV_HUGEPAGE);
        }
        if huge < REGION {
            libc::madvise(
                (base + huge) as *mut libc::c_void,
                REGION - huge,
                libc::MADV_NOHUGEPAGE,
            );
        }
    }
    Some((map, len, base))
}

#[cfg(not(target_os = "linux"))]
fn map_region(_huge: usize) -> Option<(usize, usize, usize)> {
    None
}

fn unmap(r: &Region) {
    #[cfg(target_os = "linux")]
    // SAFETY: the region's own mapping, with no live blocks.
    unsafe {
        libc::munmap(r.map as *mut libc::c_void, r.map_len);
    }
    #[cfg(not(target_os = "linux"))]
    let _ = r;
}

impl State {
    /// No region mapped; `huge_budget` bytes may be advised for huge pages.
    const fn empty(huge_budget: usize) -> State {
        State {
            regions: [Region {
                map: 0,
                map_len: 0,
                base: 0,
                huge: 0,
                live: 0,
            }; MAX_REGIONS],
            huge_budget,
            current: None,
            top: 0,
            clean: 0,
        }
    }

    /// A block and how many of its first bytes may be dirty (handed out
    /// before): the rest are still zero.
    fn bump(&mut self, layout: &Layout) -> Option<(usize, usize)> {
        let c = self.current?;
        let r = &mut self.regions[c];
        let align = layout.align().max(16);
        let start = (r.base + self.top + align - 1) & !(align - 1);
        if start + layout.size() > r.base + REGION {
            return None;
        }
        let dirty = self.clean.saturating_sub(start - r.base).min(layout.size());
        self.top = start + layout.size() - r.base;
        self.clean = self.clean.max(self.top);
        r.live += 1;
        Some((start, dirty))
    }

    /// A region block, and how many of its first bytes may be dirty.
    fn alloc(&mut self, layout: &Layout) -> Option<(usize, usize)> {
        if let Some(p) = self.bump(layout) {
            return Some(p);
        }
        let slot = self.regions.iter().position(|r| r.map == 0)?;
        let huge = self.huge_budget.min(REGION) & !(HUGE_PAGE - 1);
        let (map, map_len, base) = map_region(huge)?;
        self.huge_budget -= huge;
        if let Some(c) = self.current {
            if self.regions[c].live == 0 {
                unmap(&self.regions[c]);
                self.regions[c].map = 0;
                MAPPED.fetch_sub(1, Ordering::Relaxed);
            }
        }
        self.regions[slot] = Region {
            map,
            map_len,
            base,
            huge,
            live: 0,
        };
        MAPPED.fetch_add(1, Ordering::Relaxed);
        self.current = Some(slot);
        self.top = 0;
        self.clean = 0;
        self.bump(layout)
    }

    fn region_of(&self, p: usize) -> Option<usize> {
        self.regions
            .iter()
            .position(|r| r.map != 0 && p >= r.base && p < r.base + REGION)
    }

    /// Frees a region block; false if `p` is not in a region.
    fn free(&mut self, p: usize) -> bool {
        let Some(i) = self.region_of(p) else {
            return false;
        };
        let r = &mut self.regions[i];
        r.live -= 1;
        if r.live == 0 {
            if self.current == Some(i) {
                self.top = 0;
            } else {
                unmap(r);
                r.map = 0;
                MAPPED.fetch_sub(1, Ordering::Relaxed);
            }
        }
        true
    }
}

// SAFETY: blocks come either from `System` or from a region mapping that
// stays mapped while any of its blocks is live; `dealloc` and `realloc` tell
// the two apart by address.
unsafe impl GlobalAlloc for FrfupAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if READING.load(Ordering::Relaxed) > 0 && eligible(&layout) {
            if let Some((p, _)) = with_state(|s| s.alloc(&layout)) {
                return p as *mut u8;
            }
        }
        // SAFETY: forwarded as received.
        unsafe { System.alloc(layout) }
    }

    /// Zeroes only what a region block may hold from an earlier block: the
    /// rest of a fresh mapping is zero already (`vec![0.0; n]`, which the
    /// 58b reader reads data into, costs no pass over the memory).
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        if READING.load(Ordering::Relaxed) > 0 && eligible(&layout) {
            if let Some((p, dirty)) = with_state(|s| s.alloc(&layout)) {
                // SAFETY: the first `dirty` bytes of the new block.
                unsafe { std::ptr::write_bytes(p as *mut u8, 0, dirty) };
                return p as *mut u8;
            }
        }
        // SAFETY: forwarded as received.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        if MAPPED.load(Ordering::Relaxed) > 0
            && eligible(&layout)
            && with_state(|s| s.free(ptr as usize))
        {
            return;
        }
        // SAFETY: not a region block, so it came from System.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        // SAFETY: the caller guarantees a valid layout for `new_size`.
        let new_layout = unsafe { Layout::from_size_align_unchecked(new_size, layout.align()) };
        let in_region = MAPPED.load(Ordering::Relaxed) > 0
            && eligible(&layout)
            && with_state(|s| s.region_of(ptr as usize).is_some());
        let to_region = READING.load(Ordering::Relaxed) > 0 && eligible(&new_layout);
        if !in_region && !to_region {
            // SAFETY: a System block, forwarded as received.
            return unsafe { System.realloc(ptr, layout, new_size) };
        }
        // SAFETY: `self.alloc`/`self.dealloc` pair up as above; the copy
        // stays within both blocks.
        unsafe {
            let new = self.alloc(new_layout);
            if !new.is_null() {
                std::ptr::copy_nonoverlapping(ptr, new, layout.size().min(new_size));
                self.dealloc(ptr, layout);
            }
            new
        }
    }
}

#[cfg(all(test, target_os = "linux"))]
mod tests {
    use super::*;

    /// VmFlags of the smaps entry of this process's mapping starting at `start`.
    fn vm_flags(start: usize) -> String {
        let smaps = std::fs::read_to_string("/proc/self/smaps").unwrap();
        let head = format!("{start:x}-");
        let mut lines = smaps.lines().skip_while(|l| !l.starts_with(&head));
        assert!(lines.next().is_some(), "no mapping at {start:x}");
        lines
            .find_map(|l| l.strip_prefix("VmFlags:"))
            .expect("VmFlags line")
            .to_string()
    }

    /// Only the expected bytes, in whole huge pages, are advised for huge
    /// pages; the rest of the region is advised against them (so the page
    /// past the data is not faulted whole, even when THP is `always`), and a
    /// later region gets what is left of the budget.
    #[test]
    fn huge_pages_only_as_far_as_expected() {
        let mut s = State::empty(3 * HUGE_PAGE + HUGE_PAGE / 2);
        let block = Layout::from_size_align(MAX_BLOCK, 16).unwrap();
        let mut blocks = Vec::new();
        // 64 MiB regions of 16 MiB blocks: the fifth block opens a second region.
        for _ in 0..5 {
            blocks.push(s.alloc(&block).expect("region block").0);
        }
        let first = s.region_of(blocks[0]).unwrap();
        let second = s.region_of(blocks[4]).unwrap();
        assert_ne!(first, second);
        let (r1, r2) = (s.regions[first], s.regions[second]);
        assert_eq!(r1.huge, 3 * HUGE_PAGE);
        assert_eq!(r2.huge, 0, "budget rounds down to whole huge pages");
        assert!(vm_flags(r1.base).contains(" hg"), "{}", vm_flags(r1.base));
        assert!(vm_flags(r1.base + r1.huge).contains(" nh"));
        assert!(vm_flags(r2.base).contains(" nh"));
        for p in blocks {
            assert!(s.free(p));
        }
        let current = s.current.unwrap();
        unmap(&s.regions[current]);
        MAPPED.fetch_sub(1, Ordering::Relaxed);
    }

    /// Blocks made while reading come from regions, keep their contents
    /// through realloc, respect alignment, and the region is unmapped when its
    /// last block goes (the current region is kept for reuse).
    #[test]
    fn reading_scope_uses_regions_and_frees_them() {
        let a = FrfupAllocator;
        let big = Layout::from_size_align(100_000, 64).unwrap();
        let small = Layout::from_size_align(100, 8).unwrap();
        unsafe {
            // Outside the scope: the system allocator.
            let p = a.alloc(big);
            assert!(!with_state(|s| s.region_of(p as usize).is_some()));
            a.dealloc(p, big);
            let (p, q, s) =
                huge_pages_for_reading(usize::MAX, || (a.alloc(big), a.alloc(big), a.alloc(small)));
            assert!(with_state(|st| st.region_of(p as usize).is_some()));
            assert!(with_state(|st| st.region_of(q as usize).is_some()));
            assert!(!with_state(|st| st.region_of(s as usize).is_some()));
            assert_eq!(p as usize % 64, 0);
            assert!(q as usize >= p as usize + 100_000);
            for i in 0..100_000 {
                *p.add(i) = (i % 251) as u8;
            }
            // Growing a region block outside the scope moves it to System.
            let r = a.realloc(p, big, 300_000);
            assert!(!with_state(|st| st.region_of(r as usize).is_some()));
            for i in 0..100_000 {
                assert_eq!(*r.add(i), (i % 251) as u8);
            }
            a.dealloc(r, Layout::from_size_align(300_000, 64).unwrap());
            a.dealloc(q, big);
            a.dealloc(s, small);
            assert_eq!(with_state(|st| st.top), 0, "current region reset");
        }
    }

    /// A block is reported dirty only as far as earlier blocks of its region
    /// reached (the region's memory above that was never handed out), so
    /// `alloc_zeroed` clears exactly what a freed block may have written.
    #[test]
    fn zeroed_blocks_clear_only_reused_memory() {
        let mut s = State::empty(0);
        let l = Layout::from_size_align(100_000, 16).unwrap();
        let (p, d) = s.alloc(&l).expect("region block");
        assert_eq!(d, 0);
        let (q, d) = s.alloc(&l).expect("region block");
        assert_eq!(d, 0);
        assert!(s.free(p) && s.free(q));
        assert_eq!(s.top, 0, "current region reset");
        let big = Layout::from_size_align(250_000, 16).unwrap();
        let (r, d) = s.alloc(&big).expect("region block");
        assert_eq!(r, p);
        assert_eq!(d, q + 100_000 - p, "dirty up to the end of the old blocks");
        let (t, d) = s.alloc(&l).expect("region block");
        assert!(t >= r + 250_000);
        assert_eq!(d, 0, "past the old blocks: fresh");
        assert!(s.free(r) && s.free(t));
        let current = s.current.unwrap();
        unmap(&s.regions[current]);
        MAPPED.fetch_sub(1, Ordering::Relaxed);
    }
}
