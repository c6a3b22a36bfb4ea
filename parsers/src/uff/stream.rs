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
//! The data section of a 58b dataset of an even function, whose byte count
//! the header declares, is read straight into the dataset's values when it
//! reaches past the buffer: the part in the buffer is copied, the rest read
//! into the values' memory, so its bytes are copied once, by the kernel,
//! and the buffers hold headers (the next read is [`HEAD`] bytes). Such a
//! dataset is parsed by the reading thread (its header and a check of its
//! values), and workers start only when a job is handed over.
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
use super::{function58, parse_block, BlockResult, Ordinate, UffError, UffFile};

/// Bytes read at a time. A quarter MiB: the buffer a worker decodes is still
/// in its core's L2 cache from the read, and (workers + 2) buffers add
/// 1 MiB to the peak memory. On the 13 MB 58b benchmark file, 1 MiB chunks
/// peaked at 23.6 MB instead of 19.7 MB and read no faster (6.7 against
/// 6.4 ms); 64–128 KiB read slower (7.0–7.4 ms).
pub(crate) const CHUNK: usize = 1 << 18;

/// After a 58b data section read straight into its values, the next read
/// is this small (or `chunk`, if smaller): the closing `-1`, the next
/// header and the start of the next data section, so that little of the
/// data passes through a buffer.
const HEAD: usize = 4 << 10;

/// 58b data reaching at least this far (or `chunk`, if smaller) beyond the
/// buffer are read straight into their values; shorter ones go through the
/// buffer (fewer, larger reads).
const DIRECT_MIN: usize = 16 << 10;

/// A job whose last dataset's values were read in place, of fewer bytes
/// than this, is parsed by the reading thread instead of a worker.
const INLINE_MAX: usize = 1 << 20;

/// Datasets of one buffer, sent to a worker.
struct Job {
    seq: usize,
    /// File offset of `buf[0]`.
    base: usize,
    buf: Vec<u8>,
    blocks: Vec<Block>,
    /// The values of the last block, a 58b dataset whose data were read
    /// into them instead of `buf` (which ends at the data's start).
    direct: Option<Ordinate>,
}

/// `e` with its byte offset moved from buffer to file position.
fn rebase(mut e: UffError, base: usize) -> UffError {
    e.byte_offset += base;
    e
}

/// Parses the blocks of a job in order, up to the first error (which lowers
/// `stop` to the job's sequence number: later jobs are not needed).
fn run_job(job: &mut Job, stop: &AtomicUsize) -> Vec<BlockResult> {
    let mut out = Vec::with_capacity(job.blocks.len());
    let last = job.blocks.len().saturating_sub(1);
    for (k, block) in job.blocks.iter().enumerate() {
        let direct = if k == last { job.direct.take() } else { None };
        let r = parse_block(&job.buf, block, direct).map_err(|e| rebase(e, job.base));
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
    /// 58b data sections read straight into their values.
    direct: usize,
}

/// Reads into `buf` until it is full or the reader ends: the bytes read,
/// and the error that stopped it if any.
fn read_full<R: Read>(r: &mut R, buf: &mut [u8]) -> (usize, Option<std::io::Error>) {
    let mut filled = 0;
    while filled < buf.len() {
        match r.read(&mut buf[filled..]) {
            Ok(0) => break,
            Ok(n) => filled += n,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e) => return (filled, Some(e)),
        }
    }
    (filled, None)
}

fn read_error(e: &std::io::Error, offset: usize) -> UffError {
    UffError {
        line: None,
        byte_offset: offset,
        dataset_index: None,
        dataset_number: None,
        message: format!("read error: {e}"),
    }
}

/// Bytes to fill a buffer holding `filled` unsplit bytes up to: a chunk, or
/// double when a dataset outgrows the buffer.
fn next_want(filled: usize, chunk: usize) -> usize {
    if filled < chunk / 2 {
        chunk
    } else {
        (2 * filled).max(chunk)
    }
}

/// Reads `r` chunk by chunk, splits, and hands jobs to `dispatch` in order.
///
/// Buffers come back from the workers with their old contents: `buf[..filled]`
/// holds the unparsed bytes and the rest is initialised scratch, so a read
/// goes straight into it without zeroing it first (13 MB of memset for a
/// 13 MB file otherwise).
///
/// The data section of a large 58b dataset of an even function (its length
/// declared by its header) is read straight into the dataset's values: the
/// part already in the buffer is copied, the rest read into them, so its
/// bytes are copied once, by the kernel. Its job (the buffer up to the
/// data, with the blocks before it) waits until the closing `-1` after the
/// data is read, as the splitter returns no block before that; the next
/// read is small ([`HEAD`]), so buffers mostly hold headers.
fn produce<R: Read>(
    r: R,
    chunk: usize,
    stop: &AtomicUsize,
    get_buffer: impl FnMut() -> Vec<u8>,
    dispatch: impl FnMut(Job) -> bool,
) -> Produced {
    let mut p = Producer::new(r, chunk, get_buffer, dispatch);
    let failure = loop {
        if stop.load(Ordering::Relaxed) != usize::MAX {
            // A dispatched dataset failed: it is the first error in file order.
            break None;
        }
        if let Err(e) = p.fill() {
            break Some(e);
        }
        let round = p.split();
        if let Some(block) = round.direct {
            match p.read_direct(block, round.blocks) {
                Ok(()) => continue,
                Err(e) => break Some(e),
            }
        }
        if !p.open || p.hand_over(round.blocks, round.done) {
            break round.failure;
        }
    };
    p.finish(failure)
}

/// The reading side of [`produce`]: the buffer being filled, where it is
/// in the file, and the jobs handed over so far.
struct Producer<R, G, D> {
    r: R,
    chunk: usize,
    /// Size of the read after 58b data read in place ([`HEAD`] or less).
    head: usize,
    get_buffer: G,
    dispatch: D,
    splitter: Splitter,
    buf: Vec<u8>,
    /// Bytes of `buf` read and not yet handed over.
    filled: usize,
    /// File offset of `buf[0]`.
    base: usize,
    eof: bool,
    /// Bytes `buf` is to hold after the next read.
    want: usize,
    /// Jobs handed over.
    jobs: usize,
    /// The job of a dataset whose data were read into its values, until the
    /// closing `-1` after them is found.
    pending: Option<Job>,
    /// 58b data sections read straight into their values.
    direct: usize,
    /// Whether the workers still take jobs.
    open: bool,
}

/// What one pass of the splitter over the buffer found.
struct Round {
    /// Complete blocks, in order.
    blocks: Vec<Block>,
    /// A 58b dataset whose data the producer reads itself ([`Step::Direct`]).
    direct: Option<Block>,
    /// The split error, if any (a file offset).
    failure: Option<UffError>,
    /// No more blocks will come (file end, error, or workers gone).
    done: bool,
}

impl<R: Read, G: FnMut() -> Vec<u8>, D: FnMut(Job) -> bool> Producer<R, G, D> {
    fn new(r: R, chunk: usize, mut get_buffer: G, dispatch: D) -> Self {
        let chunk = chunk.max(1);
        let head = chunk.min(HEAD);
        let mut splitter = Splitter::default();
        splitter.direct_min = Some(chunk.min(DIRECT_MIN));
        let buf = get_buffer();
        Producer {
            r,
            chunk,
            head,
            get_buffer,
            dispatch,
            splitter,
            buf,
            filled: 0,
            base: 0,
            eof: false,
            // The first read is small too: a 58b file's data then never pass
            // through a chunk-sized buffer; a text file's first dataset asks
            // for a chunk.
            want: head,
            jobs: 0,
            pending: None,
            direct: 0,
            open: true,
        }
    }

    /// Hands `job` over with the next sequence number; false when the
    /// workers are gone.
    fn send(&mut self, mut job: Job) -> bool {
        job.seq = self.jobs;
        self.jobs += 1;
        (self.dispatch)(job)
    }

    /// Reads until the buffer holds `want` bytes or the file ends.
    fn fill(&mut self) -> Result<(), UffError> {
        if self.eof || self.filled >= self.want {
            return Ok(());
        }
        if self.buf.len() < self.want {
            self.buf.resize(self.want, 0);
        }
        let (n, error) = read_full(&mut self.r, &mut self.buf[self.filled..self.want]);
        self.filled += n;
        if let Some(e) = error {
            return Err(read_error(&e, self.base + self.filled));
        }
        self.eof = self.filled < self.want;
        Ok(())
    }

    /// Splits the buffer up to the first block it cannot complete; sends the
    /// pending job when the `-1` closing its 58b data is found.
    fn split(&mut self) -> Round {
        let mut round = Round {
            blocks: Vec::new(),
            direct: None,
            failure: None,
            done: false,
        };
        round.done = loop {
            match self.splitter.next(&self.buf[..self.filled], self.eof) {
                Ok(Step::Block(b)) => round.blocks.push(b),
                Ok(Step::Direct(b)) => {
                    round.direct = Some(b);
                    break false;
                }
                Ok(Step::Closed { line, offset }) => {
                    // The first step of this buffer: nothing to order it after.
                    if let Some(mut job) = self.pending.take() {
                        if let Some(b) = job.blocks.last_mut() {
                            b.close_line = line;
                            b.close_offset = self.base + offset - job.base;
                        }
                        if !self.send(job) {
                            self.open = false;
                            break true;
                        }
                    }
                }
                Ok(Step::NeedMore) => break self.eof, // never at eof; stop rather than spin
                Ok(Step::End) => break true,
                Err(e) => {
                    round.failure = Some(e); // already a file offset
                    break true;
                }
            }
        };
        round
    }

    /// Reads the data of `block` (a [`Step::Direct`] dataset) straight into
    /// its values; the job of `blocks` and `block` waits for the closing
    /// `-1` ([`Producer::pending`]) and reading goes on after the data.
    fn read_direct(&mut self, block: Block, mut blocks: Vec<Block>) -> Result<(), UffError> {
        let data = block.binary.as_ref().map_or(0..0, |b| b.data.clone());
        let mut values = block
            .binary
            .as_ref()
            .map(|b| function58::direct_storage(&b.record7));
        let (got, error) = match values.as_mut() {
            Some(v) => {
                let bytes = function58::direct_bytes(v);
                let have = self.filled - data.start;
                bytes[..have].copy_from_slice(&self.buf[data.start..self.filled]);
                let (n, error) = read_full(&mut self.r, &mut bytes[have..]);
                (have + n, error)
            }
            None => (0, None),
        };
        self.direct += 1;
        // The job keeps the buffer up to the data.
        self.buf.truncate(data.start);
        blocks.push(block);
        self.pending = Some(Job {
            seq: 0,
            base: self.base,
            buf: std::mem::take(&mut self.buf),
            blocks,
            direct: values,
        });
        if let Some(e) = error {
            return Err(read_error(&e, self.base + data.start + got));
        }
        if got < data.len() {
            return Err(self.splitter.direct_truncated(got));
        }
        self.base += data.end;
        self.splitter.skip_direct(data.end);
        self.buf = (self.get_buffer)();
        self.filled = 0;
        self.want = self.head;
        Ok(())
    }

    /// Hands the complete `blocks` over with their buffer (the unfinished
    /// tail goes to the next buffer) and moves on; true when reading stops
    /// (`done`, or the workers are gone).
    fn hand_over(&mut self, blocks: Vec<Block>, done: bool) -> bool {
        let (filled, chunk) = (self.filled, self.chunk);
        let consumed = self.splitter.pos();
        if !blocks.is_empty() {
            let mut next = if done {
                Vec::new()
            } else {
                (self.get_buffer)()
            };
            let tail = filled - consumed;
            if !done {
                if next.len() < tail {
                    // Room for the next read too: no second allocation.
                    next.reserve_exact(next_want(tail, chunk) - next.len());
                    next.resize(tail, 0);
                }
                next[..tail].copy_from_slice(&self.buf[consumed..filled]);
            }
            // The job sees exactly its bytes.
            self.buf.truncate(filled);
            let job = Job {
                seq: 0,
                base: self.base,
                buf: std::mem::replace(&mut self.buf, next),
                blocks,
                direct: None,
            };
            self.filled = if done { 0 } else { tail };
            if !self.send(job) {
                return true;
            }
        } else if consumed > 0 && !done {
            self.buf.copy_within(consumed..filled, 0);
            self.filled -= consumed;
        }
        if done {
            return true;
        }
        self.base += consumed;
        self.splitter.consume(consumed);
        self.want = next_want(self.filled, chunk);
        false
    }

    fn finish(mut self, failure: Option<UffError>) -> Produced {
        // A dataset whose closing `-1` was not found is not returned (the split
        // failed on it); the blocks before it in its buffer are.
        if let Some(mut job) = self.pending.take() {
            job.blocks.pop();
            job.direct = None;
            if self.open && failure.is_some() && !job.blocks.is_empty() {
                self.send(job);
            }
        }
        Produced {
            jobs: self.jobs,
            notes: self.splitter.notes,
            failure,
            direct: self.direct,
        }
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
    parse_counted(r, chunk, threads).0
}

/// [`parse_reader_with`], and how many 58b data sections were read straight
/// into their values.
fn parse_counted<R: Read>(
    r: R,
    chunk: usize,
    threads: usize,
) -> (Result<UffFile, UffError>, usize) {
    if threads <= 1 {
        parse_serial(r, chunk)
    } else {
        parse_parallel(r, chunk, threads)
    }
}

/// [`parse_counted`] on the calling thread alone.
fn parse_serial<R: Read>(r: R, chunk: usize) -> (Result<UffFile, UffError>, usize) {
    let stop = AtomicUsize::new(usize::MAX);
    let mut results = Vec::new();
    // The parsed job's buffer is the next one to fill: two buffers in all
    // (three while a 58b dataset's closing `-1` is awaited). A new one
    // is allocated at the size of its first read.
    let spare = std::cell::Cell::new(None::<Vec<u8>>);
    let produced = produce(
        r,
        chunk,
        &stop,
        || spare.take().unwrap_or_default(),
        |mut job| {
            results.push(Some(run_job(&mut job, &stop)));
            if job.buf.capacity() <= 4 * chunk {
                spare.set(Some(job.buf));
            }
            true
        },
    );
    let direct = produced.direct;
    (assemble(produced, results), direct)
}

/// Results of one job, sent back by its worker.
type JobResults = (usize, Vec<BlockResult>);

/// A worker: parses jobs until the queue closes; sends their results, then
/// their buffer back.
fn work(
    jobs: &Mutex<mpsc::Receiver<Job>>,
    results: &mpsc::Sender<JobResults>,
    free: &mpsc::Sender<Vec<u8>>,
    stop: &AtomicUsize,
    chunk: usize,
) {
    loop {
        let job = match jobs.lock() {
            Ok(rx) => rx.recv(),
            Err(_) => break,
        };
        let Ok(mut job) = job else { break };
        let parsed = if job.seq > stop.load(Ordering::Relaxed) {
            Vec::new() // after the first error: not needed
        } else {
            run_job(&mut job, stop)
        };
        if results.send((job.seq, parsed)).is_err() {
            break;
        }
        // Give back a normal-sized buffer with its (initialised)
        // contents as scratch; a big dataset's buffer is freed
        // (an empty one stands for it).
        let buf = if job.buf.capacity() <= 4 * chunk {
            job.buf
        } else {
            Vec::new()
        };
        let _ = free.send(buf);
    }
}

/// [`parse_counted`] with `threads` workers.
fn parse_parallel<R: Read>(
    r: R,
    chunk: usize,
    threads: usize,
) -> (Result<UffFile, UffError>, usize) {
    let stop = AtomicUsize::new(usize::MAX);
    let (job_tx, job_rx) = mpsc::sync_channel::<Job>(threads);
    let job_rx = Arc::new(Mutex::new(job_rx));
    let (res_tx, res_rx) = mpsc::channel::<JobResults>();
    let (free_tx, free_rx) = mpsc::channel::<Vec<u8>>();
    std::thread::scope(|scope| {
        // Workers are started with the first job handed over: a file whose
        // datasets are all parsed by the reading thread (58b read in place)
        // starts none. They get the only senders of `free_tx`: should they
        // all end, waiting for a buffer ends too.
        let start_workers = |free_tx: mpsc::Sender<Vec<u8>>| {
            for _ in 0..threads {
                let (job_rx, res_tx, free_tx, stop) =
                    (Arc::clone(&job_rx), res_tx.clone(), free_tx.clone(), &stop);
                scope.spawn(move || work(&job_rx, &res_tx, &free_tx, stop, chunk));
            }
        };
        let mut free_tx = Some(free_tx);
        // Jobs handed to the workers whose buffer has not come back: each
        // comes back, so waiting for one cannot hang.
        let in_flight = std::cell::Cell::new(0usize);
        // The buffer of the last job parsed here, the next one to fill.
        let spare = std::cell::Cell::new(None::<Vec<u8>>);
        let produced = produce(
            r,
            chunk,
            &stop,
            || {
                if let Some(b) = spare.take() {
                    return b;
                }
                let back = |b| {
                    in_flight.set(in_flight.get() - 1);
                    b
                };
                if let Ok(b) = free_rx.try_recv() {
                    return back(b);
                }
                // Buffers in use at most: one per worker, one filling, one
                // for the tail (and one for a job that waits for the closing
                // `-1` of its 58b data).
                if in_flight.get() < threads {
                    // Allocated at the size of its first read.
                    return Vec::new();
                }
                free_rx.recv().map_or_else(|_| Vec::new(), back)
            },
            |mut job| {
                // A dataset whose values were read in place is parsed here:
                // what is left (its header, a check of its values, hot in
                // this core's cache) costs less than handing it over (on 2
                // cores, 58b read in 8.2 ms with hand-overs, 5.8 ms without).
                if job
                    .direct
                    .as_ref()
                    .is_some_and(|v| v.value_bytes() < INLINE_MAX)
                {
                    let results = run_job(&mut job, &stop);
                    if job.buf.capacity() <= 4 * chunk {
                        spare.set(Some(job.buf));
                    }
                    return res_tx.send((job.seq, results)).is_ok();
                }
                if let Some(tx) = free_tx.take() {
                    start_workers(tx);
                }
                in_flight.set(in_flight.get() + 1);
                job_tx.send(job).is_ok()
            },
        );
        drop(job_tx);
        drop(res_tx);
        let mut results: Vec<Option<Vec<BlockResult>>> = (0..produced.jobs).map(|_| None).collect();
        for (seq, rs) in res_rx {
            if let Some(slot) = results.get_mut(seq) {
                *slot = Some(rs);
            }
        }
        // Jobs skipped after an error have empty results; `assemble` stops at the error first.
        let direct = produced.direct;
        (assemble(produced, results), direct)
    })
}

/// Guards of the in-place read of 58b data (`Step::Direct`): whatever the
/// chunk size, thread count, read sizes and byte order, the result and the
/// first error equal [`super::parse`] on the whole file, and the data are
/// read in place where they reach past the buffer.
#[cfg(test)]
mod direct_tests {
    use super::parse_counted;
    use crate::uff::{
        parse, write_functions_with, Abscissa, AxisCharacteristics, ByteOrder, Complex32,
        Complex64, Dataset, Function58, Ordinate, WriteOptions,
    };

    /// An even 58b function of `points` points (ordinate type 2, 4, 5 or 6).
    fn function(k: usize, points: usize, ordinate_type: i32) -> Function58 {
        let axis = |t: i32| AxisCharacteristics {
            data_type: t,
            label: "L".into(),
            units_label: "U".into(),
            ..Default::default()
        };
        let v = |i: usize| ((i * 7 + k) as f64 * 0.37).sin() * 10f64.powi((i % 9) as i32 - 4);
        let ordinate = match ordinate_type {
            2 => Ordinate::RealSingle((0..points).map(|i| v(i) as f32).collect()),
            5 => Ordinate::ComplexSingle(
                (0..points)
                    .map(|i| Complex32::new(v(i) as f32, v(i + 1) as f32))
                    .collect(),
            ),
            6 => Ordinate::Complex(
                (0..points)
                    .map(|i| Complex64::new(v(i), v(i + 1)))
                    .collect(),
            ),
            _ => Ordinate::Real((0..points).map(v).collect()),
        };
        Function58 {
            id_lines: [
                format!("f{k}"),
                "x".into(),
                "y".into(),
                "NONE".into(),
                "NONE".into(),
            ],
            function_type: 4,
            function_id: k as i32,
            version: 1,
            load_case: 0,
            response_entity: "NONE".into(),
            response_node: k as i64 + 1,
            response_direction: 3,
            reference_entity: "NONE".into(),
            reference_node: 1,
            reference_direction: 3,
            ordinate_type,
            abscissa: Abscissa::Even {
                start: 0.0,
                step: 0.25,
            },
            z_axis_value: 0.0,
            abscissa_axis: axis(18),
            numerator_axis: axis(12),
            denominator_axis: axis(13),
            z_axis: axis(0),
            ordinate,
            binary: true,
        }
    }

    fn write(functions: &[Function58], byte_order: ByteOrder) -> Vec<u8> {
        let mut bytes = Vec::new();
        write_functions_with(&mut bytes, functions, &WriteOptions { byte_order }).expect("write");
        bytes
    }

    /// One of each ordinate type, 40 to 61 points (160 to 976 data bytes).
    fn four(byte_order: ByteOrder) -> Vec<u8> {
        let functions: Vec<_> = [2, 4, 5, 6]
            .iter()
            .enumerate()
            .map(|(k, &t)| function(k, 40 + 7 * k, t))
            .collect();
        write(&functions, byte_order)
    }

    /// Returns at most `step` bytes per read.
    struct Trickle<'a>(&'a [u8], usize);
    impl std::io::Read for Trickle<'_> {
        fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
            let n = buf.len().min(self.1).min(self.0.len());
            buf[..n].copy_from_slice(&self.0[..n]);
            self.0 = &self.0[n..];
            Ok(n)
        }
    }

    /// Streams `bytes` every way; all equal `parse`. In-place reads counted.
    fn same(bytes: &[u8], chunks: &[usize], what: &str) -> usize {
        let whole = parse(bytes);
        let mut direct = 0;
        for &chunk in chunks {
            for threads in [1, 2] {
                let (r, d) = parse_counted(bytes, chunk, threads);
                assert_eq!(r, whole, "{what}: chunk {chunk}, {threads} threads");
                direct += d;
            }
            for step in [1, 5] {
                let (r, d) = parse_counted(Trickle(bytes, step), chunk, 2);
                assert_eq!(r, whole, "{what}: chunk {chunk}, reads of {step}");
                direct += d;
            }
        }
        direct
    }

    /// Each dataset starts at every offset from a chunk boundary (blank
    /// lines before the file), in both byte orders; the values are the
    /// same bits either way, and write back to the same bytes.
    #[test]
    fn split_at_every_offset_both_byte_orders() {
        let little = four(ByteOrder::Little);
        let big = four(ByteOrder::Big);
        let (Ok(l), Ok(b)) = (parse(&little), parse(&big)) else {
            panic!("parses")
        };
        assert_eq!(l.datasets, b.datasets, "big-endian values differ");
        for (bytes, order) in [(&little, "little"), (&big, "big")] {
            let mut direct = 0;
            for pad in 0..=130 {
                let mut padded = b"\n".repeat(pad);
                padded.extend_from_slice(bytes);
                direct += same(
                    &padded,
                    &[64],
                    &format!("{order}-endian, {pad} blank lines"),
                );
            }
            assert!(direct > 0, "{order}-endian: no data read in place");
            let direct = same(bytes, &[1, 7, 100, 333, 4096], order);
            assert!(direct > 0, "{order}-endian: no data read in place");
            // Bit-exact: the read functions write back to the same bytes.
            let (Ok(file), _) = parse_counted(&bytes[..], 64, 2) else {
                panic!("streams")
            };
            let functions: Vec<Function58> = file
                .datasets
                .iter()
                .map(|d| match d {
                    Dataset::Function(f) => (**f).clone(),
                    Dataset::Other(_) => panic!("58b only"),
                })
                .collect();
            let order = if order == "big" {
                ByteOrder::Big
            } else {
                ByteOrder::Little
            };
            assert_eq!(&write(&functions, order), bytes, "round trip");
        }
    }

    /// A file cut anywhere (in a header, in the data, before the closing
    /// `-1`): the same error or result as `parse`, e.g. "58b data
    /// truncated" with the dataset, its byte offset and the expected bytes.
    #[test]
    fn truncated_anywhere() {
        let bytes = four(ByteOrder::Little);
        for cut in 0..bytes.len() {
            same(&bytes[..cut], &[64], &format!("cut at {cut}"));
        }
        let cut = bytes.len() / 8;
        let e = parse(&bytes[..cut]).expect_err("truncated");
        let (r, _) = parse_counted(&bytes[..cut], 64, 1);
        assert_eq!(r, Err(e.clone()));
        assert!(e.message.contains("58b data truncated"), "{e}");
        assert_eq!((e.dataset_index, e.dataset_number), (Some(0), Some(58)));
    }

    /// Byte offset of little-endian value `index` of the real single-precision
    /// `f` in its written `bytes`.
    fn value_offset(bytes: &[u8], f: &Function58, index: usize) -> usize {
        let Ordinate::RealSingle(v) = &f.ordinate else {
            panic!("real single")
        };
        bytes
            .windows(4)
            .position(|w| w == v[index].to_le_bytes())
            .unwrap_or_else(|| panic!("value {}", index + 1))
    }

    /// A NaN or infinity in the data; no closing `-1` after the declared
    /// bytes; blank lines or a missing line break before it; a read error
    /// inside the data.
    #[test]
    fn bad_data_and_quirks() {
        let f = function(0, 300, 2);
        let bytes = write(&[f.clone(), function(1, 200, 5)], ByteOrder::Little);
        let at = value_offset(&bytes, &f, 123);
        for bad in [f32::NAN, f32::INFINITY] {
            let mut b = bytes.clone();
            b[at..at + 4].copy_from_slice(&bad.to_le_bytes());
            let e = parse(&b).expect_err("non-finite");
            assert!(e.message.contains("point 124"), "{e}");
            same(&b, &[64, 4096], "non-finite");
        }
        // The closing -1 after the first data section.
        let close = at + 4 * (300 - 123);
        assert_eq!(
            &bytes[close..close + 6],
            b"    -1",
            "closing -1 right after the data"
        );
        let mut no_close = bytes.clone();
        no_close[close + 5] = b'2';
        let e = parse(&no_close).expect_err("no closing -1");
        assert!(e.message.contains("wrong byte count"), "{e}");
        same(&no_close, &[64, 4096], "no closing -1");
        for quirk in [&b"\n"[..], b"\r\n", b"\n\n  \n"] {
            let mut q = bytes.clone();
            q.splice(close..close, quirk.iter().copied());
            same(&q, &[1, 64, 4096], "line breaks after the data");
        }
        struct Failing<'a>(&'a [u8]);
        impl std::io::Read for Failing<'_> {
            fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
                if self.0.is_empty() {
                    return Err(std::io::Error::other("disk on fire"));
                }
                let n = buf.len().min(self.0.len());
                buf[..n].copy_from_slice(&self.0[..n]);
                self.0 = &self.0[n..];
                Ok(n)
            }
        }
        // Inside the data of a dataset read in place.
        let f = function(0, 3000, 2);
        let bytes = write(std::slice::from_ref(&f), ByteOrder::Little);
        let at = value_offset(&bytes, &f, 2500);
        for threads in [1, 2] {
            let (r, direct) = parse_counted(Failing(&bytes[..at]), 64, threads);
            let e = r.expect_err("read error");
            assert!(e.message.contains("disk on fire"), "{e}");
            assert_eq!(e.byte_offset, at);
            assert_eq!(direct, 1);
        }
    }
}
