//! Streaming reader: parses a UFF file from any [`Read`] in bounded memory.
//!
//! The file is read in chunks (256 KiB) into a small pool of recycled buffers.
//! The [`Splitter`] cuts each buffer after its last complete dataset
//! (`    -1` ... `    -1`; for 58b the header's byte count decides where the
//! binary data end, whatever bytes they hold); those datasets go as one job,
//! with their buffer, to a bounded queue served by one worker per core; the
//! unfinished tail is copied to the next buffer. A worker parses its job's
//! datasets, sends the results and gives the buffer back, so the text of a
//! parsed dataset does not outlive it: peak memory is the decoded data plus
//! (workers + 2) buffers. A dataset larger than a chunk grows its buffer
//! (doubling) until it fits.
//!
//! Positions in a buffer are relative to it; jobs carry the file offset of
//! their buffer (`base`) and errors are moved by it, so line numbers and byte
//! offsets are those of the file. Results are put back in file order, and the
//! first error in file order is returned: the outcome equals [`super::parse`]
//! on the whole file, whatever the chunk size and thread count.

use std::io::Read;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{mpsc, Arc, Mutex};

use super::split::{Block, Splitter, Step};
use super::{parse_block, BlockResult, UffError, UffFile};

/// Bytes read at a time. A quarter MiB: the buffer a worker decodes is still
/// in its core's L2 cache from the read, and (workers + 2) buffers add
/// 1 MiB to the peak memory. On the 13 MB 58b benchmark file, 1 MiB chunks
/// peaked at 23.6 MB instead of 19.7 MB and read no faster (6.7 against
/// 6.4 ms); 64–128 KiB read slower (7.0–7.4 ms).
pub(crate) const CHUNK: usize = 1 << 18;

/// Datasets of one buffer, sent to a worker.
struct Job {
    seq: usize,
    /// File offset of `buf[0]`.
    base: usize,
    buf: Vec<u8>,
    blocks: Vec<Block>,
}

/// `e` with its byte offset moved from buffer to file position.
fn rebase(mut e: UffError, base: usize) -> UffError {
    e.byte_offset += base;
    e
}

/// Parses the blocks of a job in order, up to the first error (which lowers
/// `stop` to the job's sequence number: later jobs are not needed).
fn run_job(job: &Job, stop: &AtomicUsize) -> Vec<BlockResult> {
    let mut out = Vec::with_capacity(job.blocks.len());
    for block in &job.blocks {
        let r = parse_block(&job.buf, block).map_err(|e| rebase(e, job.base));
        let failed = r.is_err();
        out.push(r);
        if failed {
            stop.fetch_min(job.seq, Ordering::Relaxed);
            break;
        }
    }
    out
}

/// What the producer ends with.
struct Produced {
    jobs: usize,
    notes: Vec<String>,
    /// A split or read error, after every dispatched block in file order.
    failure: Option<UffError>,
}

/// Reads `r` chunk by chunk, splits, and hands jobs to `dispatch` in order.
///
/// Buffers come back from the workers with their old contents: `buf[..filled]`
/// holds the unparsed bytes and the rest is initialised scratch, so a read
/// goes straight into it without zeroing it first (13 MB of memset for a
/// 13 MB file otherwise).
fn produce<R: Read>(
    mut r: R,
    chunk: usize,
    stop: &AtomicUsize,
    mut get_buffer: impl FnMut() -> Vec<u8>,
    mut dispatch: impl FnMut(Job) -> bool,
) -> Produced {
    let chunk = chunk.max(1);
    let mut splitter = Splitter::default();
    let mut buf = get_buffer();
    let mut filled = 0usize;
    let (mut base, mut eof, mut want, mut jobs) = (0usize, false, chunk, 0usize);
    let failure = loop {
        if stop.load(Ordering::Relaxed) != usize::MAX {
            // A dispatched dataset failed: it is the first error in file order.
            break None;
        }
        if !eof && filled < want {
            if buf.len() < want {
                buf.resize(want, 0);
            }
            let mut error = None;
            while filled < want {
                match r.read(&mut buf[filled..want]) {
                    Ok(0) => {
                        eof = true;
                        break;
                    }
                    Ok(n) => filled += n,
                    Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                    Err(e) => {
                        error = Some(e);
                        break;
                    }
                }
            }
            if let Some(e) = error {
                break Some(UffError {
                    line: None,
                    byte_offset: base + filled,
                    dataset_index: None,
                    dataset_number: None,
                    message: format!("read error: {e}"),
                });
            }
        }
        let mut blocks = Vec::new();
        let mut failure = None;
        let done = loop {
            match splitter.next(&buf[..filled], eof) {
                Ok(Step::Block(b)) => blocks.push(b),
                Ok(Step::NeedMore) => break eof, // never at eof; stop rather than spin
                Ok(Step::End) => break true,
                Err(e) => {
                    failure = Some(e); // already a file offset
                    break true;
                }
            }
        };
        let consumed = splitter.pos();
        if !blocks.is_empty() {
            let mut next = if done { Vec::new() } else { get_buffer() };
            let tail = filled - consumed;
            if !done {
                if next.len() < tail {
                    next.resize(tail, 0);
                }
                next[..tail].copy_from_slice(&buf[consumed..filled]);
            }
            // The job sees exactly its bytes.
            buf.truncate(filled);
            let job = Job {
                seq: jobs,
                base,
                buf: std::mem::replace(&mut buf, next),
                blocks,
            };
            filled = if done { 0 } else { tail };
            jobs += 1;
            if !dispatch(job) {
                break failure;
            }
        } else if consumed > 0 && !done {
            buf.copy_within(consumed..filled, 0);
            filled -= consumed;
        }
        if done {
            break failure;
        }
        base += consumed;
        splitter.consume(consumed);
        // Room for more: a chunk, or double when a dataset outgrows the buffer.
        want = if filled < chunk / 2 {
            chunk
        } else {
            (2 * filled).max(chunk)
        };
    };
    Produced {
        jobs,
        notes: splitter.notes,
        failure,
    }
}

/// Puts the per-job results together in file order.
fn assemble(
    produced: Produced,
    mut results: Vec<Option<Vec<BlockResult>>>,
) -> Result<UffFile, UffError> {
    let mut file = UffFile {
        datasets: Vec::new(),
        notes: produced.notes,
    };
    let mut block_notes = Vec::new();
    for (seq, slot) in results.iter_mut().enumerate().take(produced.jobs) {
        let Some(rs) = slot.take() else {
            return Err(UffError {
                line: None,
                byte_offset: 0,
                dataset_index: None,
                dataset_number: None,
                message: format!("internal error: chunk {seq} was not parsed"),
            });
        };
        for r in rs {
            let (dataset, notes) = r?;
            file.datasets.push(dataset);
            block_notes.extend(notes);
        }
    }
    if let Some(e) = produced.failure {
        return Err(e);
    }
    file.notes.extend(block_notes);
    Ok(file)
}

/// Worker threads for `parse_reader`: one per core, at most 16.
pub(crate) fn default_threads() -> usize {
    std::thread::available_parallelism()
        .map_or(1, |n| n.get())
        .clamp(1, 16)
}

/// Streams `r` with buffers of `chunk` bytes and `threads` workers (1: all
/// on the calling thread).
pub(crate) fn parse_reader_with<R: Read>(
    r: R,
    chunk: usize,
    threads: usize,
) -> Result<UffFile, UffError> {
    let stop = AtomicUsize::new(usize::MAX);
    if threads <= 1 {
        let mut results = Vec::new();
        // The parsed job's buffer is the next one to fill: two buffers in all.
        let spare = std::cell::Cell::new(None::<Vec<u8>>);
        let produced = produce(
            r,
            chunk,
            &stop,
            || spare.take().unwrap_or_else(|| Vec::with_capacity(chunk)),
            |job| {
                results.push(Some(run_job(&job, &stop)));
                if job.buf.capacity() <= 4 * chunk {
                    spare.set(Some(job.buf));
                }
                true
            },
        );
        return assemble(produced, results);
    }
    // Buffers in use at most: one per worker, one filling, one for the tail.
    let max_buffers = threads + 2;
    let (job_tx, job_rx) = mpsc::sync_channel::<Job>(threads);
    let job_rx = Arc::new(Mutex::new(job_rx));
    let (res_tx, res_rx) = mpsc::channel::<(usize, Vec<BlockResult>)>();
    let (free_tx, free_rx) = mpsc::channel::<Vec<u8>>();
    std::thread::scope(|scope| {
        for _ in 0..threads {
            let (job_rx, res_tx, free_tx, stop) =
                (Arc::clone(&job_rx), res_tx.clone(), free_tx.clone(), &stop);
            scope.spawn(move || loop {
                let job = match job_rx.lock() {
                    Ok(rx) => rx.recv(),
                    Err(_) => break,
                };
                let Ok(job) = job else { break };
                let results = if job.seq > stop.load(Ordering::Relaxed) {
                    Vec::new() // after the first error: not needed
                } else {
                    run_job(&job, stop)
                };
                if res_tx.send((job.seq, results)).is_err() {
                    break;
                }
                // Give back a normal-sized buffer with its (initialised)
                // contents as scratch; a big dataset's buffer is freed.
                let buf = if job.buf.capacity() <= 4 * chunk {
                    job.buf
                } else {
                    Vec::new()
                };
                let _ = free_tx.send(buf);
            });
        }
        drop(job_rx);
        drop(res_tx);
        drop(free_tx);
        let mut allocated = 0usize;
        let produced = produce(
            r,
            chunk,
            &stop,
            || {
                if let Ok(b) = free_rx.try_recv() {
                    return b;
                }
                if allocated < max_buffers {
                    allocated += 1;
                    return Vec::with_capacity(chunk);
                }
                free_rx.recv().unwrap_or_default()
            },
            |job| job_tx.send(job).is_ok(),
        );
        drop(job_tx);
        let mut results: Vec<Option<Vec<BlockResult>>> = (0..produced.jobs).map(|_| None).collect();
        for (seq, rs) in res_rx {
            if let Some(slot) = results.get_mut(seq) {
                *slot = Some(rs);
            }
        }
        // Jobs skipped after an error have empty results; `assemble` stops at the error first.
        assemble(produced, results)
    })
}
