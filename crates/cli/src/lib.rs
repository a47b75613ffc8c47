//! What the `fpc` binary and the lab's `fpc-lab` share: standard output
//! that reports a failed write and atomic output files ([`output`]),
//! bounded and escaped lines on stderr ([`report`]), the provenance of
//! every JSON file ([`provenance`]), exit codes ([`status`]), Ctrl-C in a
//! long command ([`interrupt`]), the renderer of figures as SVG, PNG and
//! PDF ([`render`]), and the entry point that ties them to a clap command
//! line ([`main`]).
//!
//! Output goes through two doors: `output::stdout()` for results (a failed
//! write is an error, status 1) and `report` for every line on stderr.
//! `print!`-style macros and direct handles are refused by clippy (the
//! lints below and clippy.toml).
#![warn(clippy::print_stdout, clippy::print_stderr, clippy::dbg_macro)]

use std::io::Write as _;

pub mod interrupt;
pub mod output;
pub mod provenance;
pub mod render;
pub mod report;
pub mod status;

/// Runs a program of subcommands `C`: parses the arguments, runs `run`,
/// flushes standard output, reports an error on stderr (prefixed with the
/// program's name) and exits with [`status::exit_code`]. Help and version
/// go to stdout (status 0) as clap prints them; no subcommand prints the
/// help on stderr and is rejected; a usage error (unknown flag, missing or
/// malformed value) is rejected input, one line in the form of every other
/// error.
pub fn main<C: clap::Parser>(run: impl FnOnce(C) -> anyhow::Result<()>) -> ! {
    report::set_program(C::command().get_name());
    let result = match C::try_parse() {
        // what is still buffered: a failure to flush is a failure to write
        Ok(cli) => run(cli).and_then(|()| output::stdout().flush().map_err(Into::into)),
        Err(e) => usage::<C>(e),
    };
    match &result {
        // the reader went away (`fpc ... | head`): stop quietly
        Err(e) if status::reader_gone(e) => {}
        // stopped by Ctrl-C after writing what was done: not an error
        Err(e) if status::is_interrupted(e) => report::note(&format!("{e:#}")),
        Err(e) => report::error(e),
        Ok(()) => {}
    }
    std::process::exit(status::exit_code(&result));
}

fn usage<C: clap::Parser>(e: clap::Error) -> anyhow::Result<()> {
    use clap::error::ErrorKind;
    match e.kind() {
        ErrorKind::DisplayHelp | ErrorKind::DisplayVersion => {
            output::usable()?;
            e.print().map_err(|e| output::cannot_write(e).into())
        }
        ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand => {
            let _ = e.print();
            Err(status::rejected("a subcommand is required (see above)"))
        }
        _ => {
            // clap quotes the offending argument: one holding a newline
            // would break up its message, so the message is rendered again
            // from the arguments with their control characters escaped
            let escaped = std::env::args_os().map(|a| match a.to_str() {
                Some(s) => report::sanitize(s).into_owned().into(),
                None => a,
            });
            let text = match C::try_parse_from(escaped) {
                Err(again) if again.kind() == e.kind() => again.render().to_string(),
                _ => e.render().to_string(),
            };
            Err(status::rejected(usage_error_line(&text)))
        }
    }
}

/// clap's message and tips on one line, without the usage block.
fn usage_error_line(text: &str) -> String {
    // the usage block and the pointer to --help come after the message
    // (which quotes no newline: the arguments were escaped)
    let body = text.split("\nUsage:").next().unwrap_or(text);
    let body = body.split("\nFor more information").next().unwrap_or(body);
    let mut line = String::new();
    for part in body.lines().map(str::trim).filter(|l| !l.is_empty()) {
        if !line.is_empty() {
            line.push_str(if line.ends_with(':') { " " } else { "; " });
        }
        line.push_str(part);
    }
    let line = line.strip_prefix("error: ").unwrap_or(&line);
    format!("{line} (see --help)")
}
