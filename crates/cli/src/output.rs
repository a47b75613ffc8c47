//! Output: standard output and atomic file writes.

use std::io::Write;
use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::OnceLock;
use std::time::{Duration, SystemTime};

use anyhow::Context;
use fpc::InputError;

// ------------------------------------------------------------ stdout

/// Standard output, through which every command writes its results. A
/// write that fails (a closed pipe, a full disk, a descriptor that was
/// closed or opened read-only) is an `io::Error` saying "cannot write to
/// standard output: ...", which the command returns: status 1, never a
/// panic (`println!` panics on a closed pipe).
pub fn stdout() -> Stdout {
    #[allow(clippy::disallowed_methods)] // the one place stdout is written
    let inner = std::io::stdout().lock();
    Stdout(inner)
}

/// See [`stdout`].
pub struct Stdout(std::io::StdoutLock<'static>);

impl std::io::Write for Stdout {
    /// Writes `buf` with its control characters other than newline and
    /// tab escaped (`\u{1b}`): a summary echoes names from the user's
    /// files and paths, which must not drive the terminal. (JSON output
    /// escapes them already; nothing `fpc` writes on stdout needs them.)
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        usable()?;
        let control = |b: &u8| (*b < 0x20 && !matches!(*b, b'\n' | b'\t')) || *b == 0x7f;
        if !buf.iter().any(control) {
            return self.0.write(buf).map_err(cannot_write);
        }
        let mut escaped = Vec::with_capacity(buf.len() + 16);
        for b in buf {
            if control(b) {
                escaped.extend_from_slice(format!("\\u{{{b:x}}}").as_bytes());
            } else {
                escaped.push(*b);
            }
        }
        self.0.write_all(&escaped).map_err(cannot_write)?;
        Ok(buf.len())
    }

    fn flush(&mut self) -> std::io::Result<()> {
        usable()?;
        self.0.flush().map_err(cannot_write)
    }
}

pub(crate) fn cannot_write(e: std::io::Error) -> std::io::Error {
    std::io::Error::new(e.kind(), format!("cannot write to standard output: {e}"))
}

/// Fails when standard output cannot take output although writes to it
/// would seem to succeed: the standard library turns EBADF on stdout into
/// success, and its runtime puts /dev/null in place of a descriptor that
/// was closed at start (`fpc ... >&-`).
pub fn usable() -> std::io::Result<()> {
    static WHY_NOT: OnceLock<Option<&'static str>> = OnceLock::new();
    match WHY_NOT.get_or_init(why_stdout_is_unusable) {
        None => Ok(()),
        Some(why) => Err(std::io::Error::other(format!(
            "cannot write to standard output: {why}"
        ))),
    }
}

fn why_stdout_is_unusable() -> Option<&'static str> {
    if STDOUT_CLOSED_AT_START.load(Ordering::Relaxed) {
        return Some("it was closed");
    }
    // the access mode of descriptor 1 (Linux: O_RDONLY is 0)
    let info = std::fs::read_to_string("/proc/self/fdinfo/1").ok()?;
    let flags = info.lines().find_map(|l| l.strip_prefix("flags:"))?;
    let flags = u32::from_str_radix(flags.trim(), 8).ok()?;
    (flags & 0o3 == 0).then_some("it is open for reading only")
}

/// Whether descriptor 1 was closed when the process started. Rust's
/// runtime opens /dev/null in place of a closed standard descriptor before
/// `main` runs, so this is looked at earlier: by an ELF constructor, which
/// the loader runs before the runtime's initialisation. Linux only (it
/// reads /proc); elsewhere a closed stdout behaves as /dev/null.
static STDOUT_CLOSED_AT_START: AtomicBool = AtomicBool::new(false);

#[cfg(target_os = "linux")]
#[used]
#[link_section = ".init_array"]
static LOOK_AT_STDOUT_AT_START: extern "C" fn() = {
    extern "C" fn look() {
        // /proc/self/fd lists the open descriptors; without /proc, assume open
        let fds = Path::new("/proc/self/fd");
        if std::fs::symlink_metadata(fds).is_ok()
            && std::fs::symlink_metadata(fds.join("1"))
                .is_err_and(|e| e.kind() == std::io::ErrorKind::NotFound)
        {
            STDOUT_CLOSED_AT_START.store(true, Ordering::Relaxed);
        }
    }
    look
};

// ------------------------------------------------------------ files

/// The name of every temporary file `fpc` writes: this prefix, random
/// characters, `.tmp`, in the directory of its target (so the rename is
/// atomic).
pub const TEMP_PREFIX: &str = ".fpc-tmp-";

/// A temporary file older than this was left by a run that was killed
/// between writing and renaming it (a live run holds one for
/// milliseconds): [`prepare_dir`] removes it.
pub const STALE_AFTER: Duration = Duration::from_secs(15 * 60);

/// Writes `bytes` to `dir/name` atomically: a temporary file with a name
/// of its own (concurrent runs into one directory never share one) in the
/// same directory, flushed to disk, then renamed over the target. A reader
/// sees either the old file or the complete new one, never a half-written
/// file. The temporary file is removed if anything fails.
pub fn write_atomic(dir: &Path, name: &str, bytes: &[u8]) -> anyhow::Result<()> {
    write_atomic_with(dir, name, |w| w.write_all(bytes).map_err(Into::into))
}

/// [`write_atomic`] of what `write` writes, streamed (buffered) into the
/// temporary file, so that a large output (a sweep's million rows) is
/// never held in memory whole. An error of `write` removes the temporary
/// file and leaves the target as it was.
pub fn write_atomic_with(
    dir: &Path,
    name: &str,
    write: impl FnOnce(&mut dyn Write) -> anyhow::Result<()>,
) -> anyhow::Result<()> {
    let target = dir.join(name);
    let result = (|| -> anyhow::Result<()> {
        let tmp = temp_file(dir)?;
        let mut w = std::io::BufWriter::new(tmp);
        write(&mut w)?;
        let tmp = w.into_inner().map_err(|e| e.into_error())?;
        tmp.as_file().sync_all()?;
        tmp.persist(&target).map_err(|e| e.error)?;
        Ok(())
    })();
    result.with_context(|| format!("cannot write {}", target.display()))
}

/// A new temporary file in `dir`, removed when dropped unless persisted;
/// created with the mode a plain `File::create` gets (0666 less the umask).
fn temp_file(dir: &Path) -> std::io::Result<tempfile::NamedTempFile> {
    let mut b = tempfile::Builder::new();
    b.prefix(TEMP_PREFIX).suffix(".tmp");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt as _;
        b.permissions(std::fs::Permissions::from_mode(0o666));
    }
    b.tempfile_in(dir)
}

/// The stem of a command's input file (`fallback` when it has none) and
/// its output directory: `out` when given, else `<stem>-<suffix>` in the
/// current directory.
pub fn stem_and_dir(
    input: &Path,
    out: Option<&Path>,
    fallback: &str,
    suffix: &str,
) -> (String, std::path::PathBuf) {
    let stem = input.file_stem().map_or_else(
        || fallback.to_string(),
        |s| s.to_string_lossy().into_owned(),
    );
    let dir = out.map_or_else(|| format!("{stem}-{suffix}").into(), Path::to_path_buf);
    (stem, dir)
}

/// Makes `out` ready for output files before any work is done: creates it
/// if missing (rejecting an empty path, or a path that exists and is not
/// a directory, as input), removes stale temporary files ([`STALE_AFTER`])
/// and checks that it takes a new file.
pub fn prepare_dir(out: &Path) -> anyhow::Result<()> {
    let reject = |rule: String| -> anyhow::Error {
        InputError::Inconsistent {
            field: fpc::Field::key("--out"),
            rule,
        }
        .into()
    };
    if out.as_os_str().is_empty() {
        return Err(reject("the output directory must not be empty".into()));
    }
    match std::fs::metadata(out) {
        Ok(m) if m.is_dir() => {}
        Ok(_) => {
            return Err(reject(format!(
                "{} exists and is not a directory",
                out.display()
            )))
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            std::fs::create_dir_all(out)
                .with_context(|| format!("cannot create the output directory {}", out.display()))?;
        }
        Err(e) => {
            return Err(e)
                .with_context(|| format!("cannot use the output directory {}", out.display()))
        }
    }
    remove_stale_temps(out, STALE_AFTER);
    // fail now, not after the work, when the directory takes no file
    temp_file(out).with_context(|| format!("cannot write into {}", out.display()))?;
    Ok(())
}

/// Removes the regular files in `dir` named like [`TEMP_PREFIX`]`*` that
/// were last modified more than `age` ago. Best effort: a file another run
/// removes first, or one that cannot be removed, is left to it.
pub fn remove_stale_temps(dir: &Path, age: Duration) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    let now = SystemTime::now();
    for entry in entries.flatten() {
        if !entry
            .file_name()
            .as_encoded_bytes()
            .starts_with(TEMP_PREFIX.as_bytes())
        {
            continue;
        }
        let Ok(meta) = std::fs::symlink_metadata(entry.path()) else {
            continue;
        };
        let old = meta
            .modified()
            .ok()
            .and_then(|m| now.duration_since(m).ok())
            .is_some_and(|d| d > age);
        if meta.is_file() && old {
            let _ = std::fs::remove_file(entry.path());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::fs;

    /// A fresh scratch directory, removed when dropped (a failed test's too).
    fn scratch(name: &str) -> tempfile::TempDir {
        tempfile::Builder::new()
            .prefix(&format!("fpc-output-{name}-"))
            .tempdir()
            .unwrap()
    }

    #[test]
    fn atomic_write_replaces() {
        let tmp = scratch("replace");
        let dir = tmp.path();
        write_atomic(dir, "a.txt", b"one").unwrap();
        write_atomic(dir, "a.txt", b"two").unwrap();
        assert_eq!(fs::read_to_string(dir.join("a.txt")).unwrap(), "two");
        let leftovers = fs::read_dir(dir).unwrap().count();
        assert_eq!(leftovers, 1);
    }

    #[test]
    fn a_failed_write_leaves_no_temporary_file() {
        let tmp = scratch("failed");
        let dir = tmp.path();
        fs::create_dir(dir.join("a.txt")).unwrap(); // cannot be renamed over
        let e = write_atomic(dir, "a.txt", b"one").unwrap_err();
        assert!(format!("{e:#}").contains("cannot write"), "{e:#}");
        let names: Vec<_> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("a.txt")]);
    }

    /// A writer that fails half-way leaves the old file whole and no
    /// temporary file; one that succeeds is flushed through the buffer.
    #[test]
    fn a_streamed_write_is_atomic_too() {
        let tmp = scratch("streamed");
        let dir = tmp.path();
        write_atomic(dir, "a.txt", b"old").unwrap();
        let e = write_atomic_with(dir, "a.txt", |w| {
            w.write_all(&[b'x'; 100_000])?;
            anyhow::bail!("the rows ran out")
        })
        .unwrap_err();
        assert!(format!("{e:#}").contains("the rows ran out"), "{e:#}");
        assert_eq!(fs::read_to_string(dir.join("a.txt")).unwrap(), "old");
        assert_eq!(fs::read_dir(dir).unwrap().count(), 1);
        write_atomic_with(dir, "a.txt", |w| {
            for _ in 0..10_000 {
                w.write_all(b"0123456789")?;
            }
            Ok(())
        })
        .unwrap();
        assert_eq!(fs::read(dir.join("a.txt")).unwrap().len(), 100_000);
        assert_eq!(fs::read_dir(dir).unwrap().count(), 1);
    }

    #[test]
    fn a_file_is_not_an_output_directory() {
        let tmp = scratch("file");
        let dir = tmp.path();
        let f = dir.join("x");
        fs::write(&f, "x").unwrap();
        let e = prepare_dir(&f).unwrap_err();
        assert!(e.downcast_ref::<InputError>().is_some());
        assert!(e.to_string().contains("not a directory"), "{e}");
    }

    #[test]
    fn only_old_temporary_files_are_stale() {
        let tmp = scratch("stale");
        let dir = tmp.path();
        let hour_ago = SystemTime::now() - Duration::from_secs(3600);
        for name in [".fpc-tmp-old", ".fpc-tmp-new", ".other-old", "old.csv"] {
            let f = fs::File::create(dir.join(name)).unwrap();
            if name.contains("old") {
                f.set_modified(hour_ago).unwrap();
            }
        }
        fs::create_dir(dir.join(".fpc-tmp-dir")).unwrap();
        remove_stale_temps(dir, STALE_AFTER);
        let mut names: Vec<String> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().into_string().unwrap())
            .collect();
        names.sort();
        assert_eq!(
            names,
            [".fpc-tmp-dir", ".fpc-tmp-new", ".other-old", "old.csv"]
        );
    }
}
