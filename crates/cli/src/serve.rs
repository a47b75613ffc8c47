//! `fpc serve`: the live page for designers (the `fpc-serve` crate). Glue
//! only: the flags, a warning for a non-loopback address, the URL on
//! stdout, and the browser opened when asked.

use std::io::Write as _;
use std::net::{IpAddr, Ipv4Addr, SocketAddr};

/// Flags of `fpc serve`.
#[derive(clap::Args, Debug)]
pub struct Args {
    /// The port to listen on (0: any free port).
    #[arg(long, default_value_t = 8722, allow_hyphen_values = true)]
    port: u16,
    /// The address to listen on. Anything but a loopback address lets
    /// other machines run solves on this one.
    #[arg(long, default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    bind: IpAddr,
    /// Open the page in the default browser.
    #[arg(long)]
    open: bool,
}

pub fn run(args: &Args) -> anyhow::Result<()> {
    if !args.bind.is_loopback() {
        crate::report::warning(&format!(
            "--bind {}: not a loopback address; anyone who can reach it can use this server (it has no authentication)",
            args.bind
        ));
    }
    let open = args.open;
    fpc_serve::run(SocketAddr::new(args.bind, args.port), move |addr| {
        let url = format!("http://{addr}/");
        let mut out = crate::output::stdout();
        let shown = writeln!(out, "fpc serve: the page is at {url} (Ctrl-C stops)")
            .and_then(|()| out.flush());
        if let Err(e) = shown {
            crate::report::warning(&format!("cannot write the address: {e}"));
        }
        if open {
            open_browser(&url);
        }
    })
    .map_err(|e| anyhow::anyhow!("cannot serve on {}:{}: {e}", args.bind, args.port))
}

/// Opens `url` in the system's browser; a failure is a warning.
fn open_browser(url: &str) {
    let (program, pre): (&str, &[&str]) = if cfg!(target_os = "macos") {
        ("open", &[])
    } else if cfg!(windows) {
        ("cmd", &["/C", "start", ""])
    } else {
        ("xdg-open", &[])
    };
    let started = std::process::Command::new(program)
        .args(pre)
        .arg(url)
        .stdin(std::process::Stdio::null())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn();
    if let Err(e) = started {
        crate::report::warning(&format!("--open: cannot start {program}: {e}"));
    }
}
