//! Where a result came from: the command line, fpc's version and the git
//! commit it was built from (`unknown` outside a checkout; `+modified`
//! when built from a working tree with changes). Written into every JSON
//! file and index.html. The program is recorded by name (`fpc`) and the value of
//! `--out` as `<out>` (the directory the file is in), so the files name no
//! path of the machine they were made on.

use serde::Serialize;

/// The provenance of one run.
#[derive(Debug, Clone, Serialize, PartialEq, Eq)]
pub struct Provenance {
    /// The command line, program name first.
    pub command: Vec<String>,
    /// fpc's version.
    pub fpc_version: &'static str,
    /// The git commit of the build.
    pub git_commit: &'static str,
}

impl Provenance {
    /// This run's provenance.
    pub fn now() -> Provenance {
        Provenance {
            command: command(std::env::args_os().map(|a| a.to_string_lossy().into_owned())),
            fpc_version: env!("CARGO_PKG_VERSION"),
            git_commit: env!("FPC_GIT_COMMIT"),
        }
    }

    /// One line for a page footer.
    pub fn line(&self) -> String {
        format!(
            "fpc {} (commit {}): {}",
            self.fpc_version,
            self.git_commit,
            self.command.join(" ")
        )
    }
}

/// The command line as recorded: the program's name, then the arguments with the value
/// of `--out` (`--out DIR` or `--out=DIR`) replaced by `<out>`, control
/// characters escaped.
fn command(args: impl Iterator<Item = String>) -> Vec<String> {
    let mut out = Vec::new();
    let mut redact_next = false;
    for (i, a) in args.enumerate() {
        let a = if i == 0 {
            crate::report::program().to_string()
        } else if redact_next {
            redact_next = false;
            "<out>".to_string()
        } else if a == "--out" {
            redact_next = true;
            a
        } else if a.starts_with("--out=") {
            "--out=<out>".to_string()
        } else {
            a
        };
        out.push(crate::report::sanitize(&a).into_owned());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_command_names_no_path_of_the_machine() {
        let args = [
            "/opt/x/bin/fpc",
            "paper",
            "--out",
            "/srv/r",
            "--strict",
            "--out=/a",
        ];
        let c = command(args.iter().map(|s| s.to_string()));
        assert_eq!(
            c,
            ["fpc", "paper", "--out", "<out>", "--strict", "--out=<out>"]
        );
        let c = command(
            ["fpc", "finger", "--eps0", "0.3\n"]
                .iter()
                .map(|s| s.to_string()),
        );
        assert_eq!(c[3], "0.3\\n");
    }
}
