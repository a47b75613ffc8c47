//! Every line `fpc` (and `fpc-lab`) writes on standard error goes through
//! here, prefixed with the program's name ([`set_program`]): errors
//! (the library's, clap's usage errors, the CLI's own), warnings, notes
//! and progress. Such a line echoes input (a value, a key, a path, a whole
//! argument), so it is made safe and short before it is written:
//!
//! - control characters (newlines, terminal escapes) and bidirectional
//!   overrides are written escaped (`\n`, `\u{1b}`): a message is one line
//!   and cannot forge another or restyle the terminal;
//! - a word (a run of non-blank characters) longer than [`MAX_WORD`]
//!   characters keeps its first and last characters and says how long it
//!   was, so a 309-digit number or a huge argument is not echoed whole;
//! - a line longer than [`MAX_LINE`] characters keeps its head (which names
//!   the field) and its tail (which states the rule).
//!
//! A line is written with one `write` call (at most 4 x [`MAX_LINE`] bytes,
//! below the 4096 bytes a pipe takes atomically), so lines of concurrent
//! runs do not interleave. A write that fails (stderr closed or full) is
//! ignored: there is nowhere left to report it, and the exit status still
//! says what happened.

use std::io::Write as _;

/// The longest line written on stderr, in characters (Unicode scalar
/// values), prefix included, newline excluded.
pub const MAX_LINE: usize = 300;

/// The longest word kept whole, in characters.
pub const MAX_WORD: usize = 100;

/// Characters kept at each end of a shortened word.
const WORD_HEAD: usize = 60;
const WORD_TAIL: usize = 20;

/// Characters kept at the start of a shortened line (the rest of
/// [`MAX_LINE`] goes to the marker and the tail).
const LINE_HEAD: usize = 200;

static PROGRAM: std::sync::OnceLock<String> = std::sync::OnceLock::new();

/// Names the program in the prefix of every line (once; `fpc` unless set).
pub fn set_program(name: &str) {
    let _ = PROGRAM.set(name.to_owned());
}

/// The program's name.
pub fn program() -> &'static str {
    PROGRAM.get().map_or("fpc", String::as_str)
}

/// `fpc: error: ` and the error with its causes, on one line.
pub fn error(e: &anyhow::Error) {
    line(&format!("{}: error: ", program()), &format!("{e:#}"));
}

/// `fpc: warning: ` and the warning.
pub fn warning(msg: &str) {
    line(&format!("{}: warning: ", program()), msg);
}

/// Findings of one kind beyond this many are summed up in one line.
pub use fpc::error::WARNINGS_PER_KIND;

/// The warnings, `fpc: warning: ` each, summarised: of a kind with more
/// than [`WARNINGS_PER_KIND`] findings (one per element, say) only the
/// worst (furthest past its limit) is written, with how many more there
/// are ([`fpc::Warning::by_kind`]); `where_all` says where every one is
/// (the JSON output). `text` words each warning (the scene's keys, or the
/// library's names).
pub fn warnings<'a>(
    all: impl IntoIterator<Item = &'a fpc::Warning>,
    text: impl Fn(&fpc::Warning) -> String,
    where_all: &str,
) {
    for line in warning_lines(all, text, where_all) {
        warning(&line);
    }
}

fn warning_lines<'a>(
    all: impl IntoIterator<Item = &'a fpc::Warning>,
    text: impl Fn(&fpc::Warning) -> String,
    where_all: &str,
) -> Vec<String> {
    let mut lines = Vec::new();
    for s in fpc::Warning::by_kind(all) {
        if s.count <= WARNINGS_PER_KIND {
            lines.extend(s.kept.iter().map(|w| text(w)));
        } else {
            for worst in s.kept {
                lines.push(format!(
                    "{} (the worst of {} {} findings; every one in {where_all})",
                    text(worst),
                    s.count,
                    s.kind
                ));
            }
        }
    }
    lines
}

/// `fpc: ` and a note (a study that failed while the others go on).
pub fn note(msg: &str) {
    line(&format!("{}: ", program()), msg);
}

/// A line as it is (bounded), no prefix: the plain progress of `fpc-lab stress`.
pub fn plain(msg: &str) {
    line("", msg);
}

/// Seconds between two progress lines where stderr is not a terminal.
const PLAIN_PROGRESS_EVERY_S: u64 = 5;

/// When the last progress line was written where stderr is not a
/// terminal, and the characters of the line drawn on a terminal since the
/// last [`end_progress`] (0: none).
static PROGRESS: std::sync::Mutex<(Option<std::time::Instant>, usize)> =
    std::sync::Mutex::new((None, 0));

/// Progress of a long run. On a terminal a line that redraws itself
/// (carriage return, then the text, bounded like any line, and blanks
/// over what a longer line before it left; no newline: [`end_progress`]
/// ends it). Elsewhere (a log, a pipe) a whole line, the first at once
/// and then at most one every [`PLAIN_PROGRESS_EVERY_S`] seconds, so a
/// log is not flooded with redraws.
pub fn progress(msg: &str) {
    let mut state = PROGRESS.lock().unwrap_or_else(|e| e.into_inner());
    if is_terminal() {
        let text = bounded("", msg);
        let drawn = text.chars().count();
        let blanks = " ".repeat(state.1.saturating_sub(drawn));
        state.1 = drawn.max(1);
        write_stderr(format!("\r{text}{blanks}").as_bytes());
        return;
    }
    let now = std::time::Instant::now();
    let due = state
        .0
        .is_none_or(|t| now.duration_since(t).as_secs() >= PLAIN_PROGRESS_EVERY_S);
    if due {
        state.0 = Some(now);
        line("", msg);
    }
}

/// How long a run works before [`with_progress`] says anything, unless
/// [`QUIET_FOR_VARIABLE`] says otherwise: a run that ends sooner writes no
/// progress (and a quick successful run, an empty stderr).
pub const QUIET_FOR: std::time::Duration = std::time::Duration::from_secs(2);

/// The environment variable that sets the quiet time in seconds (a
/// number, zero or more; anything else leaves [`QUIET_FOR`]): `0` shows
/// progress at once, a large value keeps a log free of it.
pub const QUIET_FOR_VARIABLE: &str = "FPC_PROGRESS_AFTER_S";

/// The quiet time: [`QUIET_FOR_VARIABLE`]'s, else [`QUIET_FOR`].
fn quiet_for() -> std::time::Duration {
    std::env::var(QUIET_FOR_VARIABLE)
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .and_then(|s| std::time::Duration::try_from_secs_f64(s).ok())
        .unwrap_or(QUIET_FOR)
}

/// The last progress event a long computation reported, kept for
/// [`with_progress`]'s status line (set from the work's threads, read
/// from the reporter's).
pub struct Latest<P>(std::sync::Mutex<Option<P>>);

impl<P> Default for Latest<P> {
    /// No event yet.
    fn default() -> Latest<P> {
        Latest(std::sync::Mutex::new(None))
    }
}

impl<P: Copy> Latest<P> {
    /// Keeps `p` as the last event.
    pub fn set(&self, p: &P) {
        *self
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner) = Some(*p);
    }

    /// The last event, if any.
    pub fn get(&self) -> Option<P> {
        *self
            .0
            .lock()
            .unwrap_or_else(std::sync::PoisonError::into_inner)
    }
}

/// How often [`with_progress`] redraws its line (a log gets at most one
/// line every [`PLAIN_PROGRESS_EVERY_S`] seconds of them).
const REDRAW_EVERY: std::time::Duration = std::time::Duration::from_millis(200);

/// Runs `work`, writing `status()` with [`progress`] every
/// [`REDRAW_EVERY`] once it has worked for the quiet time ([`QUIET_FOR`],
/// or [`QUIET_FOR_VARIABLE`]'s), and ends the
/// line ([`end_progress`]) if one was drawn. `status` is called on a
/// thread of its own, so it reads what `work` shares with it (atomics,
/// a mutex). The reporter stops as soon as `work` returns, and also when
/// it unwinds: a panicking worker must not leave the reporter waiting.
pub fn with_progress<T>(status: impl Fn() -> String + Sync, work: impl FnOnce() -> T) -> T {
    let (finished, wait) = std::sync::mpsc::channel::<()>();
    let status = &status;
    let out = std::thread::scope(|s| {
        s.spawn(move || {
            let started = std::time::Instant::now();
            let quiet = quiet_for();
            // the work's end drops `finished`: the wait ends at once
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                wait.recv_timeout(REDRAW_EVERY)
            {
                if started.elapsed() >= quiet {
                    progress(&status());
                }
            }
        });
        // dropped when `work` returns or unwinds
        let _finished = finished;
        work()
    });
    end_progress();
    out
}

/// [`progress`] on a terminal only, nothing elsewhere: for a command whose
/// log should stay as quiet as before (`fpc paper`).
pub fn progress_on_terminal(msg: &str) {
    if is_terminal() {
        progress(msg);
    }
}

/// Ends a line of [`progress`] (on a terminal; elsewhere its lines are
/// whole already).
pub fn end_progress() {
    let mut state = PROGRESS.lock().unwrap_or_else(|e| e.into_inner());
    if std::mem::take(&mut state.1) > 0 {
        write_stderr(b"\n");
    }
    state.0 = None;
}

/// Writes `prefix` and `msg` as one bounded line.
fn line(prefix: &str, msg: &str) {
    let mut text = bounded(prefix, msg);
    text.push('\n');
    write_stderr(text.as_bytes());
}

/// Whether stderr is a terminal (where progress bars draw).
pub fn is_terminal() -> bool {
    use std::io::IsTerminal as _;
    #[allow(clippy::disallowed_methods)] // not a write
    std::io::stderr().is_terminal()
}

fn write_stderr(bytes: &[u8]) {
    // one write_all on the unbuffered handle: one write(2) for a line
    #[allow(clippy::disallowed_methods)] // the one place stderr is written
    let mut err = std::io::stderr().lock();
    let _ = err.write_all(bytes);
    let _ = err.flush();
}

/// `prefix` and `msg` as one line of at most [`MAX_LINE`] characters:
/// controls escaped, long words and then the line shortened in the middle.
pub fn bounded(prefix: &str, msg: &str) -> String {
    let mut line = String::with_capacity(prefix.len() + msg.len().min(4 * MAX_LINE));
    line.push_str(prefix);
    let mut first = true;
    for word in sanitize(msg).split(' ') {
        if !first {
            line.push(' ');
        }
        first = false;
        shorten_word(&mut line, word);
    }
    shorten_line(line)
}

/// Control characters and bidirectional formatting characters escaped.
pub fn sanitize(msg: &str) -> std::borrow::Cow<'_, str> {
    let unsafe_char = |c: char| {
        c.is_control()
            || matches!(c, '\u{200b}'..='\u{200f}' | '\u{202a}'..='\u{202e}' | '\u{2066}'..='\u{2069}' | '\u{feff}')
    };
    if !msg.chars().any(unsafe_char) {
        return msg.into();
    }
    let mut s = String::with_capacity(msg.len() + 16);
    for c in msg.chars() {
        if unsafe_char(c) {
            s.extend(c.escape_default());
        } else {
            s.push(c);
        }
    }
    s.into()
}

/// Appends `word`, or its ends and its length when it is too long.
fn shorten_word(out: &mut String, word: &str) {
    let n = word.chars().count();
    if n <= MAX_WORD {
        out.push_str(word);
        return;
    }
    out.extend(word.chars().take(WORD_HEAD));
    out.push_str(&format!("…[{n} chars]…"));
    out.extend(word.chars().skip(n - WORD_TAIL));
}

/// `line`, or its head and tail when it has more than [`MAX_LINE`] characters.
fn shorten_line(line: String) -> String {
    let n = line.chars().count();
    if n <= MAX_LINE {
        return line;
    }
    // the marker names the number of characters cut, which is at most n:
    // sized for n, it fits whatever the count
    let widest = format!(" …[{n} chars cut]… ").chars().count();
    let tail = MAX_LINE - LINE_HEAD - widest;
    let cut = n - LINE_HEAD - tail;
    let mut out: String = line.chars().take(LINE_HEAD).collect();
    out.push_str(&format!(" …[{cut} chars cut]… "));
    out.extend(line.chars().skip(n - tail));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A panic in the work ends the progress reporter and comes back to
    /// the caller: the reporter must not wait for work that will never
    /// finish (before its guard, `fpc sweep` hung so). Work that ends
    /// within [`QUIET_FOR`] is never asked for its status.
    #[test]
    fn the_progress_reporter_ends_with_its_work_even_a_panicking_one() {
        let (tx, rx) = std::sync::mpsc::channel();
        std::thread::spawn(move || {
            let r = std::panic::catch_unwind(|| {
                with_progress(String::new, || -> usize { panic!("a worker fails") })
            });
            let _ = tx.send(r.is_err());
        });
        let unwound = rx
            .recv_timeout(std::time::Duration::from_secs(20))
            .expect("with_progress hung after its work panicked");
        assert!(unwound);
        let asked = std::sync::atomic::AtomicBool::new(false);
        let status = || {
            asked.store(true, std::sync::atomic::Ordering::Relaxed);
            String::new()
        };
        assert_eq!(with_progress(status, || 7), 7);
        assert!(!asked.load(std::sync::atomic::Ordering::Relaxed));
    }

    fn len(s: &str) -> usize {
        s.chars().count()
    }

    #[test]
    fn many_findings_of_a_kind_are_summed_up_by_the_worst() {
        let slope = |element, degrees| fpc::Warning::ElementSlope {
            element,
            degrees,
            limit: 45.0,
        };
        let fit = fpc::Warning::Eps0OutsideFit {
            eps0: 0.9,
            lo: 0.0,
            hi: 0.6,
        };
        let few = [fit.clone(), slope(0, 50.0), slope(1, 47.0)];
        let lines = warning_lines(&few, |w| w.to_string(), "x.json");
        assert_eq!(lines.len(), 3);
        let many = [slope(0, 50.0), fit.clone(), slope(1, 61.0), slope(2, 47.0)];
        let lines = warning_lines(&many, |w| w.to_string(), "x.json");
        assert_eq!(lines.len(), 2, "{lines:?}");
        assert!(
            lines[0].starts_with("element 1 turns 61.0 degrees"),
            "{lines:?}"
        );
        assert!(lines[0].ends_with("(the worst of 3 element_slope findings; every one in x.json)"));
        assert_eq!(lines[1], fit.to_string());
    }

    #[test]
    fn short_lines_are_kept() {
        let m = "actuator.pemc.eps0 = NaN: must be finite";
        assert_eq!(bounded("fpc: error: ", m), format!("fpc: error: {m}"));
    }

    #[test]
    fn a_long_number_keeps_its_ends() {
        let digits = format!("1{}", "0".repeat(308));
        let msg = format!("actuator.pemc.eps0 = {digits}: outside [0, 0.6]");
        let b = bounded("fpc: warning: ", &msg);
        assert!(len(&b) <= MAX_LINE, "{b}");
        assert!(!b.contains(&digits), "{b}");
        assert!(b.contains("[310 chars]"), "{b}"); // the digits and the colon
        assert!(b.starts_with("fpc: warning: actuator.pemc.eps0 = 1000"));
        assert!(b.ends_with("0000: outside [0, 0.6]"), "{b}");
    }

    #[test]
    fn every_line_is_bounded() {
        for msg in [
            "x".repeat(2_000_000),
            "ab ".repeat(1_000_000),
            "é".repeat(50_000),
            "\n".repeat(100_000),
            format!("{} {}", "word ".repeat(90), "y".repeat(99)),
        ] {
            let b = bounded("fpc: error: ", &msg);
            assert!(len(&b) <= MAX_LINE, "{} chars: {b}", len(&b));
            assert!(b.starts_with("fpc: error: "));
            assert!(!b.contains('\n'));
        }
        // the boundary: a line of exactly MAX_LINE characters is whole
        let m = "w ".repeat((MAX_LINE - 12) / 2);
        assert_eq!(len(&bounded("fpc: error: ", &m)), MAX_LINE);
        assert_eq!(bounded("fpc: error: ", &m), format!("fpc: error: {m}"));
    }

    #[test]
    fn a_long_line_keeps_head_and_tail() {
        let msg = format!("field.name = {}: the rule", "ab ".repeat(1000));
        let b = bounded("fpc: error: ", &msg);
        assert!(len(&b) <= MAX_LINE, "{b}");
        assert!(b.starts_with("fpc: error: field.name = ab ab"), "{b}");
        assert!(b.ends_with("ab : the rule"), "{b}");
        assert!(b.contains(" chars cut]… "), "{b}");
    }

    #[test]
    fn controls_are_escaped() {
        let b = bounded(
            "fpc: error: ",
            "a\nfpc: error: forged\u{1b}[31m\r\u{202e}x\ty",
        );
        assert_eq!(
            b,
            "fpc: error: a\\nfpc: error: forged\\u{1b}[31m\\r\\u{202e}x\\ty"
        );
    }
}
