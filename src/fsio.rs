//! File output that never leaves a partial file: write to a temporary file in
//! the same folder, then rename over the target.

use std::io::Write;
use std::path::Path;

/// Write `bytes` to `path` atomically (temporary file in the same folder, then rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    write_atomic_with(path, |w| w.write_all(bytes))
}

/// Stream into `path` atomically: `fill` writes the whole content; on any error
/// the temporary file is removed and `path` is left untouched.
pub fn write_atomic_with<F>(path: &Path, fill: F) -> std::io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> std::io::Result<()>,
{
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".to_string());
    let tmp = dir.join(format!(".{name}.{}.tmp", std::process::id()));
    let _guard = Temporary::register(&tmp);
    let result = (|| {
        let file = std::fs::File::create(&tmp)?;
        let mut buf = std::io::BufWriter::with_capacity(1 << 20, file);
        fill(&mut buf)?;
        let file = buf.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        drop(file);
        std::fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = std::fs::remove_file(&tmp);
    }
    result
}

/// The most bytes read from an input that is not a regular file (a pipe, a
/// process substitution): enough for any deck or campaign, and a bound on the
/// memory an endless stream can take.
pub const NON_REGULAR_INPUT_LIMIT: u64 = 256 << 20;

/// Open an input file for reading, refusing what cannot be a deck or a UFF
/// file: a directory, a device (`/dev/zero`, a terminal), a socket. A pipe
/// (FIFO) is read, but through [`Bounded`] at most
/// [`NON_REGULAR_INPUT_LIMIT`] bytes. Returns the reader and the file's
/// length (0 for a pipe). Errors are whole messages naming the file.
pub fn open_input(path: &Path) -> Result<(Bounded<std::fs::File>, u64), String> {
    use std::os::unix::fs::FileTypeExt;
    let shown = path.display();
    let meta = std::fs::metadata(path).map_err(|e| format!("{shown}: cannot read: {e}"))?;
    let ft = meta.file_type();
    let kind = if ft.is_dir() {
        Some("a directory")
    } else if ft.is_char_device() {
        Some("a character device")
    } else if ft.is_block_device() {
        Some("a block device")
    } else if ft.is_socket() {
        Some("a socket")
    } else {
        None
    };
    if let Some(kind) = kind {
        return Err(format!(
            "{shown}: cannot read: {kind}, not a file (frfup reads decks, UFF files and campaigns from regular files or pipes)"
        ));
    }
    let file = std::fs::File::open(path).map_err(|e| format!("{shown}: cannot read: {e}"))?;
    let limit = if ft.is_file() {
        u64::MAX
    } else {
        NON_REGULAR_INPUT_LIMIT
    };
    let len = if ft.is_file() { meta.len() } else { 0 };
    Ok((Bounded::new(file, limit), len))
}

/// Read a whole input file (see [`open_input`]): a pipe that gives more than
/// [`NON_REGULAR_INPUT_LIMIT`] bytes is refused with a message naming it.
pub fn read_input(path: &Path) -> Result<Vec<u8>, String> {
    use std::io::Read;
    let (mut reader, len) = open_input(path)?;
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    reader
        .read_to_end(&mut bytes)
        .map_err(|e| format!("{}: cannot read: {e}", path.display()))?;
    Ok(bytes)
}

/// A reader that fails, rather than reads on, past `limit` bytes.
pub struct Bounded<R> {
    inner: R,
    left: u64,
    limit: u64,
}

impl<R> Bounded<R> {
    pub fn new(inner: R, limit: u64) -> Self {
        Bounded {
            inner,
            left: limit,
            limit,
        }
    }
}

impl<R: std::io::Read> std::io::Read for Bounded<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        if self.left == 0 {
            // One byte more tells an input of exactly `limit` bytes from an endless one.
            let mut probe = [0u8; 1];
            return match self.inner.read(&mut probe)? {
                0 => Ok(0),
                _ => Err(std::io::Error::other(format!(
                    "more than {} MiB from a pipe or other non-regular file: refused (an endless input such as /dev/zero?); write it to a file first",
                    self.limit >> 20
                ))),
            };
        }
        let n = buf
            .len()
            .min(usize::try_from(self.left).unwrap_or(usize::MAX));
        let got = self.inner.read(&mut buf[..n])?;
        self.left -= got as u64;
        Ok(got)
    }
}

/// The sibling temporary folder where [`write_folder`] builds `target`.
fn sibling_tmp(target: &Path) -> std::path::PathBuf {
    let parent = match target.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let name = target
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".to_string());
    parent.join(format!(".{name}.{}.tmp", std::process::id()))
}

/// Check, before any computation, that `target` can become a result folder:
/// not an existing file, and its parent folder exists (or can be made) and
/// takes a new folder. The message names the path.
pub fn check_out_folder(target: &Path) -> Result<(), String> {
    let shown = target.display();
    if target.exists() && !target.is_dir() {
        return Err(format!("--out {shown}: exists and is not a folder"));
    }
    let probe = sibling_tmp(target);
    if let Some(parent) = probe.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| format!("--out {shown}: cannot create its parent folder: {e}"))?;
    }
    std::fs::create_dir(&probe)
        .and_then(|()| std::fs::remove_dir(&probe))
        .map_err(|e| format!("--out {shown}: cannot write beside it: {e}"))
}

/// Write a result folder as a whole: `fill` writes every file into a
/// temporary folder beside `target`; only when it succeeds do the files
/// land in `target` (one rename of the folder when `target` does not exist,
/// else one rename per file, so files of `target` that the run does not write
/// are kept). On any error the temporary folder is removed and `target` is
/// left as it was.
pub fn write_folder<T, E>(target: &Path, fill: impl FnOnce(&Path) -> Result<T, E>) -> Result<T, E>
where
    E: From<std::io::Error>,
{
    let tmp = sibling_tmp(target);
    let _guard = Temporary::register(&tmp);
    let _ = std::fs::remove_dir_all(&tmp);
    std::fs::create_dir_all(&tmp)?;
    let result = fill(&tmp).and_then(|value| {
        move_into(&tmp, target)?;
        Ok(value)
    });
    let _ = std::fs::remove_dir_all(&tmp);
    result
}

fn move_into(tmp: &Path, target: &Path) -> std::io::Result<()> {
    if !target.exists() {
        return std::fs::rename(tmp, target);
    }
    for entry in std::fs::read_dir(tmp)? {
        let entry = entry?;
        let to = target.join(entry.file_name());
        if entry.file_type()?.is_dir() && to.is_dir() {
            move_into(&entry.path(), &to)?;
        } else {
            std::fs::rename(entry.path(), &to)?;
        }
    }
    Ok(())
}

/// Temporary files and folders being written, removed if SIGINT or SIGTERM
/// ends the process (see [`remove_temporaries_on_signals`]).
static TEMPORARIES: std::sync::Mutex<Vec<std::path::PathBuf>> = std::sync::Mutex::new(Vec::new());

/// A registered temporary path; unregistered when dropped.
struct Temporary(std::path::PathBuf);

impl Temporary {
    fn register(path: &Path) -> Temporary {
        if let Ok(mut list) = TEMPORARIES.lock() {
            list.push(path.to_path_buf());
        }
        Temporary(path.to_path_buf())
    }
}

impl Drop for Temporary {
    fn drop(&mut self) {
        if let Ok(mut list) = TEMPORARIES.lock() {
            if let Some(i) = list.iter().position(|p| *p == self.0) {
                list.swap_remove(i);
            }
        }
    }
}

/// Set by the signal thread when SIGINT or SIGTERM arrives (signals are
/// process-wide; so is this flag).
static INTERRUPTED: std::sync::atomic::AtomicBool = std::sync::atomic::AtomicBool::new(false);

/// Whether SIGINT or SIGTERM has arrived: the process is being ended by the
/// signal thread (exit 128 + N once the temporaries are gone), so `main`
/// must not end it first with its own exit code.
pub fn interrupted() -> bool {
    INTERRUPTED.load(std::sync::atomic::Ordering::SeqCst)
}

/// Remove every temporary file or folder still being written. The writing
/// thread goes on until the process exits and may recreate a subfolder that
/// was just removed (a run's `frf/` charts), so removal is repeated until
/// every path has stayed gone for three checks 5 ms apart (at most 0.5 s).
pub fn remove_temporaries() {
    let list = match TEMPORARIES.lock() {
        Ok(mut list) => std::mem::take(&mut *list),
        Err(_) => return,
    };
    let mut quiet_checks = 0;
    for _ in 0..100 {
        let mut any = false;
        for p in &list {
            if p.is_dir() {
                any = true;
                let _ = std::fs::remove_dir_all(p);
            } else if p.exists() {
                any = true;
                let _ = std::fs::remove_file(p);
            }
        }
        quiet_checks = if any { 0 } else { quiet_checks + 1 };
        if quiet_checks >= 3 {
            return;
        }
        std::thread::sleep(std::time::Duration::from_millis(5));
    }
}

/// On SIGINT or SIGTERM, remove the temporaries being written and exit with
/// 128 + the signal's number, as the shell reports a killed process. Call it
/// first in `main`: the handlers (`signal-hook`) only wake one thread, which
/// does the work outside any signal handler.
pub fn remove_temporaries_on_signals() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    let Ok(mut signals) = signal_hook::iterator::Signals::new([SIGINT, SIGTERM]) else {
        return;
    };
    let _ = std::thread::Builder::new()
        .name("signals".into())
        .spawn(move || {
            if let Some(sig) = signals.forever().next() {
                INTERRUPTED.store(true, std::sync::atomic::Ordering::SeqCst);
                remove_temporaries();
                std::process::exit(128 + sig);
            }
        });
}

/// A number as every CSV file writes it: the shortest text that reads back
/// to the same f64, plain decimal for 1e-4 ≤ |x| < 1e6 (`0.1143`,
/// `2.5`), else `1.234e-5`; zero is `0` (never `-0` or `0e0`); NaN and
/// infinities are empty cells.
pub fn csv_number(x: f64) -> String {
    if !x.is_finite() {
        String::new()
    } else if x == 0.0 {
        "0".into()
    } else if (1e-4..1e6).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `x` rounded to `digits` significant digits, written by [`csv_number`]'s
/// rule: plain decimal for 1e-4 ≤ |x| < 1e6 (`0.004413691`), else
/// `1.234568e-5`; trailing zeros dropped; zero is `0` (never `0e0`); NaN and
/// infinities are empty cells. For tables whose precision is fixed.
pub fn csv_number_sig(x: f64, digits: usize) -> String {
    if !x.is_finite() {
        return String::new();
    }
    if x == 0.0 {
        return "0".into();
    }
    let sci = format!("{:.*e}", digits.max(1) - 1, x);
    let Some((mantissa, exponent)) = sci.split_once('e') else {
        return sci;
    };
    let exponent: i32 = exponent.parse().unwrap_or(0);
    // The rounded value is m·10^e with 1 ≤ |m| < 10, so 1e-4 ≤ |x| < 1e6
    // exactly when −4 ≤ e ≤ 5: the plain decimal is the mantissa's figures
    // with the point moved, no second rounding.
    if !(-4..=5).contains(&exponent) {
        return format!("{}e{exponent}", trim_zeros(mantissa.to_string()));
    }
    let (sign, body) = match mantissa.strip_prefix('-') {
        Some(b) => ("-", b),
        None => ("", mantissa),
    };
    let figures: String = body.chars().filter(|c| *c != '.').collect();
    let mut out = String::with_capacity(figures.len() + 8);
    out.push_str(sign);
    // Figures before the decimal point.
    let whole = exponent + 1;
    if whole <= 0 {
        out.push_str("0.");
        out.extend(std::iter::repeat_n('0', whole.unsigned_abs() as usize));
        out.push_str(&figures);
    } else if whole as usize >= figures.len() {
        out.push_str(&figures);
        out.extend(std::iter::repeat_n('0', whole as usize - figures.len()));
    } else {
        let (int, frac) = figures.split_at(whole as usize);
        out.push_str(int);
        out.push('.');
        out.push_str(frac);
    }
    trim_zeros(out)
}

/// `1.500` → `1.5`, `2.000` → `2`; text without a decimal point unchanged.
fn trim_zeros(s: String) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
}
