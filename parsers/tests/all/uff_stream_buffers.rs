//! The one-thread streaming reader fills two buffers in turn, whatever the
//! file size: the parsed chunk's buffer is the next one filled. (Under the
//! `frfup` binary's bump allocator, which never reuses a freed block, a fresh
//! buffer per chunk made the peak memory the file plus the decoded data.)
//!
//! The allocator below (the global allocator of this test binary) counts, on
//! the calling thread only, the allocations of exactly one chunk (an odd size
//! nothing else asks for), larger than any dataset of the file (a buffer
//! grown for a bigger dataset is freed by design). The count is per thread,
//! so the other tests of the binary, each on its own thread, do not disturb it;
//! for every other allocation it is the system allocator.

use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;
use std::path::PathBuf;

use frfup_parsers::uff;

const CHUNK: usize = 40_009;

thread_local! {
    static CHUNK_BUFFERS: Cell<usize> = const { Cell::new(0) };
}

struct CountingChunks;

// SAFETY: defers to the system allocator; only counts.
unsafe impl GlobalAlloc for CountingChunks {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        if layout.size() == CHUNK {
            let _ = CHUNK_BUFFERS.try_with(|c| c.set(c.get() + 1));
        }
        // SAFETY: same layout contract as the caller's.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from `System.alloc` with this layout.
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static ALLOCATOR: CountingChunks = CountingChunks;

#[test]
fn one_thread_reader_recycles_its_buffer() {
    let path = PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../fixtures/uff-real/uffl-jl/dataset58_case7_ascii.unv"
    ));
    let one = std::fs::read(&path).expect("fixture");
    let bytes = one.repeat(200);
    assert!(bytes.len() / CHUNK >= 100, "{} bytes", bytes.len());
    let before = CHUNK_BUFFERS.with(Cell::get);
    let file = uff::parse_reader_with(&bytes[..], CHUNK, 1).expect("parses");
    let buffers = CHUNK_BUFFERS.with(Cell::get) - before;
    assert_eq!(file, uff::parse(&bytes).expect("parses"));
    assert!(
        buffers <= 2,
        "{buffers} chunk buffers for {} chunks",
        bytes.len() / CHUNK
    );
}
